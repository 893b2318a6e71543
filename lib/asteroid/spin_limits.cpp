#include "asteroid/spin_limits.hpp"

#include <cmath>
#include <limits>

#include "core/quadrature.hpp"
#include "gravity/self_gravity.hpp"

namespace mrjam {

std::array<double, 3> ellipsoid_shape_constants(double a, double b, double c) {
    const double abc = a * b * c, scale = a * a;
    std::array<double, 3> out{};
    const double axes[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
        // u = scale (1 / v^2 - 1) maps (0, 1] onto [0, inf) and leaves an integrand that is smooth
        // in v (it vanishes as v^2 at v = 0), so Simpson's rule converges as h^4.
        auto integrand = [&](double v) {
            const double u = scale * (1 / (v * v) - 1), du = 2 * scale / (v * v * v);
            const double delta = std::sqrt((a * a + u) * (b * b + u) * (c * c + u));
            return du / ((axes[i] * axes[i] + u) * delta);
        };
        out[i] = abc * simpson_inside(integrand, 0.0, 1.0, 2000);
    }
    return out;
}

double rigid_sphere_spin_limit(double density) { return std::sqrt(4.0 * M_PI * kNewtonG * density / 3.0); }

namespace {

// sqrt(J2) + s I1 of the averaged stresses at spin w, in units of 2 pi G rho^2 a^2 / 5.
double yield_function(const std::array<double, 3>& A, const std::array<double, 3>& axes, double density, double w,
                      double s) {
    const double g = 2.0 * M_PI * kNewtonG * density * density, a2 = axes[0] * axes[0];
    const double sx = (density * w * w - g * A[0]) * axes[0] * axes[0] / (g * a2);
    const double sy = (density * w * w - g * A[1]) * axes[1] * axes[1] / (g * a2);
    const double sz = -A[2] * axes[2] * axes[2] / a2;
    const double j2 = ((sx - sy) * (sx - sy) + (sy - sz) * (sy - sz) + (sz - sx) * (sz - sx)) / 6.0;
    return std::sqrt(j2) + s * (sx + sy + sz);
}

double dp_slope(double friction_angle) {
    const double sin_phi = std::sin(friction_angle);
    return 2.0 * sin_phi / (std::sqrt(3.0) * (3.0 - sin_phi));
}

}  // namespace

double drucker_prager_spin_limit(double density, const std::array<double, 3>& semi_axes, double friction_angle) {
    const std::array<double, 3> A = ellipsoid_shape_constants(semi_axes[0], semi_axes[1], semi_axes[2]);
    const double s = dp_slope(friction_angle);
    // At rest the body is inside the surface (or on it, at zero friction); spinning carries the
    // stresses out through it once: bisect between rest and twice the rigid sphere's limit.
    double lo = 0, hi = 2 * rigid_sphere_spin_limit(density);
    if (yield_function(A, semi_axes, density, lo, s) > 0) return 0;
    if (yield_function(A, semi_axes, density, hi, s) <= 0) return hi;
    for (int k = 0; k < 100; ++k) {
        const double mid = 0.5 * (lo + hi);
        (yield_function(A, semi_axes, density, mid, s) > 0 ? hi : lo) = mid;
    }
    return 0.5 * (lo + hi);
}

double friction_angle_for_spin(double density, const std::array<double, 3>& semi_axes, double spin) {
    double lo = 0, hi = 0.5 * M_PI;
    if (drucker_prager_spin_limit(density, semi_axes, hi) < spin) return std::numeric_limits<double>::quiet_NaN();
    for (int k = 0; k < 60; ++k) {  // the limit grows with the angle
        const double mid = 0.5 * (lo + hi);
        (drucker_prager_spin_limit(density, semi_axes, mid) < spin ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

}  // namespace mrjam
