#pragma once
// The carrier flow through a valve's bore and constriction (geometry/valve.hpp frame: axis z).
//
// The source's prescribed profile (section 3.4.4): speed U (0.273 m/s) inside the constriction's
// diameter, falling linearly to zero at the bore wall; "in a volume immediately inside the
// constriction" the speed is raised by the area ratio (r_b / r_t)^2. Two readings of it:
//
//  * `source` (default, the source's own field): the bore profile
//        u_z = U                              for r <= r_t
//        u_z = U (r_b - r) / (r_b - r_t)      for r_t < r <= r_b
//    holds at every axial position, also in the taper (cut off by the cone wall), and the
//    straight throat carries the plug U (r_b / r_t)^2. It does not carry the same flow rate
//    through every section (the taper carries less than the bore, the throat more), but it is
//    what the source's simulation prescribed: grains arriving at the orifice meet the bore's
//    slow flow, and only grains inside the throat are swept at the raised speed.
//  * `source_mean_throat`: the source's field with the throat's plug at the speed that carries
//    the bore's flow rate, U (r_t^2 + 2 I_ramp) / r_t^2 (1.15 / 0.62 / 0.42 m/s at 20x / 30x /
//    40x, against 2.38 / 1.06 / 0.60 for (r_b / r_t)^2 U). The source's area ratio is the mass-
//    conserving speed-up for a plug filling the bore; its bore profile is a plug only inside r_t,
//    so (r_b / r_t)^2 U makes the throat carry 2.07 / 1.70 / 1.41 times the bore's flow. This
//    reading keeps the slow flow at the orifice and drops that excess.
//  * `conserving`: the plug-and-ramp shape scaled with the local radius R(z),
//        u_z = U (r_b / R)^2                         for r <= R r_t / r_b
//        u_z = U (r_b / R)^2 (R - r)/(R - R r_t/r_b) up to the wall r = R,
//    the same flow rate through every section: the fluid accelerates along the taper, so the
//    grains meet the raised speed before the orifice.
//  * `converging`: a flow that satisfies continuity, not only the flow rate. The conserving
//    shape rides on the radius R_f(z) of the stream, with the radial velocity continuity asks
//    of it: streamlines keep r / R_f fixed, so
//        u_r = u_z r R_f'(z) / R_f(z),
//    and div u = 0 exactly (the self-similar shape's axial deceleration is balanced by the
//    inflow). In the taper the stream fills the passage (R_f = R), so the fluid next to the cone
//    runs along it instead of into it. Past the orifice exit the stream re-opens as the taper
//    mirrored (R_f grows from r_t to r_b over `jet_length`, the taper's length by default): at
//    the throat's Reynolds number (~10-30 for this fluid) the expansion is close to reversible
//    Stokes flow, and the fluid in the step's corner outside the stream is at rest. A periodic
//    stretch must end beyond the jet: its seam joins the downstream profile to the upstream one.
//    The two readings above stop the plug at the exit in one step, which piles fine grains up
//    there.
//
// `scale` multiplies either: 1 for the prescribed flow, set by a pressure controller for the
// pressure-driven option.
#include <atomic>
#include <numbers>
#include <string>
#include <vector>

#include "fluid/flow_field.hpp"
#include "geometry/valve.hpp"

namespace mrjam {

class ValveFlow final : public FlowField {
public:
    enum class Profile { source, source_mean_throat, conserving, converging };
    // `jet_length` (converging only): how far past the exit the stream re-opens; 0 for the taper's length.
    ValveFlow(ValveGeometry valve, double bore_speed, Profile profile = Profile::source, double jet_length = 0)
        : valve_(valve),
          speed_(bore_speed),
          profile_(profile),
          jet_length_(jet_length > 0 ? jet_length : valve.taper_length),
          throat_speed_(profile == Profile::source_mean_throat
                            ? reference_flow_rate() / (std::numbers::pi * valve.throat_radius() * valve.throat_radius())
                            : bore_speed * (valve.bore_radius() / valve.throat_radius()) *
                                  (valve.bore_radius() / valve.throat_radius())) {}
    Vec3 velocity(const Vec3& x, double) const override { return unscaled(x) * scale(); }
    Vec3 unscaled(const Vec3& x) const;  // the profile at scale 1
    // Radius of the moving stream at z and its slope dR_f/dz (the passage's radius, except past
    // the exit for `converging`).
    double stream_radius(double z) const;
    double stream_slope(double z) const;
    std::string name() const override { return "valve"; }

    // Volumetric flow rate through the bore at scale 1 (for `conserving` and `converging`, through
    // every section), m^3/s.
    double reference_flow_rate() const;
    // Flow rate through the section at z at scale 1, m^3/s (quadrature of the profile).
    double flow_rate_at(double z) const;
    double scale() const { return scale_.load(std::memory_order_relaxed); }
    void set_scale(double s) { scale_.store(s, std::memory_order_relaxed); }
    const ValveGeometry& valve() const { return valve_; }
    Profile profile() const { return profile_; }
    double jet_length() const { return jet_length_; }

    // Hindered drag per axial cell (lib/jam/axial_resistance.hpp): cell k covers
    // [z_lo + k dz, z_lo + (k+1) dz); outside the grid, or before any is set, the factor is 1.
    // Set between steps only (the force pass reads it).
    void set_drag_factors(double z_lo, double dz, std::vector<double> factors);
    double drag_factor(const Vec3& x) const override;
    const std::vector<double>& drag_factors() const { return drag_factors_; }

private:
    ValveGeometry valve_;
    double speed_;
    Profile profile_;
    double jet_length_;
    double throat_speed_;  // the straight throat's plug in the two source readings
    Vec3 self_similar(const Vec3& x, double R, double slope) const;
    std::atomic<double> scale_{1.0};
    double cells_lo_ = 0, cell_length_ = 0;
    std::vector<double> drag_factors_;
};

// The moving stream's radius at z and its slope dR_f/dz: the passage's (its slope is the
// taper's), except past the orifice exit, where a jet re-opens linearly from the throat's radius
// to the bore's over `jet_length` (0: no jet). The converging profile and the coupled flow
// (fluid/coupled_valve_flow.hpp) ride on it.
double jet_stream_radius(const ValveGeometry& valve, double jet_length, double z);
double jet_stream_slope(const ValveGeometry& valve, double jet_length, double z);

// The profiles' scene names ("source", "source_mean_throat", "conserving", "converging"), both ways, and the list a
// scene's `profile` key is checked against.
std::vector<std::string> valve_flow_profile_names();
ValveFlow::Profile valve_flow_profile(const std::string& name);
std::string valve_flow_profile_name(ValveFlow::Profile profile);

}  // namespace mrjam
