#include "geometry/slot_orifice.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mrjam {

namespace {
// Area of the disc's cap beyond the chord at distance a from the centre (0 <= a <= R).
double cap_area(double R, double a) { return R * R * std::acos(a / R) - a * std::sqrt(R * R - a * a); }

// An antiderivative of cap_area in a: R^2 (a acos(a/R) - sqrt(R^2-a^2)) + (R^2-a^2)^{3/2}/3.
double cap_area_integral(double R, double a) {
    const double w = std::max(0.0, R * R - a * a);
    return R * R * (a * std::acos(std::min(1.0, a / R)) - std::sqrt(w)) + w * std::sqrt(w) / 3.0;
}
}  // namespace

double SlotOrifice::half_size(double z, double slot_half) const {
    if (z < taper_start_z || z > exit_z) return unbounded;
    if (z >= throat_start_z) return slot_half;
    const double s = (throat_start_z - z) / (throat_start_z - taper_start_z);  // 0 at the slot, 1 at the bore
    return slot_half + s * (bore_radius - slot_half);
}

bool SlotOrifice::contains(const Vec3& p) const {
    return p.x * p.x + p.y * p.y < bore_radius * bore_radius && std::abs(p.x) < half_x(p.z) &&
           std::abs(p.y) < half_y(p.z);
}

double SlotOrifice::disc_rectangle_area(double R, double X, double Y) {
    if (!(R > 0 && X > 0 && Y > 0)) return 0.0;
    X = std::min(X, R);
    Y = std::min(Y, R);
    if (X * X + Y * Y <= R * R) return 4.0 * X * Y;  // the rectangle lies inside the disc
    // Otherwise the strips |x| > X and |y| > Y cut two caps each from the disc, and they do not
    // overlap inside it (the rectangle's corners lie outside the disc).
    return std::numbers::pi * R * R - 2.0 * cap_area(R, X) - 2.0 * cap_area(R, Y);
}

double SlotOrifice::section_area(double z) const { return disc_rectangle_area(bore_radius, half_x(z), half_y(z)); }

// The straight slot is a box; the taper is integrated in closed form in s (0 at the slot, 1 at
// the bore), where X = hw + (R - hw) s and Y = hh + (R - hh) s: while the rectangle's corners
// are inside the disc (s < s*) the section is 4XY, a polynomial; beyond, it is the disc minus
// four caps, each with the antiderivative above.
double SlotOrifice::constriction_volume() const {
    const double R = bore_radius, hw = half_width, hh = half_height;
    const double straight = 4.0 * hw * hh * (exit_z - throat_start_z);
    const double L = throat_start_z - taper_start_z;
    if (L <= 0) return straight;
    const double aw = R - hw, ah = R - hh;
    // Corners on the circle: (hw + aw s)^2 + (hh + ah s)^2 = R^2; the constant term is negative
    // (the slot fits the bore), so there is exactly one positive root, below 1.
    const double qa = aw * aw + ah * ah, qb = 2.0 * (hw * aw + hh * ah), qc = hw * hw + hh * hh - R * R;
    const double s_star = (-qb + std::sqrt(qb * qb - 4.0 * qa * qc)) / (2.0 * qa);
    auto inside = [&](double s) {
        return 4.0 * (hw * hh * s + 0.5 * (hw * ah + hh * aw) * s * s + aw * ah * s * s * s / 3.0);
    };
    const double corners_in = inside(s_star);
    const double corners_out = std::numbers::pi * R * R * (1.0 - s_star) -
                               2.0 / aw * (cap_area_integral(R, R) - cap_area_integral(R, hw + aw * s_star)) -
                               2.0 / ah * (cap_area_integral(R, R) - cap_area_integral(R, hh + ah * s_star));
    return straight + L * (corners_in + corners_out);
}

}  // namespace mrjam
