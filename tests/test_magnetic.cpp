// Magnetic forces (lib/magnetic): induced dipoles by the mutual dipole method, the saturation cap,
// permanent dipoles with torque, and the applied field with its gradient force.
//
//  1. Two touching spheres: the converged mutual-dipole force over the fixed-dipole force is
//     1/(1 - beta/4)^2 along the field and 1/(1 + beta/8)^2 across it (16/9 and 64/81 as
//     mu_r -> infinity, the +77.78 % / -20.99 % the source quotes); the fixed-dipole force itself
//     against the closed form, with the right signs.
//  2. The "L" of Table 4.3: forces after k mutual-dipole iterations against 1000 iterations and
//     against a direct solve of the linear system.
//  3. The gradient force of a FieldMap against a finite difference of m . B_ext; the map's
//     write/read round trip and its trilinear interpolation of a linear field.
//  4. Permanent dipoles: torque m x B in a uniform field and no force; a pair's forces and torques
//     against independent formulas, action-reaction and zero total torque; a free pair integrated
//     with prepare/advance conserving linear and angular momentum to round-off.
//  5. Chains: a suspension of iron grains at volume fraction 0.3 in a field along z, run through
//     the scene path, develops contacts aligned with the field.
//  6. Saturation: the induced moment is capped at M_s V.
//  7. A magnet switched off: soft grains lose their moments at once and the pass is skipped;
//     a permanent dipole still polarises and pulls its neighbour.
//  8. Forces held over k steps (update_interval): two grains' approach against an RK4 reference,
//     late by less than the lag and in proportion to k - 1.
// Set MRJAM_TEST_VERBOSE=1 to print the measured figures.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "integrator.hpp"
#include "magnetic/external_field.hpp"
#include "magnetic/magnetic_model.hpp"
#include "observers.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/magnetic_term.hpp"
#include "test_support.hpp"

using mrjam_test::rel;

namespace {

using namespace mrjam;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = 2.220446049250313e-16;

void report(const std::string& text) {
    if (std::getenv("MRJAM_TEST_VERBOSE")) MESSAGE(text);
}

std::string str(double v, int precision = 6) {
    std::ostringstream s;
    s.precision(precision);
    s << v;
    return s.str();
}

double beta_of(double mu_r) { return (mu_r - 1.0) / (mu_r + 2.0); }
double induced_coefficient(double radius, double mu_r) { return 4.0 * kPi * radius * radius * radius * beta_of(mu_r); }

// ---------------------------------------------------------------------------------------------
// Independent textbook formulas (written here, not taken from the engine).

// H at a point displaced by d from a dipole m: (3 dhat (m . dhat) - m) / (4 pi r^3).
Vec3 dipole_h(const Vec3& m, const Vec3& d) {
    const double r = norm(d);
    const Vec3 u = d / r;
    return (u * (3.0 * dot(m, u)) - m) / (4.0 * kPi * r * r * r);
}

// Force on dipole a at x_a from dipole b at x_b, d = x_a - x_b: grad_a (mu0 m_a . H_b(x_a)).
Vec3 dipole_force(const Vec3& ma, const Vec3& mb, const Vec3& d) {
    const double r = norm(d);
    const Vec3 u = d / r;
    const double a = dot(ma, u), b = dot(mb, u);
    return (mb * a + ma * b + u * (dot(ma, mb) - 5.0 * a * b)) * (3.0 * kMu0 / (4.0 * kPi * r * r * r * r));
}

Quaternion random_orientation(std::mt19937_64& rng) {
    std::normal_distribution<double> g;
    Quaternion q{g(rng), g(rng), g(rng), g(rng)};
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q.w /= n;
    q.x /= n;
    q.y /= n;
    q.z /= n;
    return q;
}

// ---------------------------------------------------------------------------------------------
// A handful of grains and a magnetic model driven directly (no scene, no integrator).
struct Rig {
    Particles p;
    MagneticModel model;
    Domain domain;

    Rig(std::shared_ptr<ExternalField> field, MutualPolicy policy, double cutoff_scale = 3.0) {
        model.enabled = true;
        model.field = std::move(field);
        model.settings.policy = policy;
        model.settings.cutoff_scale = cutoff_scale;
        domain.lo = {-0.1, -0.1, -0.1};
        domain.hi = {0.1, 0.1, 0.1};
    }
    Rig(Vec3 b, MutualPolicy policy, double cutoff_scale = 3.0)
        : Rig(std::make_shared<UniformField>(b, 0.0, 0.0, 1e300), policy, cutoff_scale) {}

    // A soft grain (linear up to a saturation far out of reach unless given).
    std::size_t add(const Vec3& x, double radius, double mu_r, double saturation_moment = 1e100) {
        const std::size_t i = p.add(x, radius, 7800.0, 0);
        p.induced_coefficient[i] = induced_coefficient(radius, mu_r);
        p.saturation_moment[i] = saturation_moment;
        return i;
    }
    // A grain with a permanent moment (body frame) and no induced part (mu_r = 1).
    std::size_t add_permanent(const Vec3& x, double radius, const Vec3& moment, const Quaternion& q) {
        const std::size_t i = add(x, radius, 1.0);
        p.permanent_moment[i] = moment;
        p.orientation[i] = q;
        return i;
    }

    // Lists the pairs, clears forces and torques, sets the moments from the applied field and
    // adds the magnetic forces once.
    void evaluate(int threads = 1) {
        model.pairs =
            NeighborList(NeighborList::Settings{0.0, model.settings.cutoff_scale, false, model.settings.cutoff_extra});
        model.pairs.build(p, domain, threads);
        model.any_permanent = false;
        for (const Vec3& m : p.permanent_moment) model.any_permanent |= norm2(m) > 0;
        for (auto& f : p.force) f = Vec3{};
        for (auto& t : p.torque) t = Vec3{};
        initialise_moments(model, p, 0.0);
        add_magnetic_forces(model, p, 0.0, threads);
    }
};

// Dense linear solve by Gaussian elimination with partial pivoting (small systems only).
std::vector<double> solve(std::vector<std::vector<double>> a, std::vector<double> b) {
    const std::size_t n = b.size();
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t piv = c;
        for (std::size_t r = c + 1; r < n; ++r)
            if (std::fabs(a[r][c]) > std::fabs(a[piv][c])) piv = r;
        std::swap(a[c], a[piv]);
        std::swap(b[c], b[piv]);
        for (std::size_t r = c + 1; r < n; ++r) {
            const double f = a[r][c] / a[c][c];
            for (std::size_t k = c; k < n; ++k) a[r][k] -= f * a[c][k];
            b[r] -= f * b[c];
        }
    }
    std::vector<double> x(n);
    for (std::size_t r = n; r-- > 0;) {
        double s = b[r];
        for (std::size_t k = r + 1; k < n; ++k) s -= a[r][k] * x[k];
        x[r] = s / a[r][r];
    }
    return x;
}

// The mutual-dipole system of grains with equal coefficient C in a uniform field H0:
// m_i = C (H0 + sum_j T_ij m_j). T is the 3n x 3n dipole-field matrix (symmetric).
std::vector<std::vector<double>> dipole_matrix(const std::vector<Vec3>& x) {
    const std::size_t n = x.size();
    std::vector<std::vector<double>> t(3 * n, std::vector<double>(3 * n, 0.0));
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (i == j) continue;
            for (int c = 0; c < 3; ++c) {
                Vec3 e{};
                e[c] = 1.0;
                const Vec3 h = dipole_h(e, x[i] - x[j]);  // field at i of a unit dipole at j along c
                for (int r = 0; r < 3; ++r) t[3 * i + r][3 * j + c] = h[r];
            }
        }
    return t;
}

// The converged moments by a direct solve of (I - C T) m = C H0, H0 along z, for the dipole-field
// matrix T of dipole_matrix.
std::vector<Vec3> direct_moments(const std::vector<std::vector<double>>& t, double C, double h0) {
    const std::size_t n3 = t.size();
    std::vector<std::vector<double>> a(n3, std::vector<double>(n3));
    std::vector<double> rhs(n3);
    for (std::size_t r = 0; r < n3; ++r) {
        for (std::size_t c = 0; c < n3; ++c) a[r][c] = (r == c ? 1.0 : 0.0) - C * t[r][c];
        rhs[r] = r % 3 == 2 ? C * h0 : 0.0;
    }
    const std::vector<double> sol = solve(a, rhs);
    std::vector<Vec3> m(n3 / 3);
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = {sol[3 * i], sol[3 * i + 1], sol[3 * i + 2]};
    return m;
}

std::vector<Vec3> forces_of(const std::vector<Vec3>& x, const std::vector<Vec3>& m) {
    std::vector<Vec3> f(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
        for (std::size_t j = 0; j < x.size(); ++j)
            if (i != j) f[i] += dipole_force(m[i], m[j], x[i] - x[j]);
    return f;
}

}  // namespace

TEST_SUITE("physics") {
    // ---------------------------------------------------------------------------------------------
    // 1. Two touching spheres.
    //
    // Each sphere sits in the other's dipole field. On the line of centres (field along it) that
    // field is 2 m / (4 pi (2R)^3) = m / (16 pi R^3) along the moment, so m = C H0 + beta m / 4 and
    // m = C H0 / (1 - beta/4); side by side it is -m / (32 pi R^3), so m = C H0 / (1 + beta/8). The
    // force goes as m^2: the converged over fixed-dipole ratio is 1/(1 - beta/4)^2 or 1/(1 + beta/8)^2.
    // The settle criterion's magnetic energy, -1/2 sum m . B0 (lib/engine/observers.hpp): a lone sphere's is
    // -1/2 C B0^2 / mu0; two touching spheres' converged moments are the lone one's over (1 - beta/4) in
    // line and over (1 + beta/8) side by side (the closed form below), so their energies are too: a
    // chain lowers it, a side-by-side pair raises it.
    TEST_CASE("magnetic: the induced dipoles' energy in the applied field, lone and in touching pairs") {
        const double R = 1e-3, b0 = 0.01, mu_r = 1000.0;
        const double beta = beta_of(mu_r), C = induced_coefficient(R, mu_r);
        const double lone = -0.5 * C * b0 * b0 / kMu0;
        auto energy = [&](const std::vector<Vec3>& centres) {
            Rig rig(Vec3{0, 0, b0}, MutualPolicy::converged);
            rig.model.settings.tolerance = 1e-12;
            rig.model.settings.max_iterations = 1000;
            for (const Vec3& x : centres) rig.add(x, R, mu_r);
            rig.evaluate();
            System s;
            s.particles = rig.p;
            s.magnetic.enabled = true;
            s.magnetic.field = rig.model.field;
            return induced_magnetic_energy(s);
        };
        // A few roundings and the iteration's 1e-12 separate the engine's sums from these products.
        CHECK(energy({{0, 0, 0}}) == rel(lone).epsilon(1e-12));
        CHECK(energy({{0, 0, 0}, {0, 0, 2 * R}}) == rel(2 * lone / (1 - beta / 4)).epsilon(1e-9));
        CHECK(energy({{0, 0, 0}, {2 * R, 0, 0}}) == rel(2 * lone / (1 + beta / 8)).epsilon(1e-9));
        // With the magnet off there is none.
        System off;
        off.particles.add({0, 0, 0}, R, 7800.0, 0);
        CHECK(induced_magnetic_energy(off) == 0.0);
    }

    TEST_CASE("magnetic: two touching spheres, converged mutual dipoles against the closed form") {
        const double R = 1e-3, b0 = 0.01;  // 1 mm grains in 10 mT
        const double h0 = b0 / kMu0;
        struct Case {
            const char* name;
            Vec3 offset;   // centre of grain 1 relative to grain 0 (grain 0 at the origin)
            bool in_line;  // along the field
        };
        const Case cases[] = {{"in line", {0, 0, 2 * R}, true}, {"side by side", {2 * R, 0, 0}, false}};
        for (const Case& c : cases) {
            for (double mu_r : {2.0, 10.0, 1000.0, 1e6}) {
                CAPTURE(c.name);
                CAPTURE(mu_r);
                const double beta = beta_of(mu_r), C = induced_coefficient(R, mu_r);
                auto run = [&](MutualPolicy policy) {
                    Rig rig(Vec3{0, 0, b0}, policy);
                    rig.model.settings.tolerance = 1e-12;
                    rig.model.settings.max_iterations = 1000;
                    rig.add({0, 0, 0}, R, mu_r);
                    rig.add(c.offset, R, mu_r);
                    rig.evaluate();
                    return rig;
                };
                const Rig fixed = run(MutualPolicy::fixed);
                const Rig conv = run(MutualPolicy::converged);

                // Fixed dipoles: m = C H0 and F = 3 mu0 m^2 / (4 pi r^4) x (2 in line, 1 side by side).
                // Only a few roundings separate the engine's sum from this product: 1e-13 relative.
                const double m = C * h0, r = 2 * R;
                const double f_closed = 3.0 * kMu0 * m * m / (4.0 * kPi * r * r * r * r) * (c.in_line ? 2.0 : 1.0);
                const Vec3 line = c.offset / norm(c.offset);  // from grain 0 to grain 1
                // In line: attraction, grain 0 pulled towards grain 1 (+line). Side by side: repulsion.
                const double f0_line = dot(fixed.p.force[0], line);
                CHECK(fixed.p.dipole_moment[0].z == rel(m).epsilon(1e-14));
                CHECK(f0_line == rel(c.in_line ? f_closed : -f_closed).epsilon(1e-13));
                // Action and reaction; nothing across the line (the moments and the line are coplanar
                // and the force lies along the line by symmetry).
                CHECK(norm(fixed.p.force[0] + fixed.p.force[1]) <= 1e-14 * f_closed);
                CHECK(norm(fixed.p.force[0] - line * f0_line) <= 1e-14 * f_closed);

                // Converged: the iteration contracts by beta/4 (in line) or beta/8 per pass; stopping
                // at a relative change below 1e-12 leaves a moment error below 1e-12 / (1 - 1/4), so
                // the force ratio is good to ~3e-12. 1e-9 relative leaves room for that and rounding.
                const double ratio = dot(conv.p.force[0], line) / f0_line;
                const double expected =
                    c.in_line ? 1.0 / ((1 - beta / 4) * (1 - beta / 4)) : 1.0 / ((1 + beta / 8) * (1 + beta / 8));
                const double m_expected = c.in_line ? m / (1 - beta / 4) : m / (1 + beta / 8);
                report(std::string(c.name) + " mu_r " + str(mu_r) + ": converged/fixed force ratio " + str(ratio, 10) +
                       " (closed form " + str(expected, 10) + "), fixed force " + str(f0_line) + " N (closed form " +
                       str(c.in_line ? f_closed : -f_closed) + " N), iterations " + str(mean_iterations(conv.model)));
                CHECK(ratio == rel(expected).epsilon(1e-9));
                CHECK(conv.p.dipole_moment[0].z == rel(m_expected).epsilon(1e-9));
                CHECK(conv.p.dipole_moment[1].z == rel(m_expected).epsilon(1e-9));
                CHECK(norm(conv.p.force[0] + conv.p.force[1]) <= 1e-14 * f_closed * expected);
                if (mu_r >= 1e6) {
                    // The source's quoted figures (Han, Feng and Owen): 1.7778 and 0.7901, i.e. the
                    // mu_r -> infinity limits 16/9 and 64/81. At mu_r = 1e6, beta = 1 - 3e-6, which
                    // moves the ratio by ~1e-6: well inside the 0.5 % asked for, so check 1e-4 too.
                    const double quoted = c.in_line ? 1.7778 : 0.7901;
                    CHECK(ratio == rel(quoted).epsilon(5e-3));
                    CHECK(ratio == rel(quoted).epsilon(1e-4));  // the quote has 5 figures
                }
            }
        }
    }

    // ---------------------------------------------------------------------------------------------
    // 2. Table 4.3: three touching spheres in an "L", field along z: P2 at the origin, P1 above it
    // (along the field), P3 beside it along x. mu_r = 1000 (iron-like, the chains example's value);
    // mu_r = 1e6 changes every figure below by under 1 %.
    //
    // What the engine does and why it cannot match the table row by row. The mutual dipole method
    // as eqs. 2.6 / 4.12 state it is a Jacobi iteration m^(k+1) = C (H0 + T m^k) started from the
    // fixed dipoles m^0 = C H0 (the engine's `iterations` policy with k passes returns m^k). Its
    // error obeys e^(k+1) = C T e^k with C T symmetric, so ||e^(k+1)|| <= rho ||e^k|| with rho the
    // spectral radius of C T, and the ratio tends to rho. For two touching spheres in line rho is
    // beta/4 exactly (1/4 as mu_r -> infinity); for this L it is 0.32 (computed below). So any
    // implementation of eq. 4.12 gains a factor ~3 per iteration, not the 10-35 of Table 4.3
    // (-23.6 %, -0.66 %, -0.071 %, -0.0044 % for P1). Measured (|F| error vs 1000 iterations, mu_r =
    // 1000): P1 -12.3 %, -3.3 %, -1.0 %, -0.27 %; P2 -12.4 %, -3.3 %, -1.1 %, -0.28 %; P3 -7.7 %,
    // +0.16 %, -0.58 %, +0.026 %. The table's rate is that of an in-place (Gauss-Seidel) sweep, whose
    // factor is ~rho^2 (~10 per sweep here); but no sweep order reproduces its first row (in-place
    // sweeps give 6-11 % at iteration 1), nor does counting the fixed dipoles as iteration 1 (-40 %,
    // -37 %, +0.04 %). The signs agree for P1 and P2: too little force before convergence, since the
    // in-line attraction grows with the mutual fields (the table's sign is that of (|F_k| - |F_1000|)).
    // For P3 the table has +17 %, the engine -7.7 %: P3's force is the sum of P2's side-by-side
    // repulsion (overestimated by fixed dipoles) and P1's diagonal pull, and which wins at iteration 1
    // depends on the iteration scheme. The engine's numbers are instead checked against an
    // independent Jacobi iteration and a direct solve written here.
    TEST_CASE("magnetic: L of three touching spheres, k mutual-dipole iterations against 1000 (Table 4.3)") {
        const double R = 1e-3, b0 = 0.01, mu_r = 1000;
        const double C = induced_coefficient(R, mu_r), h0 = b0 / kMu0;
        const std::vector<Vec3> x = {{0, 0, 2 * R}, {0, 0, 0}, {2 * R, 0, 0}};  // P1, P2, P3

        auto engine = [&](int k) {
            Rig rig(Vec3{0, 0, b0}, MutualPolicy::iterations);
            rig.model.settings.iterations = k;
            rig.model.settings.relaxation = 1.0;  // eq. 4.12 as printed: plain Jacobi
            for (const Vec3& xi : x) rig.add(xi, R, mu_r);
            rig.evaluate();
            CHECK(mean_iterations(rig.model) == k);
            return rig;
        };

        // Direct solve of (I - C T) m = C H0.
        const auto t = dipole_matrix(x);
        const std::size_t n3 = 3 * x.size();
        const std::vector<Vec3> m_exact = direct_moments(t, C, h0);
        const std::vector<Vec3> f_exact = forces_of(x, m_exact);

        // Spectral radius of C T by power iteration (symmetric: the norm ratio converges to it).
        double rho = 0;
        {
            std::vector<double> v(n3, 1.0), w(n3);
            for (int it = 0; it < 2000; ++it) {
                double nv = 0, nw = 0;
                for (std::size_t r = 0; r < n3; ++r) {
                    w[r] = 0;
                    for (std::size_t c = 0; c < n3; ++c) w[r] += C * t[r][c] * v[c];
                }
                for (std::size_t r = 0; r < n3; ++r) {
                    nv += v[r] * v[r];
                    nw += w[r] * w[r];
                }
                rho = std::sqrt(nw / nv);
                for (std::size_t r = 0; r < n3; ++r) v[r] = w[r] / std::sqrt(nw);
            }
        }

        // 1000 iterations: converged (rho^1000 is nothing) to the direct solve. Both are a few
        // hundred roundings of well-conditioned sums (I - C T has condition ~ (1+rho)/(1-rho) < 2):
        // 1e-12 relative to the largest force.
        const Rig ref = engine(1000);
        double f_scale = 0;
        for (const Vec3& f : f_exact) f_scale = std::max(f_scale, norm(f));
        for (std::size_t i = 0; i < x.size(); ++i) {
            CAPTURE(i);
            CHECK(norm(ref.p.dipole_moment[i] - m_exact[i]) <= 1e-12 * norm(m_exact[1]));
            CHECK(norm(ref.p.force[i] - f_exact[i]) <= 1e-12 * f_scale);
        }
        // Newton's third law for the whole L.
        CHECK(norm(ref.p.force[0] + ref.p.force[1] + ref.p.force[2]) <= 1e-13 * f_scale);

        // k = 1..4 against an independent Jacobi iteration (same start: the fixed dipoles).
        std::vector<Vec3> m_jacobi(x.size(), Vec3{0, 0, C * h0});
        double previous_moment_error = 0;
        std::array<double, 3> previous_force_error{};
        const std::vector<Vec3> f_fixed = forces_of(x, m_jacobi);
        for (std::size_t i = 0; i < x.size(); ++i) {
            previous_moment_error += norm2(m_jacobi[i] - m_exact[i]);
            previous_force_error[i] = norm(f_fixed[i] - f_exact[i]) / norm(f_exact[i]);
        }
        previous_moment_error = std::sqrt(previous_moment_error);

        std::ostringstream table;
        table << "L configuration, mu_r 1000, spectral radius of C T " << str(rho, 4)
              << "; |F| error vs 1000 iterations (vector error) per iteration:";
        for (int k = 1; k <= 4; ++k) {
            CAPTURE(k);
            std::vector<Vec3> next(x.size());
            for (std::size_t i = 0; i < x.size(); ++i) {
                Vec3 h{0, 0, h0};
                for (std::size_t j = 0; j < x.size(); ++j)
                    if (j != i) h += dipole_h(m_jacobi[j], x[i] - x[j]);
                next[i] = h * C;
            }
            m_jacobi = next;
            const std::vector<Vec3> f_jacobi = forces_of(x, m_jacobi);
            const Rig rig = engine(k);

            double moment_error = 0;
            for (std::size_t i = 0; i < x.size(); ++i) moment_error += norm2(rig.p.dipole_moment[i] - m_exact[i]);
            moment_error = std::sqrt(moment_error);
            // The contraction bound of a symmetric iteration, with round-off slack (errors here are
            // >= 1e-3 of the moments, round-off 1e-15).
            CHECK(moment_error <= rho * previous_moment_error * (1 + 1e-9));
            previous_moment_error = moment_error;

            table << "\n  k=" << k;
            for (int i = 0; i < 3; ++i) {
                CAPTURE(i);
                // The engine's k-th iterate is the Jacobi iterate: same arithmetic up to the order of
                // the sums, 1e-12 of the largest force.
                CHECK(norm(rig.p.force[i] - f_jacobi[i]) <= 1e-12 * f_scale);
                const double signed_error = (norm(rig.p.force[i]) - norm(ref.p.force[i])) / norm(ref.p.force[i]);
                const double error = norm(rig.p.force[i] - ref.p.force[i]) / norm(ref.p.force[i]);
                table << "  P" << i + 1 << " " << str(100 * signed_error, 4) << " % (" << str(100 * error, 4) << " %)";
                // The force error is linear in the moment error to first order, so from k = 2 on
                // it falls by about rho per iteration; require at least twofold (rho = 0.32 leaves
                // room for the mixing of eigen-components at small k: measured factors 2.4-4.1).
                // From the fixed dipoles to k = 1 the moment errors are large (the pair products
                // are 40 % off) and the second-order part of the force error is not small: P3 only
                // gains a factor 1.4 there.
                if (k >= 2)
                    CHECK(error < 0.5 * previous_force_error[i]);
                else
                    CHECK(error < previous_force_error[i]);
                previous_force_error[i] = error;
                if (k == 1) {
                    // Iteration 1: between 5 % and 20 % off (measured 7.7-13 %; Table 4.3 has 17-24 %,
                    // see above). P1 and P2 fall short in magnitude, as in the table.
                    CHECK(error > 0.05);
                    CHECK(error < 0.20);
                    if (i < 2) CHECK(signed_error < 0);
                }
                if (k == 4) CHECK(error < 0.01);  // rho^4 ~ 1e-2 of the fixed-dipole error (~40 %): measured 0.3 %
            }
        }
        report(table.str());
        CHECK(rho > beta_of(mu_r) / 4);  // the in-line pair's beta/4; the L couples more
        CHECK(rho < 0.35);
    }

    // ---------------------------------------------------------------------------------------------
    // 3. Non-uniform applied field: a FieldMap.

    namespace {

    // A field with constant, linear and quadratic parts in every component (not divergence free:
    // the interpolation and gradient code does not care), sampled on a grid.
    Vec3 test_field(const Vec3& x) {
        const double X = x.x * 1e3, Y = x.y * 1e3, Z = x.z * 1e3;  // mm
        return {0.02 + 0.011 * X - 0.004 * Y * Z + 0.003 * X * X, -0.01 + 0.006 * Y + 0.002 * X * Z - 0.005 * Z * Z,
                0.05 + 0.013 * Z - 0.007 * X * Y + 0.001 * Y * Y};
    }

    FieldMap sample(Vec3 (*f)(const Vec3&), std::array<int, 3> count, Vec3 origin, Vec3 spacing) {
        std::vector<Vec3> values;
        for (int k = 0; k < count[2]; ++k)
            for (int j = 0; j < count[1]; ++j)
                for (int i = 0; i < count[0]; ++i)
                    values.push_back(f(origin + Vec3{i * spacing.x, j * spacing.y, k * spacing.z}));
        return FieldMap(count, origin, spacing, values);
    }

    const std::array<int, 3> kCount{6, 5, 7};
    const Vec3 kOrigin{-1.5e-3, -1e-3, -0.6e-3}, kSpacing{0.5e-3, 0.6e-3, 0.4e-3};

    }  // namespace

    // A touching fcc block of iron grains (108, mu_r 1000, 1 % apart): the most negative eigenvalue
    // of C T is about -1.29, so plain Jacobi (eq. 4.12, relaxation 1) multiplies the alternating
    // mode's error by 1.29 a pass and diverges, while the default relaxation 2/3 maps every
    // eigenvalue in (-2, 1) into (-1, 1) and converges. Both are checked against a direct solve of
    // (I - C T) m = C H0 over every pair (the cutoff covers the block).
    TEST_CASE("magnetic: a dense fcc block of iron grains: relaxed mutual dipoles converge, plain Jacobi diverges") {
        const double R = 1e-3, b0 = 1e-3, mu_r = 1000, a = 2 * R * 1.01 * std::sqrt(2.0);
        const double C = induced_coefficient(R, mu_r), h0 = b0 / kMu0;
        std::vector<Vec3> x;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                for (int k = 0; k < 3; ++k)
                    for (const Vec3& b : {Vec3{0, 0, 0}, Vec3{0.5, 0.5, 0}, Vec3{0.5, 0, 0.5}, Vec3{0, 0.5, 0.5}})
                        x.push_back(Vec3{i + b.x, j + b.y, k + b.z} * a);
        const std::vector<Vec3> exact = direct_moments(dipole_matrix(x), C, h0);
        auto error_of = [&](const Rig& rig) {  // the largest moment error over the largest exact moment
            double worst = 0, scale = 0;
            for (std::size_t i = 0; i < x.size(); ++i) {
                worst = std::max(worst, norm(rig.p.dipole_moment[i] - exact[i]));
                scale = std::max(scale, norm(exact[i]));
            }
            return worst / scale;
        };
        auto converged = [&](double relaxation) {
            Rig rig(Vec3{0, 0, b0}, MutualPolicy::converged, 20.0);
            rig.model.settings.relaxation = relaxation;
            rig.model.settings.tolerance = 1e-14;
            rig.model.settings.max_iterations = 400;
            for (const Vec3& xi : x) rig.add(xi, R, mu_r);
            rig.evaluate();
            return rig;
        };
        const Rig relaxed = converged(2.0 / 3.0);
        // The error contracts by at most 0.77 a pass: 1e-14 of change leaves well under 1e-12.
        CHECK(error_of(relaxed) < 1e-12);
        CHECK(mean_iterations(relaxed.model) < 400);
        // Plain Jacobi: round-off seeds the growing mode; 400 passes at 1.29 blow it up past 1e30.
        const Rig plain = converged(1.0);
        const double plain_error = error_of(plain);
        report("fcc block of 108 iron grains: moment error after the converged policy, relaxation 2/3 " +
               str(error_of(relaxed), 3) + " in " + str(mean_iterations(relaxed.model), 4) + " passes; plain Jacobi " +
               str(plain_error, 3) + " after 400");
        CHECK(!(plain_error < 1.0));

        // The lagged policy (one update a step) reaches the same moments over steps of fixed grains.
        Rig lagged(Vec3{0, 0, b0}, MutualPolicy::lagged, 20.0);
        for (const Vec3& xi : x) lagged.add(xi, R, mu_r);
        lagged.evaluate();
        for (int step = 0; step < 200; ++step) add_magnetic_forces(lagged.model, lagged.p, 0.0, 1);
        CHECK(error_of(lagged) < 1e-12);
    }

    TEST_CASE("magnetic: gradient force of a field map equals the derivative of m . B_ext with m fixed") {
        auto map = std::make_shared<FieldMap>(sample(test_field, kCount, kOrigin, kSpacing));
        // A point well inside a cell: fractions 0.37, 0.52, 0.61 of cells (2, 1, 3).
        const Vec3 x = kOrigin + Vec3{(2 + 0.37) * kSpacing.x, (1 + 0.52) * kSpacing.y, (3 + 0.61) * kSpacing.z};
        const double R = 50e-6;
        std::mt19937_64 rng(11);
        // An induced grain (m along the local B) and a permanent one (m in an arbitrary direction).
        for (int permanent = 0; permanent < 2; ++permanent) {
            CAPTURE(permanent);
            Rig rig(map, MutualPolicy::fixed);
            if (permanent)
                rig.add_permanent(x, R, Vec3{0.3, -0.8, 0.5} * 1e-7, random_orientation(rng));
            else
                rig.add(x, R, 1000.0);
            rig.evaluate();
            const Vec3 m = rig.p.dipole_moment[0];
            const Vec3 f = rig.p.force[0];
            if (!permanent)
                CHECK(norm(m - map->flux_density(x, 0) * (induced_coefficient(R, 1000.0) / kMu0)) <= 1e-14 * norm(m));
            // Central difference with step 0.1 of the cell along each axis: x +- h stays inside the
            // cell (fractions 0.27-0.47, 0.42-0.62, 0.51-0.71), where the trilinear interpolant is
            // linear in that coordinate, so the difference has no truncation error. Round-off:
            // eps |m| |B| / h ~ 1e-16 x 0.06 T / 5e-5 m against |m| |grad B| ~ 10 T/m: ~1e-14
            // relative. 1e-9 is a wide margin (the brief's 1e-6 a wider one).
            Vec3 fd;
            for (int k = 0; k < 3; ++k) {
                Vec3 step{};
                step[k] = 0.1 * kSpacing[k];
                fd[k] =
                    (dot(m, map->flux_density(x + step, 0)) - dot(m, map->flux_density(x - step, 0))) / (2 * step[k]);
            }
            report("gradient force " + str(f.x, 10) + " " + str(f.y, 10) + " " + str(f.z, 10) +
                   " N; finite difference " + str(fd.x, 10) + " " + str(fd.y, 10) + " " + str(fd.z, 10));
            CHECK(norm(f - fd) <= 1e-9 * norm(fd));
            CHECK(norm(fd) > 0);
            // Torque on the permanent grain: m x B_ext. The induced grain gets none.
            if (permanent)
                CHECK(norm(rig.p.torque[0] - cross(m, map->flux_density(x, 0))) <=
                      1e-14 * norm(m) * norm(map->flux_density(x, 0)));
            else
                CHECK(norm(rig.p.torque[0]) == 0);
        }
    }

    TEST_CASE("magnetic: field map interpolates a linear field exactly and round-trips through its file") {
        // B = a + G x: the trilinear interpolant reproduces it, and its gradient is G everywhere.
        static const double G[3][3] = {{12, -3, 5}, {-4, 7, 2}, {6, 1, -9}};  // T/m
        auto linear = [](const Vec3& x) {
            Vec3 b{0.1, -0.2, 0.3};
            for (int l = 0; l < 3; ++l)
                for (int k = 0; k < 3; ++k) b[l] += G[l][k] * x[k];
            return b;
        };
        const FieldMap map = sample(+linear, kCount, kOrigin, kSpacing);
        std::mt19937_64 rng(3);
        const Vec3 hi = map.upper_corner();
        double b_scale = 0;
        for (int s = 0; s < 8; ++s)
            b_scale = std::max(
                b_scale, norm(linear({s & 1 ? hi.x : kOrigin.x, s & 2 ? hi.y : kOrigin.y, s & 4 ? hi.z : kOrigin.z})));
        for (int trial = 0; trial < 200; ++trial) {
            Vec3 x;
            for (int k = 0; k < 3; ++k) x[k] = std::uniform_real_distribution<double>(kOrigin[k], hi[k])(rng);
            // Eight weights summing to 1 times node values of size <= b_scale: round-off ~1e-15 of it.
            CHECK(norm(map.flux_density(x, 0) - linear(x)) <= 1e-13 * b_scale);
            // Gradient: differences of node values over the spacing, round-off ~eps b_scale / dx
            // ~ 1e-12 T/m against entries of ~10 T/m.
            const Gradient g = map.gradient(x, 0);
            for (int l = 0; l < 3; ++l)
                for (int k = 0; k < 3; ++k) CHECK(g[l][k] == rel(G[l][k]).epsilon(1e-10));
        }
        // Beyond a face the value is clamped to the face and the gradient across it is zero; along
        // the face it is the face's.
        {
            const Vec3 inside{hi.x, 0.1e-3, 0.2e-3}, beyond{hi.x + 0.7e-3, 0.1e-3, 0.2e-3};
            CHECK(norm(map.flux_density(beyond, 0) - linear(inside)) <= 1e-13 * b_scale);
            const Gradient g = map.gradient(beyond, 0);
            for (int l = 0; l < 3; ++l) {
                CHECK(g[l][0] == 0);
                CHECK(g[l][1] == rel(G[l][1]).epsilon(1e-10));
                CHECK(g[l][2] == rel(G[l][2]).epsilon(1e-10));
            }
        }

        // Write and read back: 17 significant digits round-trip every double, so the maps agree bit
        // for bit. A scale multiplies the field.
        mrjam_test::TempDir dir("mrjam_fieldmap");
        const FieldMap curved = sample(test_field, kCount, kOrigin, kSpacing);
        curved.write(dir.file("map.txt"));
        const FieldMap back = FieldMap::read(dir.file("map.txt"));
        const FieldMap doubled = FieldMap::read(dir.file("map.txt"), 2.0);
        CHECK(back.lower_corner().x == curved.lower_corner().x);
        CHECK(back.upper_corner().z == curved.upper_corner().z);
        for (int trial = 0; trial < 50; ++trial) {
            Vec3 x;
            for (int k = 0; k < 3; ++k)
                x[k] = std::uniform_real_distribution<double>(kOrigin[k] - 1e-4, hi[k] + 1e-4)(rng);
            const Vec3 b0 = curved.flux_density(x, 0), b1 = back.flux_density(x, 0);
            CHECK(b0.x == b1.x);
            CHECK(b0.y == b1.y);
            CHECK(b0.z == b1.z);
            CHECK(curved.gradient(x, 0) == back.gradient(x, 0));
            CHECK(norm(doubled.flux_density(x, 0) - b0 * 2.0) <= 4 * kEps * norm(b0));
        }
        // A damaged file is refused with its path and line number.
        {
            std::ofstream out(dir.file("bad.txt"));
            out << "mrjam-fieldmap 1\n2 2 2\n0 0 0\n1 1 1\n0 0 1\n0 0 one\n";
        }
        bool threw = false;
        try {
            FieldMap::read(dir.file("bad.txt"));
        } catch (const std::runtime_error& e) {
            threw = true;
            CHECK(std::string(e.what()).find("bad.txt:6") != std::string::npos);
        }
        CHECK(threw);
    }

    // ---------------------------------------------------------------------------------------------
    // 4. Permanent dipoles.
    TEST_CASE("magnetic: a permanent dipole in a uniform field feels the torque m x B and no force") {
        std::mt19937_64 rng(5);
        const Vec3 b{0.03, -0.05, 0.2};
        Rig rig(b, MutualPolicy::lagged);
        const Vec3 body{2e-4, -1e-4, 3e-4};
        const Quaternion q = random_orientation(rng);
        rig.add_permanent({0, 0, 0}, 1e-3, body, q);
        rig.evaluate();
        const Vec3 m = q.rotate(body);
        CHECK(norm(rig.p.dipole_moment[0] - m) <= 4 * kEps * norm(m));
        const Vec3 expected = cross(m, b);
        report("torque " + str(rig.p.torque[0].x) + " " + str(rig.p.torque[0].y) + " " + str(rig.p.torque[0].z) +
               " N m, m x B " + str(expected.x) + " " + str(expected.y) + " " + str(expected.z));
        CHECK(norm(rig.p.torque[0] - expected) <= 1e-14 * norm(m) * norm(b));
        CHECK(norm(rig.p.force[0]) == 0);
    }

    TEST_CASE("magnetic: a pair of permanent dipoles: action and reaction, zero total torque, textbook force") {
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(-1, 1);
        const double R = 1e-3;
        for (int trial = 0; trial < 20; ++trial) {
            CAPTURE(trial);
            Rig rig(Vec3{}, MutualPolicy::fixed, 10.0);
            const Vec3 xi{u(rng) * 1e-3, u(rng) * 1e-3, u(rng) * 1e-3};
            Vec3 dir{u(rng), u(rng), u(rng)};
            dir = dir / norm(dir);
            const Vec3 xj = xi + dir * (R * (2.2 + 4 * (u(rng) + 1)));  // 2.2 to 10.2 radii apart
            rig.add_permanent(xi, R, Vec3{u(rng), u(rng), u(rng)} * 1e-4, random_orientation(rng));
            rig.add_permanent(xj, R, Vec3{u(rng), u(rng), u(rng)} * 1e-4, random_orientation(rng));
            rig.evaluate();
            const Vec3 mi = rig.p.dipole_moment[0], mj = rig.p.dipole_moment[1];
            const Vec3 fi = rig.p.force[0], fj = rig.p.force[1], ti = rig.p.torque[0], tj = rig.p.torque[1];
            // The force is computed once per pair and applied with opposite signs: exactly opposite.
            CHECK(fi.x == -fj.x);
            CHECK(fi.y == -fj.y);
            CHECK(fi.z == -fj.z);
            // Total angular momentum change: sum of torques plus moments of the forces. Each term is
            // a few roundings of products: 1e-13 of the largest term.
            const Vec3 total = ti + tj + cross(rig.p.position[0], fi) + cross(rig.p.position[1], fj);
            const double scale =
                norm(ti) + norm(tj) + norm(cross(rig.p.position[0], fi)) + norm(cross(rig.p.position[1], fj));
            CHECK(norm(total) <= 1e-13 * scale);
            // Torque mu0 m_i x H_j(x_i), from the textbook field.
            CHECK(norm(ti - cross(mi, dipole_h(mj, xi - xj)) * kMu0) <= 1e-12 * norm(ti));
            CHECK(norm(tj - cross(mj, dipole_h(mi, xj - xi)) * kMu0) <= 1e-12 * norm(tj));
            // Force: the gradient of mu0 m_i . H_j(x) at x_i with the moments fixed, by a central
            // difference of step 1e-5 r (truncation ~(1e-5)^2 = 1e-10 relative, round-off
            // eps / 1e-5 ~ 2e-11): 1e-8 relative.
            const double h = 1e-5 * norm(xi - xj);
            Vec3 fd;
            for (int k = 0; k < 3; ++k) {
                Vec3 s{};
                s[k] = h;
                fd[k] = kMu0 * (dot(mi, dipole_h(mj, xi + s - xj)) - dot(mi, dipole_h(mj, xi - s - xj))) / (2 * h);
            }
            CHECK(norm(fi - fd) <= 1e-8 * norm(fd));
        }
    }

    TEST_CASE("magnetic: two free permanent dipoles conserve linear and angular momentum over many steps") {
        // Two 1 mm iron-density grains with remanence ~1e5 A/m (m ~ 4e-4 A m^2), 6 radii apart, random
        // orientations, velocities and spins; no contact model, no applied field, fixed policy (the
        // moments follow the orientations each step). Torques ~1e-7 N m turn the grains by ~1 rad in
        // the 0.05 s simulated; forces ~1e-4 N bring them ~0.5 R closer: they never touch.
        //
        // Why round-off only. In a half kick the positions are fixed, so the change of
        // L = sum (x_i x m_i v_i + I_i w_i) is h (sum x_i x F_i + tau_i), zero because the pair
        // forces and torques are (checked above); in the drift x_i += v_i dt, x_i x m_i v_i changes by
        // dt v_i x m_i v_i = 0. Linear momentum: F_i = -F_j exactly. So both drift only by rounding,
        // of order (steps) eps |L|: 2e4 x 1e-16 = 2e-12. 1e-10 leaves a factor 50, while a torque of
        // the wrong sign or size would change L by ~ integral |tau| dt ~ 1e-9, comparable to L.
        std::mt19937_64 rng(13);
        std::uniform_real_distribution<double> u(-1, 1);
        const double R = 1e-3, density = 7800;
        System s;
        s.domain.lo = {-0.05, -0.05, -0.05};
        s.domain.hi = {0.05, 0.05, 0.05};
        s.physics.contact = false;
        const double skin = 0.2 * R;
        s.contacts = NeighborList(NeighborList::Settings{skin, 1.0, true});
        Particles& p = s.particles;
        const double volume = 4.0 / 3.0 * kPi * R * R * R;
        for (int i = 0; i < 2; ++i) {
            const Vec3 x = Vec3{(i ? 3.0 : -3.0) * R, 0.4 * R * u(rng), 0.4 * R * u(rng)};
            const std::size_t k = p.add(x, R, density, 0);
            Vec3 dir{u(rng), u(rng), u(rng)};
            p.permanent_moment[k] = dir / norm(dir) * (1e5 * volume);
            p.orientation[k] = random_orientation(rng);
            p.saturation_moment[k] = 1e100;
            p.velocity[k] = Vec3{u(rng), u(rng), u(rng)} * 2e-3;
            p.angular_velocity[k] = Vec3{u(rng), u(rng), u(rng)} * 5.0;
        }
        MagneticModel& mag = s.magnetic;
        mag.enabled = true;
        s.terms.add(std::make_unique<MagneticTerm>());
        mag.field = std::make_shared<UniformField>(Vec3{}, 0.0, 0.0, 1e300);
        mag.settings.policy = MutualPolicy::fixed;
        mag.settings.cutoff_scale = 20;
        mag.pairs = NeighborList(NeighborList::Settings{skin, 20.0, false, 0.0});
        mag.any_permanent = true;
        initialise_moments(mag, p, 0.0);
        s.dt = 2.5e-6;
        prepare(s);

        auto linear = [&] {
            Vec3 l{};
            for (std::size_t i = 0; i < p.size(); ++i) l += p.velocity[i] * p.mass[i];
            return l;
        };
        auto angular = [&] {
            Vec3 l{};
            for (std::size_t i = 0; i < p.size(); ++i)
                l += cross(p.position[i], p.velocity[i] * p.mass[i]) + p.angular_velocity[i] * p.inertia[i];
            return l;
        };
        auto scales = [&](double& ps, double& ls) {
            for (std::size_t i = 0; i < p.size(); ++i) {
                ps = std::max(ps, p.mass[i] * norm(p.velocity[i]));
                ls = std::max(ls, norm(cross(p.position[i], p.velocity[i] * p.mass[i])) +
                                      p.inertia[i] * norm(p.angular_velocity[i]));
            }
        };
        const Vec3 p0 = linear(), l0 = angular();
        const Vec3 spin0 = p.angular_velocity[0] * p.inertia[0];
        double p_scale = 0, l_scale = 0, worst_p = 0, worst_l = 0, min_gap = 1;
        scales(p_scale, l_scale);
        for (int chunk = 0; chunk < 100; ++chunk) {
            advance_steps(s, 200);
            scales(p_scale, l_scale);
            worst_p = std::max(worst_p, norm(linear() - p0));
            worst_l = std::max(worst_l, norm(angular() - l0));
            min_gap = std::min(min_gap, norm(p.position[0] - p.position[1]) - 2 * R);
        }
        const double spin_exchange = norm(p.angular_velocity[0] * p.inertia[0] - spin0);
        report("free dipole pair over 2e4 steps: |dP| / P " + str(worst_p / p_scale) + ", |dL| / L " +
               str(worst_l / l_scale) + ", spin angular momentum exchanged " + str(spin_exchange / l_scale) +
               " of L, closest gap " + str(min_gap / R) + " R");
        CHECK(min_gap > 2 * R);  // far apart throughout: no contact needed
        CHECK(worst_p <= 1e-10 * p_scale);
        CHECK(worst_l <= 1e-10 * l_scale);
        // The test is not vacuous: the torques moved a sizeable share of the angular momentum.
        CHECK(spin_exchange > 0.05 * l_scale);
    }

    // ---------------------------------------------------------------------------------------------
    // Threads: the same forces (within round-off) whatever the thread count.
    TEST_CASE("magnetic: forces, torques and moments do not depend on the thread count beyond round-off") {
        // In a uniform field and in a field map (its gradient force and the permanent grains'
        // torques summed per grain over the threads).
        const std::shared_ptr<ExternalField> fields[2] = {
            std::make_shared<UniformField>(Vec3{0.01, 0.02, 0.3}, 0.0, 0.0, 1e300),
            std::make_shared<FieldMap>(sample(test_field, kCount, kOrigin, kSpacing))};
        for (const auto& field : fields) {
            CAPTURE(field->name());
            auto build = [&](std::uint64_t seed) {
                std::mt19937_64 g(seed);
                std::uniform_real_distribution<double> v(0, 1);
                Rig rig(field, MutualPolicy::converged, 3.0);
                rig.model.settings.tolerance = 1e-13;
                const double R = 1e-4;
                // 60 grains on a jittered cubic lattice of spacing 2.2 R, every tenth permanent.
                int k = 0;
                for (int i = 0; i < 4; ++i)
                    for (int j = 0; j < 5; ++j)
                        for (int l = 0; l < 3; ++l, ++k) {
                            const Vec3 x{2.2 * R * i + 0.1 * R * v(g), 2.2 * R * j + 0.1 * R * v(g),
                                         2.2 * R * l + 0.1 * R * v(g)};
                            if (k % 10 == 3)
                                rig.add_permanent(x, R, Vec3{v(g) - 0.5, v(g) - 0.5, v(g) - 0.5} * 1e-6,
                                                  random_orientation(g));
                            else
                                rig.add(x, R, 1000.0, 1.7e6 * 4.0 / 3.0 * kPi * R * R * R);
                        }
                return rig;
            };
            Rig one = build(99), three = build(99);
            one.evaluate(1);
            three.evaluate(3);
            double f_scale = 0, t_scale = 0, m_scale = 0;
            for (std::size_t i = 0; i < one.p.size(); ++i) {
                f_scale = std::max(f_scale, norm(one.p.force[i]));
                t_scale = std::max(t_scale, norm(one.p.torque[i]));
                m_scale = std::max(m_scale, norm(one.p.dipole_moment[i]));
            }
            REQUIRE(f_scale > 0);
            REQUIRE(t_scale > 0);
            // Sums in a different order: a few hundred roundings, ~1e-14 of the largest term; and the
            // converged iteration stops on a change below 1e-13, so the two runs may stop one pass
            // apart, ~1e-13 of the moments. 1e-11 of the largest term covers both.
            for (std::size_t i = 0; i < one.p.size(); ++i) {
                CAPTURE(i);
                CHECK(norm(one.p.force[i] - three.p.force[i]) <= 1e-11 * f_scale);
                CHECK(norm(one.p.torque[i] - three.p.torque[i]) <= 1e-11 * t_scale);
                CHECK(norm(one.p.dipole_moment[i] - three.p.dipole_moment[i]) <= 1e-11 * m_scale);
            }
        }
    }

    // ---------------------------------------------------------------------------------------------
    // 5. Chains through the scene path.
    //
    // Iron grains (6.7 um, mu_r 1000, M_s 1.7e6 A/m, cohesion and rolling resistance as in
    // examples/chains_600mT.json) at volume fraction 0.3 in a 50 um box (238 grains) periodic in x
    // and y between walls, in 10 mPa s oil, 600 mT along z, lagged mutual dipoles, for 20 us (3924
    // steps, ~0.5 s). The grains chain within ~4 us and then sit in columns.
    //
    // Thresholds. For contact normals spread uniformly over the sphere the mean |cos| to any axis is
    // 1/2, the fraction with |cos| > 0.9 is 0.1 and the fraction in the dipoles' repulsive cone
    // (|cos| < 1/sqrt(3)) is 0.577. Isolated straight chains would give 1, 1 and 0. But at volume
    // fraction 0.3 chains coalesce into columns: in the body-centred tetragonal ground state of
    // such columns each sphere touches 2 chain neighbours (|cos| = 1) and 8 in the neighbouring
    // chains, half a diameter up or down (|cos| = 1/2), a mean of 0.6. So "> 0.8" would demand
    // isolated chains, which this density does not form; we require > 0.62, above the column
    // value and 8 standard errors above isotropy (400 contacts: sigma = 0.29 / sqrt(400) = 0.014).
    // Measured: 0.71 (cohesion on; 0.69 frictionless and cohesionless), with 35 % of contacts within
    // 26 degrees of the field and ~30 % in the repulsive cone.
    // At the start no grains touch (random insertion), so the start is measured on near pairs (gap
    // below 5 % of the contact distance): 0.49 there at the start, 0.68 at the end.
    namespace {

    struct Alignment {
        double mean_cos = 0;
        long pairs = 0;
        double aligned = 0;    // fraction with |cos| > 0.9
        double repulsive = 0;  // fraction with |cos| < 1/sqrt(3)
    };

    Alignment alignment(const System& s, double reach) {
        const Particles& p = s.particles;
        const NeighborList& list = s.contacts;
        Alignment a;
        for (std::size_t i = 0; i < p.size(); ++i)
            for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
                const std::uint32_t j = list.partners[k];
                const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
                const double r = norm(d);
                if (r >= reach * (p.radius[i] + p.radius[j])) continue;
                const double c = std::fabs(d.z) / r;
                a.mean_cos += c;
                a.aligned += c > 0.9;
                a.repulsive += c < 1.0 / std::sqrt(3.0);
                ++a.pairs;
            }
        if (a.pairs) {
            a.mean_cos /= a.pairs;
            a.aligned /= a.pairs;
            a.repulsive /= a.pairs;
        }
        return a;
    }

    }  // namespace

    TEST_CASE("magnetic: iron grains at volume fraction 0.3 form contacts aligned with the field") {
        const auto start = std::chrono::steady_clock::now();
        const json scene_json = json::parse(R"({
      "seed": 5,
      "domain": {"lo": [0, 0, 0], "hi": ["50 um", "50 um", "50 um"], "periodic": "xy"},
      "materials": [
        {"name": "iron", "density": "7800 kg/m3", "youngs_modulus": "1 GPa", "poisson_ratio": 0.278,
         "restitution": 0.1, "friction": 0.1, "rolling_friction": 0.1, "rolling_damping": 0.1,
         "cohesion_energy_density": "60 kJ/m3", "relative_permeability": 1000, "saturation_magnetisation": "1.7e6 A/m"}
      ],
      "contact": {"model": "hertz_mindlin", "rolling": "epsd", "cohesion": "sjkr"},
      "fluid": {"viscosity": "10 mPa s"},
      "magnetic": {"field": {"type": "uniform", "flux_density": [0, 0, "600 mT"]},
                   "mutual": "lagged", "cutoff": {"beyond_contact": "8 um"}},
      "walls": [
        {"name": "bottom", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]},
        {"name": "top", "type": "plane", "point": [0, 0, "50 um"], "normal": [0, 0, -1]}
      ],
      "grains": [
        {"material": "iron", "size": {"distribution": "single", "diameter": "6.7 um"},
         "placement": {"method": "random", "volume_fraction": 0.3}}
      ],
      "run": {"duration": "20 us", "characteristic_speed": "1 m/s", "timestep_safety": 0.1}
    })");
        BuildOptions options;  // timestep_safety pinned above: independent of the fidelity tier's default
        Scene scene = build_scene(scene_json, options);
        choose_timestep(scene);
        System& s = scene.system;
        prepare(s);
        const std::size_t n = s.particles.size();
        CHECK(n >= 200);
        CHECK(n <= 400);
        const Alignment near0 = alignment(s, 1.05), touch0 = alignment(s, 1.0);
        advance_steps(s, scene.stages.front().steps);
        const Alignment near1 = alignment(s, 1.05), touch1 = alignment(s, 1.0);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        report("chains: " + std::to_string(n) + " grains, " + std::to_string(scene.stages.front().steps) +
               " steps in " + str(seconds, 3) + " s; start: " + std::to_string(touch0.pairs) +
               " contacts, near pairs " + std::to_string(near0.pairs) + " with mean |cos| " + str(near0.mean_cos, 3) +
               "; end: " + std::to_string(touch1.pairs) + " contacts, mean |cos| " + str(touch1.mean_cos, 3) +
               ", |cos| > 0.9: " + str(touch1.aligned, 3) + ", repulsive cone: " + str(touch1.repulsive, 3) +
               "; near pairs mean |cos| " + str(near1.mean_cos, 3) + ", mean iterations " +
               str(mean_iterations(s.magnetic)));
        // The start is isotropic: ~125 near pairs, standard error 0.026; 0.1 is ~4 of them.
        REQUIRE(near0.pairs > 50);
        CHECK(std::fabs(near0.mean_cos - 0.5) < 0.1);
        // Chains: far more contacts (touching: at least one per grain; ~1.8 measured), aligned.
        CHECK(touch1.pairs > static_cast<long>(n));
        CHECK(touch1.mean_cos > 0.62);
        CHECK(touch1.aligned > 0.25);    // 2.5 x the isotropic 0.1 (measured 0.35)
        CHECK(touch1.repulsive < 0.45);  // isotropic 0.577 (measured 0.30)
        CHECK(near1.mean_cos > near0.mean_cos + 0.1);
        CHECK(touch1.mean_cos > near0.mean_cos + 0.1);
        CHECK(seconds < 20);
    }

    // The magnetic range is a pair list the magnet alone uses: while the magnet is off it is not built,
    // and the first step with the magnet on builds it, at that step's positions.
    TEST_CASE("magnetic: the magnetic pair list waits for the magnet and is built the step it switches on") {
        const json scene_json = json::parse(R"({
      "seed": 6,
      "domain": {"lo": [0, 0, 0], "hi": ["40 um", "40 um", "40 um"], "periodic": "xyz"},
      "materials": [{"name": "iron", "density": "7800 kg/m3", "youngs_modulus": "1 GPa", "poisson_ratio": 0.278,
                     "restitution": 0.1, "friction": 0.1, "relative_permeability": 1000}],
      "contact": {"model": "hertz_mindlin"},
      "magnetic": {"field": {"type": "uniform", "flux_density": [0, 0, "200 mT"], "switch_on": "0.5 us"},
                   "mutual": "lagged", "cutoff": {"diameters": 2}},
      "grains": [{"material": "iron", "size": {"distribution": "single", "diameter": "5 um"},
                  "placement": {"method": "random", "volume_fraction": 0.3}}],
      "run": {"duration": "1 us", "characteristic_speed": "1 m/s"}
    })");
        Scene scene = build_scene(scene_json, BuildOptions{});
        choose_timestep(scene);
        System& s = scene.system;
        prepare(s);
        const std::size_t n = s.particles.size();
        REQUIRE(n > 100);
        long steps = 0;
        while (s.magnetic.force_passes == 0 && steps < 1000000) {
            REQUIRE(s.magnetic.pairs.builds() == 0);
            REQUIRE_FALSE(s.magnetic.pairs.current(n));
            advance(s);
            ++steps;
        }
        REQUIRE(s.magnetic.force_passes == 1);
        CHECK(s.time >= 0.5e-6);
        CHECK(s.time - s.dt < 0.5e-6);
        CHECK(s.magnetic.pairs.builds() == 1);
        CHECK(s.magnetic.pairs.current(n));
        // The same pairs as a list built from scratch at the positions it was built at.
        Particles at_build = s.particles;
        std::copy(s.magnetic.pairs.positions_at_build(), s.magnetic.pairs.positions_at_build() + n,
                  at_build.position.begin());
        NeighborList fresh(s.magnetic.pairs.settings());
        fresh.build(at_build, s.domain, 1);
        auto pairs_of = [n](const NeighborList& l) {
            std::vector<std::array<std::uint32_t, 3>> out;
            for (std::uint32_t i = 0; i < n; ++i)
                for (std::uint32_t k = l.offsets[i]; k < l.offsets[i + 1]; ++k)
                    out.push_back({i, l.partners[k], l.image[k]});
            std::sort(out.begin(), out.end());
            return out;
        };
        CHECK(fresh.pair_count() > n);
        CHECK(pairs_of(fresh) == pairs_of(s.magnetic.pairs));
        // The lagged moments of that first step are still zero (the magnet was off the step before);
        // one step later the grains along the field attract.
        advance(s);
        double largest = 0;
        for (const Vec3& f : s.particles.force) largest = std::max(largest, norm(f));
        CHECK(largest > 0);
    }

    // ---------------------------------------------------------------------------------------------
    // 6. Saturation.
    TEST_CASE("magnetic: the induced moment saturates at M_s V") {
        const double R = 2e-6, mu_r = 1000, ms = 1.7e6;
        const double volume = 4.0 / 3.0 * kPi * R * R * R;
        const Vec3 dir = Vec3{0.2, -0.3, 0.9} / norm(Vec3{0.2, -0.3, 0.9});
        // Linear moment 4 pi R^3 beta H = 3 beta V H: the knee is at H = M_s / (3 beta) = 0.57 MA/m,
        // B = 0.71 T. At 0.5 T the grain is linear; at 2 T and 50 T it is capped.
        for (double b : {0.5, 2.0, 50.0}) {
            CAPTURE(b);
            Rig rig(dir * b, MutualPolicy::fixed);
            rig.add({0, 0, 0}, R, mu_r, ms * volume);
            rig.evaluate();
            const Vec3 m = rig.p.dipole_moment[0];
            const double linear = induced_coefficient(R, mu_r) * b / kMu0;
            report("B " + str(b) + " T: |m| " + str(norm(m), 12) + " A m^2, linear " + str(linear) + ", M_s V " +
                   str(ms * volume, 12));
            // Along the field either way (a scaling of the field direction: a few roundings).
            CHECK(norm(cross(m, dir)) <= 8 * kEps * norm(m));
            if (linear < ms * volume) {
                CHECK(norm(m) == rel(linear).epsilon(1e-14));
            } else {
                // The cap rescales by M_s V / |m|: |m| = M_s V to a couple of roundings.
                CHECK(std::fabs(norm(m) - ms * volume) <= 8 * kEps * ms * volume);
            }
        }
        // Two touching grains far into saturation, iterated to convergence: both at M_s V.
        Rig pair(Vec3{0, 0, 5.0}, MutualPolicy::converged);
        pair.model.settings.tolerance = 1e-12;
        pair.add({0, 0, 0}, R, mu_r, ms * volume);
        pair.add({0, 0, 2 * R}, R, mu_r, ms * volume);
        pair.evaluate();
        for (int i = 0; i < 2; ++i)
            CHECK(std::fabs(norm(pair.p.dipole_moment[i]) - ms * volume) <= 8 * kEps * ms * volume);
    }

    // ---------------------------------------------------------------------------------------------
    // 7. A magnet switched off (the jam predictor's no-field flow and its release test).
    TEST_CASE(
        "magnetic: with the magnet switched off soft grains lose their moments at once; permanent ones still act") {
        const double R = 1e-4, T_off = 1e-3;
        auto field = std::make_shared<SwitchedField>(std::make_shared<UniformField>(Vec3{0, 0.23, 0}, 0.0, 0.0, 1e300),
                                                     0.0, T_off);
        Rig rig(field, MutualPolicy::lagged);
        // A touching chain of three soft grains along the field: with the field on they attract.
        for (int k = 0; k < 3; ++k) rig.add({0, 2 * R * k, 0}, R, 1000.0);
        rig.evaluate();
        REQUIRE(norm(rig.p.force[0]) > 0);
        REQUIRE(rig.model.skipped_passes == 0);

        // Field off: no applied field and no permanent moment, so the self-consistent moments are
        // zero (the lagged update would have left m = chi H_neighbours and let it decay step by step).
        for (auto& f : rig.p.force) f = Vec3{};
        add_magnetic_forces(rig.model, rig.p, 2 * T_off, 1);
        CHECK(rig.model.skipped_passes == 1);
        for (std::size_t i = 0; i < rig.p.size(); ++i) {
            CHECK(norm(rig.p.dipole_moment[i]) == 0);
            CHECK(norm(rig.p.force[i]) == 0);
        }

        // The same switch with a permanent dipole beside the chain: the pass still runs and the
        // permanent grain polarises its neighbour, which then attracts it.
        Rig mixed(field, MutualPolicy::lagged);
        mixed.add({0, 0, 0}, R, 1000.0);
        mixed.add_permanent({0, 2.5 * R, 0}, R, Vec3{0, 1e-9, 0}, Quaternion{});
        mixed.evaluate();
        for (int step = 0; step < 3; ++step) {
            for (auto& f : mixed.p.force) f = Vec3{};
            add_magnetic_forces(mixed.model, mixed.p, 2 * T_off, 1);
        }
        CHECK(mixed.model.skipped_passes == 0);
        CHECK(norm(mixed.p.dipole_moment[0]) > 0);
        CHECK(mixed.p.force[0].y > 0);  // pulled towards the permanent grain at +y
        CHECK(mixed.p.force[0].y == -mixed.p.force[1].y);
    }

    // ---------------------------------------------------------------------------------------------
    // 8. Held magnetic forces (update_interval k): two soft grains pulled together along the field.
    TEST_CASE("magnetic: forces held for k steps: the approach of two grains converges to the exact one as k -> 1") {
        // Two 5 um iron grains (mu_r 1000) on the field's axis, 3 radii apart, at rest, no contact
        // law and no fluid; fixed dipoles, so each carries m = C H0 and the pair attracts with
        // F = 6 mu0 m^2 / (4 pi r^4). The reference is that ODE for r integrated by RK4 at a 50th of
        // the engine's step: the time at which r reaches 2R (contact) and the speed there.
        //
        // What holding costs: the force applied at a step is the one evaluated at most k - 1 steps
        // before, at a larger separation, so it is weaker than the exact one while the grains close
        // in: they arrive late, by less than the lag (k - 1) dt, and the delay grows in proportion
        // to k - 1 (a first-order error in the hold). With k = 1 only velocity Verlet's O(dt^2)
        // error is left. Wrong holds fail: forces added only on evaluating steps arrive ~sqrt(k)
        // times later, forces added twice arrive early, and forces never refreshed far too late.
        const double R = 5e-6, density = 7800, mu_r = 1000, B = 0.2, dt = 1e-9;
        const double m = induced_coefficient(R, mu_r) * B / kMu0;
        const double mass = density * 4.0 / 3.0 * kPi * R * R * R;
        const double pull = 6.0 * kMu0 / (4.0 * kPi) * m * m;  // F = pull / r^4 on each grain

        // Reference: r'' = -2 F / M (relative motion of two equal masses).
        double ref_time = 0, ref_speed = 0;
        {
            auto accel = [&](double r) { return -2.0 * pull / (r * r * r * r) / mass; };
            double r = 3 * R, v = 0, t = 0;
            const double h = dt / 50;
            while (true) {
                const double k1r = v, k1v = accel(r);
                const double k2r = v + 0.5 * h * k1v, k2v = accel(r + 0.5 * h * k1r);
                const double k3r = v + 0.5 * h * k2v, k3v = accel(r + 0.5 * h * k2r);
                const double k4r = v + h * k3v, k4v = accel(r + h * k3r);
                const double r_next = r + h / 6 * (k1r + 2 * k2r + 2 * k3r + k4r);
                const double v_next = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
                if (r_next <= 2 * R) {
                    const double s = (r - 2 * R) / (r - r_next);
                    ref_time = t + s * h;
                    ref_speed = -(v + s * (v_next - v));
                    break;
                }
                r = r_next, v = v_next, t += h;
            }
        }

        // The engine: separation and closing speed at contact, interpolated between steps.
        struct Arrival {
            double time, speed;
            long held;
        };
        auto arrive = [&](int interval) {
            System s;
            s.domain.lo = {-1e-4, -1e-4, -1e-4};
            s.domain.hi = {1e-4, 1e-4, 1e-4};
            s.physics.contact = false;
            s.contacts = NeighborList(NeighborList::Settings{0.2 * R, 1.0, true});
            Particles& p = s.particles;
            for (int i = 0; i < 2; ++i) {
                const std::size_t k = p.add({(i ? 1.5 : -1.5) * R, 0, 0}, R, density, 0);
                p.induced_coefficient[k] = induced_coefficient(R, mu_r);
                p.saturation_moment[k] = 1e100;
            }
            MagneticModel& mag = s.magnetic;
            mag.enabled = true;
            s.terms.add(std::make_unique<MagneticTerm>());
            mag.field = std::make_shared<UniformField>(Vec3{B, 0, 0}, 0.0, 0.0, 1e300);
            mag.settings.policy = MutualPolicy::fixed;
            mag.settings.cutoff_scale = 4;
            mag.hold.interval = interval;
            mag.pairs = NeighborList(NeighborList::Settings{0.2 * R, 4.0, false, 0.0});
            initialise_moments(mag, p, 0.0);
            s.dt = dt;
            prepare(s);
            double r = 3 * R, v = 0;
            for (long step = 0; step < 1000000; ++step) {
                advance(s);
                const double r_next = p.position[1].x - p.position[0].x;
                const double v_next = p.velocity[0].x - p.velocity[1].x;
                if (r_next <= 2 * R) {
                    const double f = (r - 2 * R) / (r - r_next);
                    return Arrival{(s.time - dt) + f * dt, v + f * (v_next - v), mag.hold.reused};
                }
                r = r_next, v = v_next;
            }
            FAIL("the grains never met");
            return Arrival{};
        };

        const Arrival exact = arrive(1);
        const double steps = ref_time / dt;
        report("two grains closing 1 R: reference " + str(ref_time * 1e6) + " us (" + str(steps) + " steps), speed " +
               str(ref_speed) + " m/s; interval 1: delay " + str((exact.time - ref_time) / dt) + " steps");
        REQUIRE(steps > 1000);  // long enough that a lag of a few steps is a small error
        CHECK(exact.held == 0);
        CHECK(std::fabs(exact.time - ref_time) < 0.05 * dt);
        CHECK(std::fabs(exact.speed - ref_speed) < 1e-4 * ref_speed);
        double last_delay = 0;
        int last_k = 1;
        for (int k : {2, 4, 8}) {
            const Arrival a = arrive(k);
            const double delay = (a.time - exact.time) / dt;  // in steps
            const double speed_error = (a.speed - exact.speed) / exact.speed;
            report("interval " + std::to_string(k) + ": arrives " + str(delay) + " steps late (lag " +
                   std::to_string(k - 1) + " steps), closing speed " + str(100 * speed_error) + " %, held on " +
                   std::to_string(a.held) + " steps");
            CHECK(a.held > 0);
            CHECK(delay > 0);           // weaker forces while closing in
            CHECK(delay < k - 1);       // by less than the lag
            CHECK(delay > last_delay);  // and more the longer the hold
            // First order in the hold: the delay about proportional to k - 1.
            if (last_k > 1) CHECK(delay == doctest::Approx(last_delay * (k - 1) / (last_k - 1)).epsilon(0.3));
            CHECK(std::fabs(speed_error) < 0.01);
            last_delay = delay;
            last_k = k;
        }
    }

    // Checkpoints written before another policy's settings were refused record all three in their
    // resolved scene; rebuilt to resume (no grains inserted) they must still be read, while the same
    // scene given new is refused at the first unused key.
    TEST_CASE("magnetic: another policy's settings are refused in a new scene, read in a checkpoint's") {
        json scene_json = json::parse(R"({
      "seed": 6,
      "domain": {"lo": [0, 0, 0], "hi": ["40 um", "40 um", "40 um"], "periodic": "xyz"},
      "materials": [{"name": "iron", "density": "7800 kg/m3", "youngs_modulus": "1 GPa"}],
      "magnetic": {"field": {"type": "uniform", "flux_density": [0, 0, "200 mT"]},
                   "mutual": "lagged", "iterations": 1, "tolerance": 1e-6, "max_iterations": 500},
      "grains": [{"material": "iron", "size": {"distribution": "single", "diameter": "5 um"},
                  "placement": {"method": "random", "volume_fraction": 0.1}}],
      "run": {"duration": "1 us"}
    })");
        std::string refused_at;
        try {
            build_scene(scene_json, BuildOptions{});
        } catch (const SceneError& e) {
            refused_at = e.path();
        }
        CHECK(refused_at == "/magnetic/iterations");
        BuildOptions resume;
        resume.insert_grains = false;
        const Scene restored = build_scene(scene_json, resume);
        CHECK(restored.system.magnetic.settings.policy == MutualPolicy::lagged);
        scene_json["magnetic"].erase("iterations");
        scene_json["magnetic"].erase("tolerance");
        scene_json["magnetic"].erase("max_iterations");
        const Scene fresh = build_scene(scene_json, BuildOptions{});
        // Only the policy's own settings are recorded, so a resolved scene can be run again as given.
        CHECK_FALSE(fresh.resolved["magnetic"].contains("iterations"));
        CHECK_FALSE(fresh.resolved["magnetic"].contains("tolerance"));
        // The relaxation is recorded for a mutual policy, refused for fixed dipoles and outside (0, 1].
        CHECK(fresh.resolved["magnetic"]["relaxation"].get<double>() == doctest::Approx(2.0 / 3.0).epsilon(1e-15));
        auto refusal = [&](const json& magnetic) {
            json scene = scene_json;
            scene["magnetic"].update(magnetic);
            try {
                build_scene(scene, BuildOptions{});
            } catch (const SceneError& e) {
                return e.path();
            }
            return std::string("accepted");
        };
        CHECK(refusal({{"mutual", "fixed"}, {"relaxation", 0.5}}) == "/magnetic/relaxation");
        CHECK(refusal({{"relaxation", 0.0}}) == "/magnetic/relaxation");
        CHECK(refusal({{"relaxation", 1.5}}) == "/magnetic/relaxation");
        CHECK(refusal({{"relaxation", 1.0}}) == "accepted");
    }

    // `run` used to hold the map's edge value for grains outside it, silently, while `jam` refused
    // the same map: a map that misses a grain is refused, one the domain outgrows is a warning.
    TEST_CASE("field map coverage: a map that misses a grain is refused by name; a smaller domain is fine") {
        mrjam_test::TempDir dir("mrjam_coverage");
        const FieldMap map({3, 3, 3}, Vec3{0, 0, 0}, Vec3{5e-3, 5e-3, 5e-3}, std::vector<Vec3>(27, Vec3{0, 0, 0.1}));
        map.write(dir.file("map.txt"));
        auto scene = [&](const Vec3& grain, double box) {
            return json{
                {"domain", {{"lo", {0, 0, 0}}, {"hi", {box, box, box}}}},
                {"materials",
                 {{{"name", "iron"}, {"density", 7800}, {"youngs_modulus", 1e9}, {"relative_permeability", 1000}}}},
                {"magnetic", {{"field", {{"type", "map"}, {"file", dir.file("map.txt")}}}}},
                {"grains",
                 {{{"material", "iron"},
                   {"size", {{"distribution", "single"}, {"diameter", 1e-3}}},
                   {"placement", {{"method", "list"}, {"positions", {{grain.x, grain.y, grain.z}}}}}}}},
                {"run", {{"steps", 1}}}};
        };
        const Scene inside = build_scene(scene({5e-3, 5e-3, 5e-3}, 10e-3), BuildOptions{});
        CHECK(inside.warnings.empty());
        const Scene bigger = build_scene(scene({5e-3, 5e-3, 5e-3}, 30e-3), BuildOptions{});
        REQUIRE(bigger.warnings.size() == 1);
        CHECK(bigger.warnings[0].find("beyond the field map") != std::string::npos);
        try {
            build_scene(scene({20e-3, 5e-3, 5e-3}, 30e-3), BuildOptions{});
            FAIL("a grain 10 mm outside the map was accepted");
        } catch (const SceneError& e) {
            CHECK(e.path() == "/magnetic/field/file");
            CHECK(std::string(e.what()).find("does not reach grain 0") != std::string::npos);
        }
    }

}  // TEST_SUITE
