#include "fluid/valve_flow.hpp"

#include <cmath>
#include <numbers>

namespace mrjam {

Vec3 ValveFlow::unscaled(const Vec3& x) const {
    const double R = valve_.passage_radius(x.z);
    const double r = std::hypot(x.x, x.y);
    if (r >= R) return {};
    const double rb = valve_.bore_radius(), rt = valve_.throat_radius();
    if (profile_ == Profile::source || profile_ == Profile::source_mean_throat) {
        const bool in_throat = x.z >= -0.5 * valve_.throat_length && x.z <= valve_.throat_end_z();
        if (in_throat) return {0, 0, throat_speed_};
        return {0, 0, r <= rt ? speed_ : speed_ * (rb - r) / (rb - rt)};
    }
    if (profile_ == Profile::conserving) return self_similar(x, R, 0.0);
    return self_similar(x, stream_radius(x.z), stream_slope(x.z));
}

// The bore's plug-and-ramp shape on a stream of radius R carrying the bore's flow rate; with a
// slope, the radial velocity that keeps r / R constant along a streamline (div u = 0).
Vec3 ValveFlow::self_similar(const Vec3& x, double R, double slope) const {
    const double r = std::hypot(x.x, x.y);
    if (r >= R) return {};
    const double rb = valve_.bore_radius(), rt = valve_.throat_radius();
    const double ratio = rb / R;
    const double plug = R * rt / rb;
    const double peak = speed_ * ratio * ratio;
    const double u = r <= plug ? peak : peak * (R - r) / (R - plug);
    const double radial = u * slope / R;  // u_r / r
    return {radial * x.x, radial * x.y, u};
}

double jet_stream_radius(const ValveGeometry& valve, double jet_length, double z) {
    const double exit = valve.throat_end_z();
    if (z <= exit || z >= exit + jet_length) return valve.passage_radius(z);
    const double rb = valve.bore_radius(), rt = valve.throat_radius();
    return rt + (z - exit) * (rb - rt) / jet_length;
}

double jet_stream_slope(const ValveGeometry& valve, double jet_length, double z) {
    const double rb = valve.bore_radius(), rt = valve.throat_radius();
    const double exit = valve.throat_end_z();
    if (z > valve.taper_start_z() && z < -0.5 * valve.throat_length) return -(rb - rt) / valve.taper_length;
    if (z > exit && z < exit + jet_length) return (rb - rt) / jet_length;
    return 0.0;
}

double ValveFlow::stream_radius(double z) const {
    return jet_stream_radius(valve_, profile_ == Profile::converging ? jet_length_ : 0.0, z);
}

double ValveFlow::stream_slope(double z) const {
    return jet_stream_slope(valve_, profile_ == Profile::converging ? jet_length_ : 0.0, z);
}

// In the bore: U pi r_t^2 for the plug plus the ramp's integral 2 pi U int (r_b - r)/(r_b - r_t) r dr.
double ValveFlow::reference_flow_rate() const {
    const double rb = valve_.bore_radius(), rt = valve_.throat_radius();
    const double ramp = (rb * rb * rb / 6.0 - rb * rt * rt / 2.0 + rt * rt * rt / 3.0) / (rb - rt);
    return speed_ * std::numbers::pi * (rt * rt + 2.0 * ramp);
}

// Midpoint rule in r on 4000 rings: the profile is piecewise linear, so this is exact to ~1e-7.
double ValveFlow::flow_rate_at(double z) const {
    const double R = valve_.passage_radius(z);  // the stream never leaves the passage
    const int n = 4000;
    double q = 0;
    for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * R / n;
        q += unscaled({r, 0, z}).z * 2.0 * std::numbers::pi * r * (R / n);
    }
    return q;
}

void ValveFlow::set_drag_factors(double z_lo, double dz, std::vector<double> factors) {
    cells_lo_ = z_lo;
    cell_length_ = dz;
    drag_factors_ = std::move(factors);
}

double ValveFlow::drag_factor(const Vec3& x) const {
    if (drag_factors_.empty()) return 1.0;
    const double k = std::floor((x.z - cells_lo_) / cell_length_);
    if (k < 0 || k >= static_cast<double>(drag_factors_.size())) return 1.0;
    return drag_factors_[static_cast<std::size_t>(k)];
}

std::vector<std::string> valve_flow_profile_names() {
    return {"source", "source_mean_throat", "conserving", "converging"};
}

ValveFlow::Profile valve_flow_profile(const std::string& name) {
    if (name == "source_mean_throat") return ValveFlow::Profile::source_mean_throat;
    if (name == "conserving") return ValveFlow::Profile::conserving;
    if (name == "converging") return ValveFlow::Profile::converging;
    return ValveFlow::Profile::source;
}

std::string valve_flow_profile_name(ValveFlow::Profile profile) {
    switch (profile) {
        case ValveFlow::Profile::source_mean_throat:
            return "source_mean_throat";
        case ValveFlow::Profile::conserving:
            return "conserving";
        case ValveFlow::Profile::converging:
            return "converging";
        default:
            return "source";
    }
}

}  // namespace mrjam
