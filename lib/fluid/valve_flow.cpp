#include "fluid/valve_flow.hpp"

#include <cmath>
#include <numbers>

namespace mrjam {

Vec3 ValveFlow::unscaled(const Vec3& x) const {
    const double R = valve_.passage_radius(x.z);
    const double r = std::hypot(x.x, x.y);
    if (r >= R) return {};
    const double ratio = valve_.bore_radius() / R;
    const double plug = R * valve_.throat_radius() / valve_.bore_radius();
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

}  // namespace mrjam
