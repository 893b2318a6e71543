// `mrjam asteroid scaling`: each force law against its definition computed another way (the
// masses and moments themselves, the engine's dipole pair force and mutual-dipole solver), the
// crossovers against bisection, the source's printed equivalences, and the reader's refusals.
#include <doctest/doctest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "asteroid/force_scaling.hpp"
#include "asteroid/scaling_spec.hpp"
#include "asteroid/scaling_study.hpp"
#include "magnetic/magnetic_model.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "rel_approx.hpp"
#include "scene/scene_node.hpp"
#include "test_support.hpp"

using mrjam_test::rel;
using namespace mrjam;
using json = nlohmann::json;

namespace {

json fig_4_15_scene() {
    return {{"material", {{"density", "7750 kg/m3"}}},
            {"radius", {{"min", "1 um"}, {"max", "1 km"}, {"points_per_decade", 4}}},
            {"magnetism", {{"flux_densities", {"5e-7 T", "5e-4 T", "5e-3 T"}}}},
            {"surface_gravities", {"1e-4 m/s2", "0.144 m/s2"}},
            {"cleanliness", {1, 0.1}}};
}

// The force of grain j's moment on grain i's, both along z, i at `offset` (m) from j.
Vec3 engine_dipole_force(const Vec3& mi, const Vec3& mj, const Vec3& d) {
    const double r2 = dot(d, d), r = std::sqrt(r2);
    return dipole_pair_force(mi, mj, d, 1 / r2, 1 / (4 * M_PI * r2 * r), dot(mi, d), dot(mj, d));
}

std::string refusal_path(const json& scene) {
    try {
        read_scaling_spec(scene);
    } catch (const SceneError& e) {
        return e.path();
    }
    return "accepted";
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("asteroid scaling: self-gravity of two touching spheres is G m^2 / (2R)^2; the printed one a quarter") {
        const double rho = 3000, R = 0.25;
        const double m = rho * 4.0 / 3.0 * M_PI * R * R * R;
        const double newton = kGravitationalConstant * m * m / (4 * R * R);
        CHECK(self_gravity_force(rho, SelfGravityFormula::two_spheres).at(R) == rel(newton).epsilon(1e-12));
        CHECK(self_gravity_force(rho, SelfGravityFormula::printed).at(R) == rel(newton / 4).epsilon(1e-12));
        CHECK(surface_gravity_force(rho, 0.144).at(R) == rel(m * 0.144).epsilon(1e-12));
        CHECK(cohesion_force(0.1).at(2.0) == rel(3.6e-2 * 0.01 * 2.0).epsilon(1e-12));
    }

    TEST_CASE("asteroid scaling: the pair laws equal the engine's dipole force, head-to-tail and side by side") {
        const SoftMagneticGrain iron;
        const double R = 0.01, B = 5e-3;
        const double M = equivalent_magnetisation(iron, B), m = M * 4.0 / 3.0 * M_PI * R * R * R;
        // Head to tail: attraction along the line of centres.
        const Vec3 f = engine_dipole_force({0, 0, m}, {0, 0, m}, {0, 0, 2 * R});
        CHECK(f.x == doctest::Approx(0));
        CHECK(-f.z == rel(dipole_pair_force(M).at(R)).epsilon(1e-12));
        CHECK(-f.z == rel(induced_pair_force(iron, B, InducedPairModel::fixed_dipoles, 0.01).at(R)).epsilon(1e-12));
        // Side by side: repulsion, half the head-to-tail attraction (3 mu0 m^2 / (4 pi r^4)).
        const Vec3 g = engine_dipole_force({0, 0, m}, {0, 0, m}, {2 * R, 0, 0});
        CHECK(g.x == rel(3 * kMu0 * m * m / (4 * M_PI * std::pow(2 * R, 4))).epsilon(1e-12));
        CHECK(g.x == rel(-0.5 * f.z).epsilon(1e-12));
    }

    TEST_CASE("asteroid scaling: mutual dipoles match the engine's converged pair; the exact pair exceeds both") {
        const SoftMagneticGrain iron;
        const double B = 5e-4, H0 = B / kMu0, R = 0.3;
        const SpherePairResponse pair =
            mutual_dipole_pair_response(iron.relative_permeability, 2.0, PairOrientation::axial);
        const double engine = -2 * M_PI * kMu0 * H0 * H0 * R * R * pair.dpolarisability_ds;
        const double mutual = induced_pair_force(iron, B, InducedPairModel::mutual_dipoles, 0.01).at(R);
        CHECK(mutual == rel(engine).epsilon(1e-12));
        // Converging the moments raises the pull by 1 / (1 - beta/4)^2 (1.78 for iron).
        const double fixed = induced_pair_force(iron, B, InducedPairModel::fixed_dipoles, 0.01).at(R);
        CHECK(mutual / fixed == rel(1 / std::pow(1 - iron.beta() / 4, 2)).epsilon(1e-12));
        const double exact = induced_pair_force(iron, B, InducedPairModel::exact_pair, 0.01).at(R);
        CHECK(exact > 10 * mutual);  // 0.01 radii apart, iron: 14 times the dipoles (docs/magnetic_forces.md)
    }

    TEST_CASE("asteroid scaling: the source's equivalent magnetisations; saturation caps the dipoles") {
        const SoftMagneticGrain iron;
        // Section 4.5: 5e-7 ... 5e-3 T give 1.19 ... 11900 A/m (three printed digits).
        CHECK(equivalent_magnetisation(iron, 5e-4) == rel(1190).epsilon(5e-4));
        CHECK(equivalent_magnetisation(iron, 5e-7) == rel(1.19).epsilon(5e-3));
        const PairMagnetisation sat = induced_pair_magnetisation(iron, 2.0, InducedPairModel::mutual_dipoles);
        CHECK(sat.saturated);
        CHECK(sat.magnetisation == rel(iron.saturation_magnetisation));
        CHECK_FALSE(induced_pair_magnetisation(iron, 5e-3, InducedPairModel::mutual_dipoles).saturated);
    }

    TEST_CASE("asteroid scaling: crossovers agree with bisection on the forces to 1e-9") {
        const PowerLaw laws[] = {cohesion_force(0.1), dipole_pair_force(1190), surface_gravity_force(7750, 1e-4),
                                 self_gravity_force(7750, SelfGravityFormula::two_spheres)};
        for (const PowerLaw& a : laws)
            for (const PowerLaw& b : laws) {
                if (a.exponent >= b.exponent) continue;
                double lo = 1e-12, hi = 1e9;  // a - b changes sign once: b grows faster
                for (int k = 0; k < 200; ++k) {
                    const double mid = std::sqrt(lo * hi);
                    (a.at(mid) > b.at(mid) ? lo : hi) = mid;
                }
                CHECK(crossover_radius(a, b) == rel(std::sqrt(lo * hi)).epsilon(1e-9));
            }
        CHECK(std::isnan(crossover_radius(cohesion_force(1), cohesion_force(0.1))));
    }

    TEST_CASE("asteroid scaling: magnetism's band lies between its crossings; none when cohesion always wins") {
        const PowerLaw coh = cohesion_force(0.1), weight = surface_gravity_force(7750, 1e-4),
                       self = self_gravity_force(7750, SelfGravityFormula::two_spheres);
        const auto band = magnetic_dominance(dipole_pair_force(1190), coh, weight, self);
        REQUIRE(band);
        const double mid = std::sqrt(band->from * band->to);
        CHECK(dipole_pair_force(1190).at(mid) > coh.at(mid));
        CHECK(dipole_pair_force(1190).at(mid) > weight.at(mid));
        CHECK(dipole_pair_force(1190).at(band->from * 0.9) < coh.at(band->from * 0.9));
        CHECK(dipole_pair_force(1190).at(band->to * 1.1) < weight.at(band->to * 1.1));
        CHECK_FALSE(magnetic_dominance(dipole_pair_force(1.19), coh, weight, self));
    }

    TEST_CASE("asteroid scaling: the avalanche claim's ratios fall as 1/R, so 10x at 5 mm means 1x at 5 cm") {
        const ScalingSpec spec = read_scaling_spec(fig_4_15_scene());
        const auto claims = evaluate_section_4_5_claims(spec);
        REQUIRE(claims.size() == 4);
        const json& f = claims[3].figures;
        CHECK(f[0]["magnetic_over_weight"].get<double>() / f[2]["magnetic_over_weight"].get<double>() ==
              rel(10).epsilon(1e-12));
    }
}

TEST_SUITE("unit") {
    TEST_CASE("asteroid scaling scene: bad input is refused at its key") {
        CHECK(refusal_path(fig_4_15_scene()) == "accepted");
        json s = fig_4_15_scene();
        s["material"].erase("density");
        CHECK(refusal_path(s) == "/material/density");
        s = fig_4_15_scene();
        s["magnetism"] = {{"magnetisations", {"1190 A/m", "2e6 A/m"}}};
        CHECK(refusal_path(s) == "/magnetism/magnetisations/1");
        s["magnetism"] = json::object();
        CHECK(refusal_path(s) == "/magnetism/flux_densities");
        s = fig_4_15_scene();
        s["radius"]["max"] = "1 nm";
        CHECK(refusal_path(s) == "/radius/max");
        s = fig_4_15_scene();
        s["radius"] = {{"min", "1e-12 m"}, {"max", "1e7 m"}, {"points_per_decade", 1000}};  // 19,001 radii
        CHECK(refusal_path(s) == "/radius/points_per_decade");
        s = fig_4_15_scene();
        s["magnetism"]["exact_pair_gap"] = 0;
        CHECK(refusal_path(s) == "/magnetism/exact_pair_gap");
        s = fig_4_15_scene();
        s["cleanliness"] = {0};
        CHECK(refusal_path(s) == "/cleanliness/0");
        s = fig_4_15_scene();
        s["self_gravity"] = "eq_4_14";
        CHECK(refusal_path(s) == "/self_gravity");
        s = fig_4_15_scene();
        s["surprise"] = 1;
        CHECK(refusal_path(s) == "/surprise");
    }

    TEST_CASE("asteroid scaling scene: the radius grid covers the range at the asked density") {
        const ScalingSpec spec = read_scaling_spec(fig_4_15_scene());
        const auto r = spec.radii();
        REQUIRE(r.size() == 37);  // 9 decades x 4 + 1
        CHECK(r.front() == rel(1e-6));
        CHECK(r.back() == rel(1e3));
        CHECK(r[4] == rel(1e-5).epsilon(1e-12));
    }
}

#ifdef MRJAM_BINARY
TEST_SUITE("cli") {
    TEST_CASE("mrjam asteroid scaling: the report, the plot, and bad input with exit 2") {
        mrjam_test::TempDir dir("mrjam_asteroid");
        const auto ok = mrjam_test::run_mode(dir, "asteroid scaling", "fig", fig_4_15_scene());
        CAPTURE(ok.err);
        REQUIRE(ok.exit_code == 0);
        const json report = json::parse(mrjam_test::slurp(dir.file("fig_report.json")));
        CHECK(report["results"]["claims"].size() == 4);
        CHECK(report["results"]["crossovers"].size() == 3 * 2 * 2);
        CHECK(report["inputs"]["magnetism"]["dominance_model"] == "mutual_dipoles");  // the default, echoed
        CHECK(mrjam_test::slurp(dir.file("fig_report_forces.svg")).find("grain radius R (m)") != std::string::npos);
        json bad = fig_4_15_scene();
        bad["material"]["density"] = "7750 kg";
        mrjam_test::expect_mode_refused(dir, "asteroid scaling", "bad", bad, "/material/density");
        const auto unknown = mrjam_test::mrjam(dir, "asteroid coalesce " + mrjam_test::quote(dir.file("fig.json")));
        CHECK(unknown.exit_code == 2);
    }
}
#endif
