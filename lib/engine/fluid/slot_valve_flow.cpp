#include "fluid/slot_valve_flow.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace mrjam {

namespace {
std::atomic<std::uint64_t> instances{0};

// 8-point Gauss-Legendre on [-1, 1]: exact for polynomials of degree 15; A(t) is analytic between
// the corner crossings, so a piece is integrated to round-off.
constexpr std::array<double, 4> gl_x{0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> gl_w{0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

template <class F>
double gauss_legendre(F f, double a, double b) {
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    double sum = 0;
    for (std::size_t i = 0; i < gl_x.size(); ++i) sum += gl_w[i] * (f(mid - half * gl_x[i]) + f(mid + half * gl_x[i]));
    return sum * half;
}
}  // namespace

SlotValveFlow::SlotValveFlow(const SlotOrifice& slot, double bore_speed)
    : instance_(++instances),
      slot_(slot),
      speed_(bore_speed),
      ramp_fraction_(1.0 - slot.half_height / slot.bore_radius) {
    flow_rate_ = speed_ * shape_integral(slot_.taper_start_z - 1.0);  // any z in the bore
}

double SlotValveFlow::ramp_width(double z) const {
    return ramp_fraction_ * std::min({slot_.half_x(z), slot_.half_y(z), slot_.bore_radius});
}

double SlotValveFlow::shape_integral(double z) const {
    const double R = slot_.bore_radius;
    const double X = std::min(slot_.half_x(z), R), Y = std::min(slot_.half_y(z), R);
    const double delta = ramp_width(z);
    if (X >= R && Y >= R)  // the bore: (pi / 3 delta) (R^3 - (R - delta)^3)
        return std::numbers::pi * (R * R * R - std::pow(R - delta, 3)) / (3.0 * delta);
    auto area = [&](double t) { return SlotOrifice::disc_rectangle_area(R - t, X - t, Y - t); };
    // Where the shrunk rectangle's corners cross the shrunk circle:
    // (X - t)^2 + (Y - t)^2 = (R - t)^2, i.e. t^2 - 2 b t + c = 0.
    std::vector<double> cuts{0.0};
    const double b = X + Y - R, c = X * X + Y * Y - R * R, disc = b * b - c;
    if (disc > 0)
        for (double t : {b - std::sqrt(disc), b + std::sqrt(disc)})
            if (t > 0 && t < delta) cuts.push_back(t);
    cuts.push_back(delta);
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) sum += gauss_legendre(area, cuts[i], cuts[i + 1]);
    return sum / delta;
}

double SlotValveFlow::plug_speed(double z) const {
    if (z < slot_.taper_start_z || z > slot_.exit_z) return speed_;
    // Calls at one z in a row (a quadrature over a section) reuse k; per thread, so the drag
    // loop's threads never share it.
    // Keyed by an instance number, not the address, which a later flow may reuse.
    thread_local std::uint64_t owner = 0;
    thread_local double last_z = 0, last_k = 0;
    if (owner != instance_ || last_z != z) {
        owner = instance_;
        last_z = z;
        last_k = flow_rate_ / shape_integral(z);
    }
    return last_k;
}

Vec3 SlotValveFlow::velocity(const Vec3& x, double) const {
    if (!slot_.contains(x)) return {};
    const double d = std::min({slot_.bore_radius - std::hypot(x.x, x.y), slot_.half_x(x.z) - std::abs(x.x),
                               slot_.half_y(x.z) - std::abs(x.y)});
    return {0, 0, plug_speed(x.z) * std::min(1.0, d / ramp_width(x.z))};
}

}  // namespace mrjam
