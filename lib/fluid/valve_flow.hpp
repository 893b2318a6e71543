#pragma once
// The carrier flow through a valve's bore and constriction (geometry/valve.hpp frame: axis z).
//
// The source's prescribed profile (section 3.4.4): speed U (0.273 m/s) inside the constriction's
// diameter, falling linearly to zero at the bore wall; inside the constriction the speed is
// raised by the area ratio. mrjam applies it at every axial position with the local radius R(z):
//     u_z = U (r_b / R)^2                       for r <= R r_t / r_b   (the plug)
//     u_z = U (r_b / R)^2 (R - r)/(R - R r_t/r_b) up to the wall r = R,
// which is the source's profile in the bore (R = r_b) and carries the same flow rate through
// every section of the taper and throat (the plug-and-ramp shape scales with R, the speed with
// 1/R^2). `scale` multiplies it: 1 for the prescribed flow, set by a pressure controller for
// the pressure-driven option.
#include <atomic>

#include "fluid/flow_field.hpp"
#include "geometry/valve.hpp"

namespace mrjam {

class ValveFlow final : public FlowField {
public:
    ValveFlow(ValveGeometry valve, double bore_speed) : valve_(valve), speed_(bore_speed) {}
    Vec3 velocity(const Vec3& x, double) const override { return unscaled(x) * scale(); }
    Vec3 unscaled(const Vec3& x) const;  // the profile at scale 1
    std::string name() const override { return "valve"; }

    // Volumetric flow rate at scale 1 (the same through every section), m^3/s.
    double reference_flow_rate() const;
    double scale() const { return scale_.load(std::memory_order_relaxed); }
    void set_scale(double s) { scale_.store(s, std::memory_order_relaxed); }
    const ValveGeometry& valve() const { return valve_; }

private:
    ValveGeometry valve_;
    double speed_;
    std::atomic<double> scale_{1.0};
};

}  // namespace mrjam
