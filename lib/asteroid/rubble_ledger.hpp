#pragma once
// The books of a rubble-pile run: the grains that pass the escape radius are taken out, and the
// mass, momentum and angular momentum they carry away are kept, so the conservation checks of the
// grains still present close (momentum to round-off with pairwise forces, angular momentum to the
// held forces' error).
#include <cstddef>
#include <nlohmann/json.hpp>

#include "core/vec3.hpp"
#include "system.hpp"

namespace mrjam {

class RubbleLedger {
public:
    // At the start: the grains' mass, momenta and the scale momentum drift is measured against.
    void open(const System& s, double escape_radius, double cloud_radius);
    // Angular momentum given to the grains on purpose (a spin-up step): added to the books.
    void inject_angular_momentum(const Vec3& l) { initial_angular_ += l; }
    // Takes out every grain farther than the escape radius from the origin; returns how many.
    std::size_t remove_escaped(System& s);
    // Momentum drift (|Delta P| over the larger of sum m |v| now and at the start), angular momentum
    // drift (|Delta L| over the larger of |L0| and sum m |r x v| + I |omega| now), kinetic and
    // gravitational energy.
    nlohmann::json conservation(const System& s) const;

    double initial_mass() const { return initial_mass_; }
    double escaped_mass() const { return escaped_mass_; }
    std::size_t escaped() const { return escaped_; }

    nlohmann::json to_json() const;
    static RubbleLedger from_json(const nlohmann::json& j);

private:
    double escape_radius_ = 0, initial_mass_ = 0, momentum_scale_ = 0, escaped_mass_ = 0;
    Vec3 initial_linear_, initial_angular_, removed_linear_, removed_angular_;
    std::size_t escaped_ = 0;
};

}  // namespace mrjam
