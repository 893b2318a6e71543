#include "fluid/brinkman_slice.hpp"

#include <cmath>
#include <numbers>

namespace mrjam {

std::vector<double> brinkman_profile(const BrinkmanRings& rings, double pressure_gradient) {
    const std::size_t n = rings.beta.size();
    const double dr = rings.radius / static_cast<double>(n);
    const double mu = rings.viscosity;
    // Ring j: mu/(r_j dr^2) [r_{j+1/2}(u_j - u_{j+1}) + r_{j-1/2}(u_j - u_{j-1})] + beta_j u_j
    //       = G + beta_j v_j, with r_{-1/2} = 0 (axis) and the wall's u = 0 half a ring past the last centre.
    std::vector<double> lower(n, 0.0), diag(n, 0.0), upper(n, 0.0), rhs(n, 0.0);
    for (std::size_t j = 0; j < n; ++j) {
        const double rc = (static_cast<double>(j) + 0.5) * dr;
        const double inner = static_cast<double>(j) * dr, outer = static_cast<double>(j + 1) * dr;
        const double k = mu / (rc * dr * dr);
        const double outer_coupling = j + 1 < n ? k * outer : 2.0 * k * outer;  // to the wall over dr / 2
        diag[j] = k * inner + outer_coupling + rings.beta[j];
        if (j > 0) lower[j] = -k * inner;
        if (j + 1 < n) upper[j] = -k * outer;
        rhs[j] = pressure_gradient + rings.beta[j] * rings.grain_speed[j];
    }
    for (std::size_t j = 1; j < n; ++j) {
        const double m = lower[j] / diag[j - 1];
        diag[j] -= m * upper[j - 1];
        rhs[j] -= m * rhs[j - 1];
    }
    std::vector<double> u(n, 0.0);
    for (std::size_t j = n; j-- > 0;) u[j] = (rhs[j] - (j + 1 < n ? upper[j] * u[j + 1] : 0.0)) / diag[j];
    return u;
}

double ring_flow_rate(const std::vector<double>& u, double radius) {
    const double dr = radius / static_cast<double>(u.size());
    double q = 0;
    for (std::size_t j = 0; j < u.size(); ++j)
        q += 2.0 * std::numbers::pi * (static_cast<double>(j) + 0.5) * dr * dr * u[j];
    return q;
}

}  // namespace mrjam
