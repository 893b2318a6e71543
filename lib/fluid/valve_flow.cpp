#include "fluid/valve_flow.hpp"

#include <cmath>
#include <numbers>

namespace mrjam {

Vec3 ValveFlow::unscaled(const Vec3& x) const {
    const double R = valve_.passage_radius(x.z);
    const double r = std::hypot(x.x, x.y);
    if (r >= R) return {};
    const double rb = valve_.bore_radius(), rt = valve_.throat_radius();
    if (profile_ == Profile::source) {
        const bool in_throat = x.z >= -0.5 * valve_.throat_length && x.z <= valve_.throat_end_z();
        if (in_throat) return {0, 0, speed_ * (rb / rt) * (rb / rt)};
        return {0, 0, r <= rt ? speed_ : speed_ * (rb - r) / (rb - rt)};
    }
    const double ratio = rb / R;
    const double plug = R * rt / rb;
    const double peak = speed_ * ratio * ratio;
    const double u = r <= plug ? peak : peak * (R - r) / (R - plug);
    return {0, 0, u};
}

// In the bore: U pi r_t^2 for the plug plus the ramp's integral 2 pi U int (r_b - r)/(r_b - r_t) r dr.
double ValveFlow::reference_flow_rate() const {
    const double rb = valve_.bore_radius(), rt = valve_.throat_radius();
    const double ramp = (rb * rb * rb / 6.0 - rb * rt * rt / 2.0 + rt * rt * rt / 3.0) / (rb - rt);
    return speed_ * std::numbers::pi * (rt * rt + 2.0 * ramp);
}

// Midpoint rule in r on 4000 rings: the profile is piecewise linear, so this is exact to ~1e-7.
double ValveFlow::flow_rate_at(double z) const {
    const double R = valve_.passage_radius(z);
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

}  // namespace mrjam
