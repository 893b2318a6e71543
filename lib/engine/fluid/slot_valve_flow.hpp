#pragma once
// The carrier flow through a valve with a slot orifice (geometry/slot_orifice.hpp). Kept apart
// from fluid/valve_flow.hpp (the circular orifice's profile) on purpose: same idea, other shape.
//
// The source's shape idea, carried over: a plug in the middle of the section and a linear ramp
// to zero at the wall, with the same flow rate through every section. With d the distance from
// a point to the section's boundary (the bore circle and, in the constriction, the sides of the
// cutting rectangle), the profile is
//     u_z = k(z) min(1, d / delta(z)),   delta(z) = (1 - h/R) min(X(z), Y(z), R),
// h the slot's half height (the gap's half), R the bore radius. In the bore this is the source's
// profile: U inside the radius h (the constriction's "diameter" along the field), linear to 0 at
// the wall. k(z) = Q / I(z) keeps the flow rate Q = U I_bore, where I(z) is the section's integral
// of min(1, d/delta). By the coarea formula I = (1/delta) * integral over [0, delta] of A(t) dt, A(t)
// the area of the section shrunk by t (the disc of radius R - t cut by the rectangle X - t, Y - t);
// A is known in closed form, smooth between the values of t where the rectangle's corners cross
// the circle, and integrated by Gauss-Legendre between them (to round-off).
#include <cstdint>

#include "fluid/flow_field.hpp"
#include "geometry/slot_orifice.hpp"

namespace mrjam {

class SlotValveFlow final : public FlowField {
public:
    SlotValveFlow(const SlotOrifice& slot, double bore_speed);
    Vec3 velocity(const Vec3& x, double time) const override;
    std::string name() const override { return "valve (slot)"; }

    double flow_rate() const { return flow_rate_; }  // m^3/s, the same through every section
    double plug_speed(double z) const;               // k(z), the speed of the plug at z
    // The section integral of the profile's shape, I(z) above (m^2).
    double shape_integral(double z) const;

private:
    double ramp_width(double z) const;
    std::uint64_t instance_;
    SlotOrifice slot_;
    double speed_;
    double ramp_fraction_;  // 1 - h/R
    double flow_rate_;
};

}  // namespace mrjam
