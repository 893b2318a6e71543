// The saturating two-sphere force (magnetics/sphere_pair_fem, gmsh + GetDP) and the engine's
// saturating close-pair correction built from its bundled table.
//
//  1. Linear iron: the finite-element force and moment agree with the exact multipole solution
//     (lib/engine/magnetic/sphere_pair_exact) from 0.1 down to 0.001 radii, where the exact
//     force is 80 times the point dipoles'. Tolerance 0.5 % on the force, 1 % on the moment:
//     the mesh's discretisation error measured at refinement 1 and 2 is 0.01-0.15 % on the
//     force and 0.4 % on the moment (read from the far field, where elements are coarser).
//  2. Deep saturation (H0 = 3 M_s, 0.3 radii apart): the iron is magnetised at M_s (the
//     Frohlich-Kennelly law leaves it 0.04 % short there), and a uniformly magnetised sphere's
//     outside field is exactly a dipole's, so the force is nearly the dipole force of moments
//     M_s V: within 5 %, the partner's field (about 0.1 M_s against 2.7 M_s inside) tilting the
//     magnetisation by a few per cent (the moment itself is M_s V within 1 %).
//  3. At 70 kA/m, touching (0.001 radii): saturation caps the force far below the linear one and
//     keeps it above the point dipoles', and the gap's flux density has reached the iron's J_s.
//  4. The engine, an isolated iron pair with converged dipoles plus the saturating correction,
//     at a gap and field between the table's nodes: the finite-element force within 3 % (the
//     table's force is bilinear in log gap and log field on a grid 1.5x apart, where the force
//     bends from the linear pair's to the saturated plateau; 1-2.2 % measured at these points).
//  5. The capped dipole pair the correction subtracts is the engine's mutual dipoles: the linear
//     two-dipole force below the cap, the moments M_s V above it.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "magnetic/magnetic_model.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "magnetics/sphere_pair_fem.hpp"
#include "rel_approx.hpp"
#include "test_support.hpp"

using namespace mrjam;
using magnetics::solve_sphere_pair_fem;
using magnetics::SpherePairFemRequest;
using mrjam_test::rel;

namespace {

constexpr double kMs = 1.7e6;

// An iron pair (mu_r 1000, M_s 1.7 MA/m) on the field's axis, gap in radii, converged dipoles
// plus the saturating correction: the force on the upper grain over mu0 H0^2 a^2.
double engine_axial_coefficient(double gap, double h0) {
    const double a = 10e-6;
    Particles p;
    MagneticModel model;
    model.enabled = true;
    model.field = std::make_shared<UniformField>(Vec3{0, 0, kMu0 * h0}, 0.0, 0.0, 1e300);
    model.settings.policy = MutualPolicy::converged;
    model.settings.tolerance = 1e-13;
    model.settings.max_iterations = 1000;
    model.settings.cutoff_scale = 3.0;
    model.settings.close_pairs = {true, ClosePairModel::saturating, 0.0, 1.0};
    model.close_pair_table = ClosePairTable(1000, model.settings.close_pairs, kMs);
    const double beta = 999.0 / 1002.0;
    for (const Vec3& x : {Vec3{}, Vec3{0, 0, (2 + gap) * a}}) {
        const std::size_t i = p.add(x, a, 7800.0, 0);
        p.induced_coefficient[i] = 4 * M_PI * a * a * a * beta;
        p.saturation_moment[i] = kMs * 4.0 / 3.0 * M_PI * a * a * a;
    }
    Domain domain;
    domain.lo = {-1, -1, -1};
    domain.hi = {1, 1, 1};
    model.pairs = NeighborList(NeighborList::Settings{0.0, 3.0, false, 0.0});
    model.pairs.build(p, domain, 1);
    for (auto& f : p.force) f = Vec3{};
    initialise_moments(model, p, 0.0);
    add_magnetic_forces(model, p, 0.0, 1);
    return p.force[1].z / (kMu0 * h0 * h0 * a * a);
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("sphere pair FEM: linear iron reproduces the exact two-sphere force and moment") {
        mrjam_test::TempDir dir("pair_fem_linear");
        for (double gap : {0.1, 0.01, 0.001}) {
            CAPTURE(gap);
            SpherePairFemRequest r;
            r.saturating = false;
            r.applied_field = 1e3;
            r.gap = gap;
            const auto fem = solve_sphere_pair_fem(r, dir.path);
            const auto exact = converged_sphere_pair_response(1000, 2 + gap, PairOrientation::axial);
            CHECK(fem.force_coefficient == rel(2 * M_PI * exact.dpolarisability_ds).epsilon(5e-3));
            CHECK(fem.polarisability == rel(exact.polarisability).epsilon(1e-2));
        }
    }

    TEST_CASE("sphere pair FEM: deep in saturation the pair is two uniformly magnetised spheres") {
        mrjam_test::TempDir dir("pair_fem_saturated");
        SpherePairFemRequest r;
        r.applied_field = 3 * kMs;
        r.gap = 0.3;
        const auto fem = solve_sphere_pair_fem(r, dir.path);
        // m = M_s 4 pi / 3 (a = 1), F = 6 mu0 m^2 / (4 pi s^4), over mu0 H0^2.
        const double m = kMs * 4 * M_PI / 3, s = 2 + r.gap;
        const double uniform = -6 * m * m / (4 * M_PI * std::pow(s, 4)) / (r.applied_field * r.applied_field);
        CHECK(fem.force_coefficient == rel(uniform).epsilon(5e-2));
        CHECK(fem.polarisability == rel(2 * m / (4 * M_PI) / r.applied_field).epsilon(1e-2));
    }

    TEST_CASE("sphere pair FEM: at 70 kA/m saturation caps the touching pair's attraction") {
        mrjam_test::TempDir dir("pair_fem_contact");
        SpherePairFemRequest r;
        r.applied_field = 7e4;
        r.gap = 0.001;
        const auto fem = solve_sphere_pair_fem(r, dir.path);
        const double linear =
            2 * M_PI * converged_sphere_pair_response(1000, 2.001, PairOrientation::axial).dpolarisability_ds;
        const double dipoles =
            2 * M_PI * mutual_dipole_pair_response(1000, 2.001, PairOrientation::axial).dpolarisability_ds;
        CAPTURE(fem.force_coefficient);
        CHECK(fem.force_coefficient > 0.25 * linear);  // less than a quarter of the linear attraction
        CHECK(fem.force_coefficient < 3 * dipoles);    // more than three times the point dipoles'
        CHECK(fem.max_gap_flux_density > kMu0 * kMs);  // the gap's iron faces are past J_s
    }

    TEST_CASE("close pairs, saturating: the engine's isolated pair follows the finite elements between nodes") {
        mrjam_test::TempDir dir("pair_fem_engine");
        for (auto [gap, h0] : {std::pair{0.03, 6e4}, std::pair{0.003, 2.5e5}}) {
            CAPTURE(gap);
            CAPTURE(h0);
            SpherePairFemRequest r;
            r.applied_field = h0;
            r.gap = gap;
            const double fem = solve_sphere_pair_fem(r, dir.path).force_coefficient;
            CHECK(engine_axial_coefficient(gap, h0) == rel(fem).epsilon(3e-2));
        }
    }

    TEST_CASE("close pairs, saturating: the subtracted dipole pair is the engine's capped mutual dipoles") {
        const double s = 2.05;
        const auto linear = mutual_dipole_pair_response(1000, s, PairOrientation::axial);
        const auto low = capped_dipole_pair(1000, s, 1e-3);
        CHECK(low.force == rel(2 * M_PI * linear.dpolarisability_ds).epsilon(1e-12));
        CHECK(low.polarisability == rel(linear.polarisability).epsilon(1e-12));
        // H0 = M_s: a lone sphere saturates at M_s / 3, so each moment is M_s V = 4 pi / 3 in a^3 H0.
        const auto high = capped_dipole_pair(1000, s, 1.0);
        const double m = 4 * M_PI / 3;
        CHECK(high.polarisability == rel(2 * m / (4 * M_PI)).epsilon(1e-12));
        CHECK(high.force == rel(-6 * m * m / (4 * M_PI * std::pow(s, 4))).epsilon(1e-12));
    }
}
