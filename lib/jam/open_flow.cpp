#include "jam/open_flow.hpp"

#include <cmath>
#include <numbers>

namespace mrjam {

OpenFlowEstimate open_flow_estimate(const ValveGeometry& v, double mu, double phi, double rho, double pressure) {
    constexpr double phi_max = 0.64, intrinsic = 2.5, discharge = 0.61;
    const double pi = std::numbers::pi;
    OpenFlowEstimate e;
    e.suspension_viscosity = mu * std::pow(1.0 - phi / phi_max, -intrinsic * phi_max);
    const double rb = v.bore_radius(), rt = v.throat_radius();
    const double bore_length = v.upstream_length + v.downstream_length - v.taper_length - v.throat_length;
    const double a = 8.0 * e.suspension_viscosity *
                     (bore_length / std::pow(rb, 4) + (v.throat_length + v.taper_length) / std::pow(rt, 4)) / pi;
    const double area = pi * rt * rt;
    const double b = rho / (2.0 * discharge * discharge * area * area);
    e.flow_rate = (-a + std::sqrt(a * a + 4.0 * b * pressure)) / (2.0 * b);
    e.throat_speed = e.flow_rate / area;
    e.reynolds_throat = rho * e.throat_speed * 2.0 * rt / e.suspension_viscosity;
    return e;
}

}  // namespace mrjam
