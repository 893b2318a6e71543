#pragma once
// Stokes drag against the carrier flow (eq. 2.3): F = -6 pi mu R (v - v_f) f_h, with the flow's
// velocity v_f and hindered-drag factor f_h at the grain. The lookup of (v_f, f_h) may be held
// for `lookup_interval` steps (scene: fluid/lookup_interval): a grain moves a few nanometres a
// step against flow features microns wide, while the lookup (grid search, interpolation) was a
// tenth of the 10 um valve's step (docs/notes/jam_measurements.md, "Held carrier-flow lookups",
// measures both). The drag itself uses the grain's velocity of every step.
#include <vector>

#include "fluid/flow_field.hpp"
#include "force_term.hpp"

namespace mrjam {

class DragTerm final : public ForceTerm {
public:
    DragTerm(double viscosity, int lookup_interval);

    std::string name() const override { return "drag"; }
    std::unique_ptr<ForceTerm> clone() const override { return std::make_unique<DragTerm>(*this); }
    bool per_grain() const override { return true; }
    void begin_pass(const System& s) override;
    void add_per_grain(const System& s, Vec3* force, std::size_t begin, std::size_t end) override;
    void end_pass() override;
    void save(const System&, std::ostream& out) const override;
    void load(System&, std::istream& in) override;
    void grains_removed(System&, const std::vector<std::int64_t>& index, std::size_t kept) override;
    void summarise(const System&, nlohmann::json& summary) const override;

    double viscosity() const { return viscosity_ * share_; }
    // A protocol may run the carrier at a share of its viscosity for a while (the jam mode's
    // fast-forwarded closed period); the scene's viscosity stays the reference.
    void set_viscosity_share(double share) { share_ = share; }
    double viscosity_share() const { return share_; }
    const HoldSchedule& lookups() const { return hold_; }
    // The flow at each grain from the last lookup (empty when none is held).
    const std::vector<FlowField::Drag>& held_lookups() const { return held_; }

private:
    enum class Lookup { fresh, fresh_and_hold, held };
    double viscosity_;
    double share_ = 1.0;
    HoldSchedule hold_;
    std::vector<FlowField::Drag> held_;
    Lookup lookup_ = Lookup::fresh;
};

// The carrier fluid's viscosity (Pa s) of a system with drag; 0 without.
double carrier_viscosity(const System& s);

}  // namespace mrjam
