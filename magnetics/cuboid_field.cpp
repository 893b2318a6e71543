#include "magnetics/cuboid_field.hpp"

#include <cmath>
#include <initializer_list>
#include <numbers>

// Derivation (see the header for the sources). A rectangle u' in [p1, p2], v' in [q1, q2] in the
// plane w' = w0 with charge density sigma gives, at a point with offsets u = x_p - u',
// v = x_q - v', w = x_k - w0 from a charge element and R = |(u, v, w)|,
//     H = sigma / (4 pi) * Integral (u, v, w) / R^3 du' dv'.
// Integrating each component over one variable in closed form and then the other:
//     H_p: Int u/R^3 du = -1/R, then Int dv/sqrt(v^2 + rho^2), rho^2 = u^2 + w^2  -> log_span below
//     H_q: the same with u and v exchanged
//     H_k: the solid angle, sum over corners (-1)^(i+j) atan(u_i v_j / (w R_ij))
// With u_1 = x_p - p1 > u_2 = x_p - p2 (and likewise v), the corner sums are
//     G_p = L(v_2, v_1; rho(u_2)) - L(v_2, v_1; rho(u_1))
//     G_q = L(u_2, u_1; rho(v_2)) - L(u_2, u_1; rho(v_1))
//     G_k = sum_ij (-1)^(i+j) atan(u_i v_j / (w R_ij))
// where L(a, b; rho) = Integral_a^b dt / sqrt(t^2 + rho^2) = asinh(b/rho) - asinh(a/rho), and
// mu0 H = Br_k / (4 pi) * (+-1) * G for the face with charge +-M_k.

namespace mrjam::magnetics {
namespace {

constexpr double kPi = std::numbers::pi;

// L(a, b; rho) = Integral_a^b dt / sqrt(t^2 + rho^2) for a <= b, evaluated without the
// cancellations of the textbook log(b + R_b) - log(a + R_a):
//  * for t < 0, log(t + R) cancels catastrophically (t + R -> rho^2 / 2|t|); the integrand is
//    even, so an interval on the negative side is mirrored to the positive side;
//  * on the positive side the ratio (b + R_b)/(a + R_a) is 1 + (b - a)(1 + (a + b)/(R_a + R_b))
//    / (a + R_a) exactly, so log1p keeps full precision when the interval is short compared
//    with the distance (the far field);
//  * an interval straddling t = 0 is split there: asinh(b/rho) + asinh(|a|/rho).
// rho = 0 is the limit of a point on the line through a face's rim: finite if the interval does
// not contain 0 (the extension of an edge), +inf if it does (the point is on the edge itself).
double log_span(double a, double b, double rho) {
    if (b <= 0) return log_span(-b, -a, rho);
    if (a < 0) return std::asinh(b / rho) + std::asinh(-a / rho);
    const double ra = std::hypot(a, rho), rb = std::hypot(b, rho);
    return std::log1p((b - a) * (1.0 + (a + b) / (ra + rb)) / (a + ra));
}

// One corner's solid-angle term atan(u v / (w R)). In the face's own plane (w = 0) the term is
// the one-sided limit (pi/2) sign(u v) sign(w), taken from the side `w_side` the caller chooses.
double corner_angle(double u, double v, double w, double w_side) {
    if (w == 0) {
        const double uv = u * v;
        return uv == 0 ? 0.0 : std::copysign(kPi / 2, uv) * std::copysign(1.0, w_side);
    }
    return std::atan(u * v / (w * std::sqrt(u * u + v * v + w * w)));
}

struct FaceTerms {
    double gp, gq, gk;  // the corner sums G_p, G_q, G_k above (dimensionless)
};

// Corner sums for a rectangle spanning u' in [-hp, hp], v' in [-hq, hq] (relative to the block
// centre) at the point whose offsets from the block centre are (dp, dq) and whose offset from
// the face plane is w. `w_side` picks the one-sided limit when the point lies in the plane.
FaceTerms face_terms(double dp, double dq, double w, double hp, double hq, double w_side) {
    const double u1 = dp + hp, u2 = dp - hp, v1 = dq + hq, v2 = dq - hq;
    FaceTerms t{};
    t.gp = log_span(v2, v1, std::hypot(u2, w)) - log_span(v2, v1, std::hypot(u1, w));
    t.gq = log_span(u2, u1, std::hypot(v2, w)) - log_span(u2, u1, std::hypot(v1, w));
    t.gk = corner_angle(u1, v1, w, w_side) - corner_angle(u1, v2, w, w_side) - corner_angle(u2, v1, w, w_side) +
           corner_angle(u2, v2, w, w_side);
    return t;
}

// mu0 H of the block magnetised along axis k alone, with remanence br (tesla); d = point - centre.
Vec3 axis_field(int k, double br, const Vec3& d, const Vec3& half) {
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    Vec3 b{};
    for (const double s : {1.0, -1.0}) {  // face at +h_k carries +M_k, the one at -h_k carries -M_k
        const double w = d[k] - s * half[k];
        // In the face plane, take the limit from inside the block (-s side): a face point counts
        // as inside, so with Br added it gives the same B as the limit from outside.
        const FaceTerms t = face_terms(d[p], d[q], w, half[p], half[q], -s);
        const double scale = s * br / (4 * kPi);
        b[p] += scale * t.gp;
        b[q] += scale * t.gq;
        b[k] += scale * t.gk;
    }
    return b;
}

}  // namespace

bool cuboid_contains(const Cuboid& magnet, const Vec3& point) {
    const Vec3 d = point - magnet.centre;
    for (int k = 0; k < 3; ++k)
        if (!(std::abs(d[k]) <= 0.5 * magnet.size[k])) return false;
    return true;
}

Vec3 cuboid_flux_density(const Cuboid& magnet, const Vec3& point) {
    const Vec3 d = point - magnet.centre;
    const Vec3 half = 0.5 * magnet.size;
    Vec3 b{};
    for (int k = 0; k < 3; ++k)
        if (magnet.remanence_T[k] != 0) b += axis_field(k, magnet.remanence_T[k], d, half);
    if (cuboid_contains(magnet, point)) b += magnet.remanence_T;  // B = mu0 (H + M) inside
    return b;
}

}  // namespace mrjam::magnetics
