// Closed-form field of a uniformly magnetised cuboid (magnetics/cuboid_field.hpp) against the
// exact on-axis formula, the far-field dipole, brute-force quadrature of the surface charge,
// mirror symmetries and the field equations div B = 0, curl B = 0.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <vector>

#include "magnetics/cuboid_field.hpp"
#include "rel_approx.hpp"

using mrjam_test::rel;

using mrjam::Vec3;
using mrjam::magnetics::Cuboid;
using mrjam::magnetics::cuboid_flux_density;

namespace {

constexpr double kPi = std::numbers::pi;

// A 10 x 6 x 4 mm block, deliberately not a cube (a cube's octupole vanishes, which would hide
// the (size/r)^2 far-field correction), off the origin so the centre offset is exercised.
const Vec3 kCentre{0.010, -0.020, 0.005};
const Vec3 kSize{0.010, 0.006, 0.004};

Cuboid block(const Vec3& br) { return Cuboid{kCentre, kSize, br}; }

double rel_diff(const Vec3& a, const Vec3& b) { return mrjam::norm(a - b) / mrjam::norm(b); }

// n-point Gauss-Legendre nodes and weights on [-1, 1]: Newton on P_n from the Chebyshev guess,
// P_n and P_n' by the three-term recurrence (Press et al., Numerical Recipes, sec. 4.6).
struct GaussLegendre {
    std::vector<double> x, w;
    explicit GaussLegendre(int n) : x(n), w(n) {
        for (int i = 0; i < n; ++i) {
            double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
            for (int iter = 0; iter < 100; ++iter) {
                double p0 = 1, p1 = z;
                for (int k = 2; k <= n; ++k) {
                    const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (z * p1 - p0) / (z * z - 1);
                const double step = p1 / dp;
                z -= step;
                if (std::abs(step) < 1e-16) break;
            }
            x[i] = z;
            w[i] = 2 / ((1 - z * z) * dp * dp);
        }
    }
};

// mu0 H of the charge on one face by composite Gauss-Legendre (panels x panels squares, n points
// each way): B = Br_k s / (4 pi) Integral (r - r') / |r - r'|^3 dA over the face at
// x_k = c_k + s h_k. Independent of the closed form: no antiderivatives, no branch choices.
Vec3 face_field_numeric(int k, double s, double br, const Vec3& point, const GaussLegendre& gl, int panels) {
    const int p = (k + 1) % 3, q = (k + 2) % 3;
    const Vec3 half = 0.5 * kSize;
    Vec3 sum{};
    const double dp = 2 * half[p] / panels, dq = 2 * half[q] / panels;
    for (int ip = 0; ip < panels; ++ip)
        for (int iq = 0; iq < panels; ++iq)
            for (std::size_t a = 0; a < gl.x.size(); ++a)
                for (std::size_t b = 0; b < gl.x.size(); ++b) {
                    Vec3 src = kCentre;
                    src[k] += s * half[k];
                    src[p] += -half[p] + dp * (ip + 0.5 * (1 + gl.x[a]));
                    src[q] += -half[q] + dq * (iq + 0.5 * (1 + gl.x[b]));
                    const Vec3 r = point - src;
                    const double r2 = mrjam::norm2(r);
                    sum += (gl.w[a] * gl.w[b] * 0.25 * dp * dq / (r2 * std::sqrt(r2))) * r;
                }
    return (s * br / (4 * kPi)) * sum;
}

Vec3 brute_force(const Vec3& br, const Vec3& point) {
    static const GaussLegendre gl(16);
    Vec3 b{};
    for (int k = 0; k < 3; ++k)
        if (br[k] != 0)
            for (const double s : {1.0, -1.0}) b += face_field_numeric(k, s, br[k], point, gl, 16);
    if (mrjam::magnetics::cuboid_contains(block(br), point)) b += br;
    return b;
}

// Field of a point dipole m = M V at the block centre, written with Br = mu0 M:
// B = Br V / (4 pi r^3) (3 (b.r^) r^ - b)  (the mu0 cancels).
Vec3 dipole_field(const Vec3& br, const Vec3& point) {
    const Vec3 r = point - kCentre;
    const double rn = mrjam::norm(r), volume = kSize.x * kSize.y * kSize.z;
    const Vec3 rhat = r / rn;
    return (volume / (4 * kPi * rn * rn * rn)) * (3 * mrjam::dot(br, rhat) * rhat - br);
}

// Jacobian J[l][m] = dB_l/dx_m by central differences with step h.
std::array<std::array<double, 3>, 3> jacobian(const Cuboid& magnet, const Vec3& x, double h) {
    std::array<std::array<double, 3>, 3> j{};
    for (int m = 0; m < 3; ++m) {
        Vec3 xp = x, xm = x;
        xp[m] += h;
        xm[m] -= h;
        const Vec3 d = (cuboid_flux_density(magnet, xp) - cuboid_flux_density(magnet, xm)) / (2 * h);
        for (int l = 0; l < 3; ++l) j[l][m] = d[l];
    }
    return j;
}

}  // namespace

TEST_SUITE("physics") {
    // On the z axis of a 2a x 2b x 2c block magnetised along z only the two charged faces'
    // solid angles matter: a 2a x 2b rectangle seen along its axis from distance d subtends
    // Omega = 4 atan(ab / (d sqrt(a^2 + b^2 + d^2))) (the four equal corner terms of the
    // rectangle's solid angle, Furlani 2001 sec. 4.3, on its axis), and mu0 H = Br Omega / (4 pi)
    // per face, signed by the face charge and by the side. Hence, outside and (with + Br) inside,
    //   Bz(z) = (Br/pi) [atan(ab / ((z-c) sqrt(a^2+b^2+(z-c)^2)))
    //                  - atan(ab / ((z+c) sqrt(a^2+b^2+(z+c)^2)))]  (+ Br for |z| < c),
    // the formula quoted by magnet vendors for block magnets (e.g. K&J Magnetics' block calculator).
    TEST_CASE("cuboid: on-axis field of a z-magnetised block matches the exact formula") {
        const double br = 1.21, a = 0.5 * kSize.x, b = 0.5 * kSize.y, c = 0.5 * kSize.z;
        const Cuboid magnet = block({0, 0, br});
        auto exact = [&](double z) {
            auto face = [&](double d) { return std::atan(a * b / (d * std::sqrt(a * a + b * b + d * d))); };
            return br / kPi * (face(z - c) - face(z + c)) + (std::abs(z) < c ? br : 0.0);
        };
        double worst = 0;
        for (const double z :
             {-0.2, -0.03, -0.0021, -0.0019, -0.001, 0.0, 0.0005, 0.00199, 0.00201, 0.002001, 0.004, 0.01, 0.05, 0.3}) {
            CAPTURE(z);
            const Vec3 bfield = cuboid_flux_density(magnet, kCentre + Vec3{0, 0, z});
            const double bz = exact(z);
            worst = std::max(worst, std::abs(bfield.z - bz) / std::abs(bz));
            CHECK(std::abs(bfield.z - bz) <= 1e-12 * std::abs(bz));
            CHECK(std::abs(bfield.x) <= 1e-15 * br);
            CHECK(std::abs(bfield.y) <= 1e-15 * br);
        }
        MESSAGE("on-axis worst relative error " << worst);
    }

    // A uniformly magnetised body with inversion symmetry has no quadrupole: the first correction
    // to its dipole field is the octupole, relatively O((size/r)^2). Doubling r must divide the
    // relative error by ~4 (both distances are far enough for higher multipoles to be small).
    TEST_CASE("cuboid: far field tends to the point dipole m = M V with error ~ (size/r)^2") {
        const Vec3 br{0.3, -0.5, 1.1};
        const Cuboid magnet = block(br);
        for (const Vec3 dir : {Vec3{1, 0.7, 0.4}, Vec3{0, 0, 1}, Vec3{-0.2, 1, -0.5}}) {
            const Vec3 rhat = dir / mrjam::norm(dir);
            std::vector<double> errors;
            for (const double r : {0.1, 0.2, 0.4, 3.0}) {  // 10, 20, 40 and 300 block lengths
                const Vec3 x = kCentre + r * rhat;
                errors.push_back(rel_diff(cuboid_flux_density(magnet, x), dipole_field(br, x)));
            }
            CAPTURE(dir.x);
            MESSAGE("dipole relative error at 10, 20, 40, 300 L: " << errors[0] << " " << errors[1] << " " << errors[2]
                                                                   << " " << errors[3]);
            CHECK(errors[0] < 1e-2);
            CHECK(errors[1] / errors[2] == rel(4.0).epsilon(0.05));
            CHECK(errors[0] / errors[1] == rel(4.0).epsilon(0.2));
            // At 300 L the cancellation between corners and faces costs ~3 log10(r/L) ~ 7.5 digits
            // (see the header), still far below the physical (size/r)^2 term, which must scale.
            CHECK(errors[3] * (300.0 / 40) * (300.0 / 40) / errors[2] == rel(1.0).epsilon(0.05));
        }
    }

    // Independent check: integrate the surface charge numerically (no antiderivatives, no branch
    // choices). Points are at least 1 mm from every charged face, and the 16 x 16 panels are
    // 0.6 mm or smaller, so 16-point Gauss-Legendre per panel converges far below 1e-8.
    TEST_CASE("cuboid: closed form matches brute-force quadrature of the surface charge") {
        const Vec3 h = 0.5 * kSize;
        const std::vector<Vec3> offsets = {
            {0.007, 0.004, 0.003}, {-0.003, 0.0045, -0.0035}, {0.0085, -0.001, 0.0},
            {0.0, 0.0, 0.006},     {0.001, -0.001, 0.0005},  // inside
            {0.008, 0.0, h.z},                               // in the plane of the top face, beside it
            {-0.02, 0.015, -0.01},
        };
        double worst = 0;
        for (const Vec3 br : {Vec3{0, 0, 1.2}, Vec3{1.2, 0, 0}, Vec3{0, -1.2, 0}, Vec3{0.4, -0.7, 0.9}})
            for (const Vec3& off : offsets) {
                const Vec3 x = kCentre + off;
                const Vec3 closed = cuboid_flux_density(block(br), x), numeric = brute_force(br, x);
                CAPTURE(off.x);
                CAPTURE(off.y);
                CAPTURE(off.z);
                CAPTURE(br.x);
                const double err = mrjam::norm(closed - numeric) / mrjam::norm(numeric);
                worst = std::max(worst, err);
                CHECK(err < 1e-8);
            }
        MESSAGE("brute-force worst relative difference " << worst);
    }

    // The z-magnetised block's charge is even under x -> -x and y -> -y and odd under z -> -z
    // (about the block centre), so H (hence B) has the matching parities component by component.
    // And an x-magnetised block is a z-magnetised one with the axes relabelled cyclically.
    TEST_CASE("cuboid: mirror symmetries and axis relabelling") {
        const double br = 1.3;
        const Cuboid magnet = block({0, 0, br});
        const std::vector<Vec3> offsets = {{0.003, 0.002, 0.004},
                                           {0.007, -0.001, 0.0015},
                                           {0.002, 0.0035, -0.0005},
                                           {0.0011, 0.0007, 0.0003},
                                           {0.04, 0.03, 0.02}};
        double worst = 0;
        auto expect = [&](double got, double want, double scale) {
            worst = std::max(worst, std::abs(got - want) / scale);
            CHECK(std::abs(got - want) <= 1e-12 * scale);
        };
        for (const Vec3& o : offsets) {
            const Vec3 b0 = cuboid_flux_density(magnet, kCentre + o);
            const double scale = mrjam::norm(b0);
            const Vec3 bx = cuboid_flux_density(magnet, kCentre + Vec3{-o.x, o.y, o.z});
            const Vec3 by = cuboid_flux_density(magnet, kCentre + Vec3{o.x, -o.y, o.z});
            const Vec3 bz = cuboid_flux_density(magnet, kCentre + Vec3{o.x, o.y, -o.z});
            expect(bx.x, -b0.x, scale);
            expect(bx.y, b0.y, scale);
            expect(bx.z, b0.z, scale);
            expect(by.x, b0.x, scale);
            expect(by.y, -b0.y, scale);
            expect(by.z, b0.z, scale);
            expect(bz.x, -b0.x, scale);
            expect(bz.y, -b0.y, scale);
            expect(bz.z, b0.z, scale);

            // Relabel (x, y, z) -> (y, z, x): the z-magnetised block of sizes (sx, sy, sz) becomes
            // an x-magnetised block of sizes (sz, sx, sy); fields and points relabel the same way.
            const Cuboid turned{{0, 0, 0}, {kSize.z, kSize.x, kSize.y}, {br, 0, 0}};
            const Vec3 bt = cuboid_flux_density(turned, {o.z, o.x, o.y});
            expect(bt.x, b0.z, scale);
            expect(bt.y, b0.x, scale);
            expect(bt.z, b0.y, scale);
        }
        MESSAGE("symmetry worst relative deviation " << worst);
    }

    // Outside, B is a gradient of a harmonic potential: div B = 0 and curl B = 0. Inside, B =
    // mu0 H + Br with Br constant, so the same holds away from the faces. With step h the central
    // difference has truncation error ~ h^2 |B'''| ~ (h/d)^2 |J| for a point at distance d from the
    // nearest edge or face, and rounding error ~ eps |B| / h ~ eps (d/h) |J|. h = 1e-4 d makes both
    // ~1e-8 |J| or below (rounding in B itself is a few eps), hence the tolerance 1e-7 |J|.
    TEST_CASE("cuboid: div B = 0 and curl B = 0 by central differences") {
        const Cuboid magnet = block({0.4, -0.7, 0.9});
        const Vec3 h = 0.5 * kSize;
        const std::vector<Vec3> offsets = {{0.007, 0.004, 0.003}, {-0.006, 0.001, -0.004}, {0.0, 0.0, 0.005},
                                           {0.002, -0.0045, 0.0}, {0.02, 0.01, -0.03},     {0.001, 0.0005, -0.0008}};
        double worst_div = 0, worst_curl = 0;
        for (const Vec3& o : offsets) {
            // Distance to the block surface (outside) or to its nearest face (inside).
            Vec3 outside{std::max(std::abs(o.x) - h.x, 0.0), std::max(std::abs(o.y) - h.y, 0.0),
                         std::max(std::abs(o.z) - h.z, 0.0)};
            double d = mrjam::norm(outside);
            if (d == 0) d = std::min({h.x - std::abs(o.x), h.y - std::abs(o.y), h.z - std::abs(o.z)});
            const auto j = jacobian(magnet, kCentre + o, 1e-4 * d);
            double jnorm = 0;
            for (const auto& row : j)
                for (const double v : row) jnorm = std::max(jnorm, std::abs(v));
            const double div = j[0][0] + j[1][1] + j[2][2];
            const double curl =
                std::max({std::abs(j[2][1] - j[1][2]), std::abs(j[0][2] - j[2][0]), std::abs(j[1][0] - j[0][1])});
            worst_div = std::max(worst_div, std::abs(div) / jnorm);
            worst_curl = std::max(worst_curl, curl / jnorm);
            CAPTURE(o.x);
            CAPTURE(o.y);
            CAPTURE(o.z);
            CHECK(std::abs(div) <= 1e-7 * jnorm);
            CHECK(curl <= 1e-7 * jnorm);
        }
        MESSAGE("worst |div B|/|J| " << worst_div << ", worst |curl B|/|J| " << worst_curl);
    }

    // Across a face the normal B is continuous and the tangential H = (B - Br)/mu0 is continuous;
    // a point exactly on a face (not on an edge) is finite and counts as inside.
    TEST_CASE("cuboid: interface conditions at the faces, finite on faces and edge extensions") {
        const Vec3 br{0.4, -0.7, 0.9};
        const Cuboid magnet = block(br);
        const Vec3 h = 0.5 * kSize;
        const double eps = 1e-10;
        struct FacePoint {
            Vec3 offset;
            int axis;
        };
        for (const FacePoint f : {FacePoint{{0.001, 0.0012, h.z}, 2}, FacePoint{{-0.002, 0.001, -h.z}, 2},
                                  FacePoint{{h.x, -0.001, 0.0005}, 0}, FacePoint{{0.003, -h.y, -0.0011}, 1}}) {
            Vec3 n{};
            n[f.axis] = f.offset[f.axis] > 0 ? 1.0 : -1.0;
            const Vec3 on = kCentre + f.offset;
            const Vec3 in = cuboid_flux_density(magnet, on - eps * n), out = cuboid_flux_density(magnet, on + eps * n);
            const Vec3 at = cuboid_flux_density(magnet, on);
            CHECK(mrjam::finite(at));
            CHECK(std::abs(in[f.axis] - out[f.axis]) < 1e-6);  // normal B continuous (~1e-10 m step)
            CHECK(rel_diff(at, in) < 1e-6);                    // the face value is the inside limit
            const Vec3 jump = in - out;                        // = Br tangentially
            for (int k = 0; k < 3; ++k)
                if (k != f.axis) CHECK(std::abs(jump[k] - br[k]) < 1e-6);
        }
        // On the line through an edge but beyond the block: finite and continuous.
        const Vec3 beyond = kCentre + Vec3{h.x + 0.003, h.y, h.z};
        const Vec3 b_line = cuboid_flux_density(magnet, beyond);
        CHECK(mrjam::finite(b_line));
        CHECK(rel_diff(cuboid_flux_density(magnet, beyond + Vec3{0, 1e-12, -1e-12}), b_line) < 1e-8);
        // On an edge itself the field diverges (documented): not finite. Centred at the origin so the
        // point is exactly on the edge (kCentre + h would be off it by a rounding error).
        const Cuboid at_origin{{0, 0, 0}, kSize, br};
        CHECK_FALSE(mrjam::finite(cuboid_flux_density(at_origin, {0.001, h.y, h.z})));
        CHECK_FALSE(mrjam::finite(cuboid_flux_density(at_origin, {h.x, -h.y, -h.z})));  // a corner
    }
}
