#pragma once
// Gravity with buoyancy: F = (m - rho_f V) g on every grain (the carrier fluid's density rho_f;
// 0 without a fluid).
#include "force_term.hpp"

namespace mrjam {

class GravityTerm final : public ForceTerm {
public:
    GravityTerm(const Vec3& acceleration, double fluid_density)
        : acceleration_(acceleration), fluid_density_(fluid_density) {}

    std::string name() const override { return "gravity"; }
    std::unique_ptr<ForceTerm> clone() const override { return std::make_unique<GravityTerm>(*this); }
    bool per_grain() const override { return true; }
    void add_per_grain(const System& s, Vec3* force, std::size_t begin, std::size_t end) override;

    // The grains' potential energy, -sum (m - rho_f V) g . x (J).
    double potential_energy(const System& s) const;
    const Vec3& acceleration() const { return acceleration_; }

private:
    double effective_mass(double mass, double radius) const;
    Vec3 acceleration_;
    double fluid_density_;
};

}  // namespace mrjam
