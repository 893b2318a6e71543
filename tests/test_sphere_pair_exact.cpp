// The exact two-sphere solution (lib/engine/magnetic/sphere_pair_exact): the yardstick for the point
// dipoles' error between close grains.
//
//  1. Translation coefficients: an outgoing harmonic about one centre, evaluated directly, equals
//     its re-expansion about the other centre (m = 0 and 1, either side), to round-off.
//  2. Far apart, the exact force tends to the mutual-dipole force, and the difference falls as
//     s^-5: the first term the dipoles miss is the quadrupole each sphere takes up in the other's
//     dipole field gradient (energy ~ (grad H)^2 ~ s^-8 against the dipoles' s^-3).
//  3. The derivative the solver gives (used for the force) equals a finite difference of its
//     polarisability; mu = 1 gives neither moment nor force; the series converges with order.
//  4. Close together, along the field the exact attraction is stronger than the point dipoles'
//     and across it the repulsion weaker (signs the multipoles must have: the field crowds into
//     the gap of an axial pair and is pushed out of a transverse one).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>

#include "magnetic/sphere_pair_exact.hpp"
#include "rel_approx.hpp"

using mrjam_test::rel;
using namespace mrjam;

namespace {

struct Spherical {
    double r, cos_theta;
};
Spherical spherical(double x, double y, double z) {
    const double r = std::sqrt(x * x + y * y + z * z);
    return {r, z / r};
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("sphere pair: translation coefficients re-expand an outgoing harmonic about the other centre") {
        // A field point 0.9 radii from centre i, off the axis; centre j at +-2.5 along z. The series
        // converges like (0.9/2.5)^l, so 80 terms leave less than 1e-30.
        const double x = 0.5, y = -0.3, z = 0.6;
        const Spherical about_i = spherical(x, y, z);
        for (double offset : {2.5, -2.5}) {
            const Spherical about_j = spherical(x, y, z - offset);
            for (int m = 0; m <= 1; ++m) {
                for (int n = std::max(1, m); n <= 5; ++n) {
                    const double direct = std::pow(about_j.r, -(n + 1)) * std::assoc_legendre(n, m, about_j.cos_theta);
                    double series = 0;
                    for (int l = m; l <= 80; ++l)
                        series += translation_coefficient(m, l, n, offset) * std::pow(about_i.r, l) *
                                  std::assoc_legendre(l, m, about_i.cos_theta);
                    CAPTURE(offset);
                    CAPTURE(m);
                    CAPTURE(n);
                    CHECK(series == rel(direct).epsilon(1e-11));
                }
            }
        }
    }

    TEST_CASE("sphere pair: far apart the exact force tends to the mutual-dipole force, the gap closing as s^-5") {
        const double mu = 1000;
        for (PairOrientation orientation : {PairOrientation::axial, PairOrientation::transverse}) {
            double previous_error = 0;
            for (double s : {8.0, 16.0}) {
                const SpherePairResponse exact = converged_sphere_pair_response(mu, s, orientation, 1e-12);
                const SpherePairResponse dipoles = mutual_dipole_pair_response(mu, s, orientation);
                CHECK(exact.polarisability == rel(dipoles.polarisability).epsilon(1e-6));
                const double error = std::abs(exact.dpolarisability_ds / dipoles.dpolarisability_ds - 1.0);
                CHECK(error < 1e-3);
                if (previous_error > 0) {
                    const double exponent = std::log(previous_error / error) / std::log(2.0);
                    CAPTURE(exponent);
                    CHECK(exponent == doctest::Approx(5.0).epsilon(0.1));
                }
                previous_error = error;
            }
        }
    }

    TEST_CASE("sphere pair: the force's derivative, mu = 1, and convergence with order") {
        for (PairOrientation orientation : {PairOrientation::axial, PairOrientation::transverse}) {
            const double s = 2.2, h = 1e-5;
            const SpherePairResponse at = sphere_pair_response(200, s, orientation, 64);
            const double difference = (sphere_pair_response(200, s + h, orientation, 64).polarisability -
                                       sphere_pair_response(200, s - h, orientation, 64).polarisability) /
                                      (2 * h);
            CHECK(at.dpolarisability_ds == rel(difference).epsilon(1e-6));

            const SpherePairResponse vacuum = sphere_pair_response(1.0, s, orientation, 32);
            CHECK(vacuum.polarisability == doctest::Approx(0.0).scale(1.0).epsilon(1e-15));
            CHECK(vacuum.dpolarisability_ds == doctest::Approx(0.0).scale(1.0).epsilon(1e-15));

            // A gap of 0.05 radii: the series settles as the order doubles.
            const SpherePairResponse a = sphere_pair_response(1000, 2.05, orientation, 128);
            const SpherePairResponse b = sphere_pair_response(1000, 2.05, orientation, 256);
            CHECK(a.dpolarisability_ds == rel(b.dpolarisability_ds).epsilon(1e-6));
        }
    }

    TEST_CASE(
        "sphere pair: near contact the exact axial attraction exceeds the dipoles' and the transverse repulsion is "
        "weaker") {
        const double mu = 1000, s = 2.1;
        const SpherePairResponse axial = converged_sphere_pair_response(mu, s, PairOrientation::axial);
        const SpherePairResponse axial_dipoles = mutual_dipole_pair_response(mu, s, PairOrientation::axial);
        const SpherePairResponse across = converged_sphere_pair_response(mu, s, PairOrientation::transverse);
        const SpherePairResponse across_dipoles = mutual_dipole_pair_response(mu, s, PairOrientation::transverse);
        CHECK(axial.dpolarisability_ds < 0);   // attraction
        CHECK(across.dpolarisability_ds > 0);  // repulsion
        const double axial_ratio = axial.dpolarisability_ds / axial_dipoles.dpolarisability_ds;
        const double across_ratio = across.dpolarisability_ds / across_dipoles.dpolarisability_ds;
        if (std::getenv("MRJAM_TEST_VERBOSE"))
            std::printf("sphere pair, mu %.0f, gap 0.1 radii: exact / dipole force %.3f axial, %.3f transverse\n", mu,
                        axial_ratio, across_ratio);
        CHECK(axial_ratio > 1.0);
        CHECK(across_ratio < 1.0);
    }

}  // TEST_SUITE
