// `mrjam asteroid spinup` (lib/asteroid/body_spin, spinup_spec, spinup_run): a spin-up step is a
// rigid rotation of the body whose rate and angular momentum are the ones given; the protocol's
// steps and holds are section 4.3's; a small rubble pile spun past its rigid-sphere limit
// deforms, its books closing (momentum to round-off with the tree's net force removed).
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

#include "asteroid/body_spin.hpp"
#include "asteroid/cloud.hpp"
#include "asteroid/spin_limits.hpp"
#include "asteroid/spinup_run.hpp"
#include "asteroid/spinup_spec.hpp"
#include "particles.hpp"
#include "rel_approx.hpp"
#include "scene/scene_node.hpp"
#include "test_support.hpp"

using namespace mrjam;
using json = nlohmann::json;
using mrjam_test::rel;

namespace {

json small_pile(long count, const json& protocol) {
    return {{"description", "test pile"},
            {"grains",
             {{"diameter", "1 m"},
              {"material",
               {{"density", "3000 kg/m3"},
                {"youngs_modulus", "1 MPa"},
                {"restitution", 0.1},
                {"friction", 0.4},
                {"surface_energy", "2.86 mJ/m2"}}}}},
            {"cloud", {{"count", count}, {"lattice_spacing", "1.1 m"}, {"thermal_speed", 0.0}}},
            {"spin_up", protocol}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("spin limits: ellipsoid shape constants against the sphere and the oblate spheroid's closed form") {
        for (double A : ellipsoid_shape_constants(5, 5, 5)) CHECK(A == rel(2.0 / 3.0).epsilon(1e-6));
        const auto tri = ellipsoid_shape_constants(3, 2, 1);
        CHECK(tri[0] + tri[1] + tri[2] == rel(2.0).epsilon(1e-6));
        CHECK(tri[0] < tri[1]);  // the longest axis feels the weakest pull per length
        CHECK(tri[1] < tri[2]);
        // Oblate a = b > c, e^2 = 1 - c^2 / a^2: A_c = 2 / e^2 (1 - sqrt(1 - e^2) asin(e) / e).
        const double a = 2, c = 1, e = std::sqrt(1 - c * c / (a * a));
        const double A_c = 2 / (e * e) * (1 - std::sqrt(1 - e * e) * std::asin(e) / e);
        const auto ob = ellipsoid_shape_constants(a, a, c);
        CHECK(ob[2] == rel(A_c).epsilon(1e-6));
        CHECK(ob[0] == rel(0.5 * (2 - A_c)).epsilon(1e-6));
    }

    TEST_CASE("spin limits: Holsapple's sphere, w^2 = (4 pi G rho / 3) 3 s / (1 / sqrt 3 + 2 s), and its inverse") {
        const double rho = 1800, rigid = rigid_sphere_spin_limit(rho);
        CHECK(rigid == rel(709e-6).epsilon(2e-3));  // the source's figure at 1800 kg/m3
        const std::array<double, 3> sphere{10, 10, 10};
        for (double deg : {10.0, 30.0, 45.0, 70.0}) {
            const double sp = std::sin(deg * M_PI / 180), s = 2 * sp / (std::sqrt(3.0) * (3 - sp));
            const double expected = rigid * std::sqrt(3 * s / (1 / std::sqrt(3.0) + 2 * s));
            CHECK(drucker_prager_spin_limit(rho, sphere, deg * M_PI / 180) == rel(expected).epsilon(1e-9));
            CHECK(friction_angle_for_spin(rho, sphere, expected) * 180 / M_PI == rel(deg).epsilon(1e-9));
        }
        CHECK(drucker_prager_spin_limit(rho, sphere, 30 * M_PI / 180) ==
              rel(rigid * std::sqrt(2.0 / 3.0)).epsilon(1e-9));
        CHECK(drucker_prager_spin_limit(rho, sphere, 0.5 * M_PI) == rel(rigid).epsilon(1e-9));  // no shear failure
        CHECK(drucker_prager_spin_limit(rho, sphere, 0) < 1e-6 * rigid);  // a fluid cannot hold a sphere
        CHECK(std::isnan(friction_angle_for_spin(rho, sphere, 1.01 * rigid)));
        // An elongated body fails sooner than the sphere at the same angle (Holsapple's Fig. 3).
        CHECK(drucker_prager_spin_limit(rho, {20, 10, 10}, 30 * M_PI / 180) <
              drucker_prager_spin_limit(rho, sphere, 30 * M_PI / 180));
    }

    TEST_CASE("spin-up step: a rigid rotation of the body at the rate given, its angular momentum I omega") {
        Particles p;
        const auto x = lattice_cloud(300, 1.1, 1.0, 0.0);
        p.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
            p.position[i] = x[i] + Vec3{3.0, -2.0, 1.0};  // off the origin: the rotation is about the body's centre
            p.radius[i] = 0.5;
            p.mass[i] = 3000 * M_PI / 6.0;
            p.inertia[i] = 0.4 * p.mass[i] * 0.25;
        }
        std::vector<std::size_t> all(p.size());
        for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
        const Vec3 added = spin_up_body(p, all, 2e-4);
        const BodySpin spin = body_spin(p, all);
        CHECK(spin.rate == rel(2e-4).epsilon(1e-12));
        CHECK(added.z == rel(2e-4 * spin.i_zz).epsilon(1e-12));
        Vec3 momentum{};
        for (std::size_t i = 0; i < p.size(); ++i) momentum += p.velocity[i] * p.mass[i];
        CHECK(norm(momentum) < 1e-12 * spin.i_zz * 2e-4);
    }

    TEST_CASE("spin-up protocol: 100 urad/s every 500 s to 400 urad/s, then the late hold, to the final spin") {
        const SpinupSpec s = read_spinup_spec(small_pile(100, {{"settle_time", "1000 s"}}), "standard");
        CHECK(s.steps() == 10);
        CHECK(s.target(4) == rel(400e-6));
        CHECK(s.interval(4) == 500.0);
        CHECK(s.interval(5) == 3000.0);
        CHECK(s.body.duration == rel(1000 + 4 * 500 + 6 * 3000));
        CHECK(read_spinup_spec(small_pile(100, {{"settle_time", "1000 s"}}), "quick").interval(5) == 1500.0);
        json bad = small_pile(100, {{"settle_time", "1000 s"}, {"final_spin", "50 urad/s"}});
        CHECK_THROWS_WITH_AS(read_spinup_spec(bad, "quick"), doctest::Contains("/spin_up/final_spin"), SceneError);
        bad = small_pile(100, {{"settle_time", "1000 s"}});
        bad["run"] = {{"duration", "100 s"}};  // the protocol sets the length
        CHECK_THROWS_WITH_AS(read_spinup_spec(bad, "quick"), doctest::Contains("/run/duration"), SceneError);
    }
}

TEST_SUITE("physics") {
    TEST_CASE("spinup: a small cohesive pile keeps its shape below the rigid-sphere limit and deforms past it") {
        mrjam_test::TempDir dir;
        json s = small_pile(300, {{"settle_time", "2500 s"},
                                  {"increment", "300 urad/s"},
                                  {"early_until", "300 urad/s"},
                                  {"early_interval", "300 s"},
                                  {"late_interval", "600 s"},
                                  {"final_spin", "1200 urad/s"}});
        s["output"] = {{"directory", dir.file("out")}};
        CoalesceOptions o;
        o.progress = false;
        o.report_path = dir.file("report.json");
        const CoalesceOutcome out = run_spinup(read_spinup_spec(s, "quick"), o);
        REQUIRE(out.exit_status == 0);
        const json& u = out.report["results"]["spin_up"];
        const double limit = u["rigid_sphere_limit_rad_s"].get<double>();
        // A settled pile of 3000 kg/m3 grains at a packing of about 0.5: 1300-1800 kg/m3, so the
        // rigid sphere's limit sqrt(4 pi G rho / 3) is 610-710 urad/s.
        CHECK(limit > 600e-6);
        CHECK(limit < 720e-6);
        // The steps below the limit leave the shape (no event at 300 or 600 urad/s); by 1200 urad/s,
        // 1.7-2 times the limit, the pile has deformed.
        // Friction alone (atan 0.4 = 21.8 deg, cohesionless) would hold the sphere to less than the rigid limit.
        CHECK(u["drucker_prager"]["limit_at_grain_friction_angle_rad_s"].get<double>() < limit);
        REQUIRE_FALSE(u["first_deformation_rad_s"].is_null());
        CHECK(u["first_deformation_rad_s"].get<double>() > limit);
        const json& last = u["steps"].back();
        CHECK(last["axis_ratio_c_a"].get<double>() < 0.95 * u["steps"][0]["axis_ratio_c_a"].get<double>());
        // Every event carries the body's picture as it left it.
        for (const json& e : u["events"]) {
            REQUIRE(e.contains("picture"));
            CHECK(mrjam_test::slurp(e["picture"].get<std::string>()).find("<circle") != std::string::npos);
        }
        // The tree's net force removed, every force pairwise in sum: momentum to round-off.
        CHECK(u["largest_momentum_drift"].get<double>() < 1e-9);
        // Over the spin steps, held (100 steps) tree forces on a rotating pile: within 1e-3.
        CHECK(u["largest_angular_momentum_drift_spinning"].get<double>() < 1e-3);
        // ... taken over the samples of the spin steps, told by their stage: the settling's last
        // sample (a few steps past its end) measures the cold pile's own near-zero momentum.
        double spinning = 0;
        for (const json& row : u["series"]) {
            REQUIRE(row.contains("stage"));
            if (row["stage"].get<int>() > 0)
                spinning = std::max(spinning, row["conservation"]["angular_momentum_drift"].get<double>());
        }
        CHECK(u["largest_angular_momentum_drift_spinning"].get<double>() == spinning);
    }
}

TEST_SUITE("cli") {
    TEST_CASE(
        "mrjam asteroid coalesce and spinup: Ctrl-C keeps a checkpoint; resumed it ends the run, and only its own mode "
        "reads it") {
        mrjam_test::TempDir dir;
        // 400 grains for 1000 s (67,500 steps): a few seconds of work, interrupted half a second after
        // the output directory appears (the handler is installed before it is made: a SIGINT before
        // that would be lost, as a background job in a script ignores it until the handler is in).
        json c = {{"grains",
                   {{"diameter", "1 m"},
                    {"material", {{"density", "3000 kg/m3"}, {"youngs_modulus", "1 MPa"}, {"friction", 0.4}}}}},
                  {"cloud", {{"count", 400}, {"lattice_spacing", "1.1 m"}, {"thermal_speed", 0.0}}},
                  {"run", {{"duration", "1000 s"}, {"sample_every", "100 s"}}},
                  {"output", {{"directory", dir.file("out")}}}};
        mrjam_test::write_text(dir.file("c.json"), c.dump(2));
        const auto cut =
            mrjam_test::mrjam(dir,
                              "asteroid coalesce " + mrjam_test::quote(dir.file("c.json")) + " --report " +
                                  mrjam_test::quote(dir.file("cut.json")),
                              " & pid=$!; for i in $(seq 400); do [ -d " + mrjam_test::quote(dir.file("out")) +
                                  " ] && break; sleep 0.05; done; sleep 0.5; kill -INT $pid; wait $pid");
        CAPTURE(cut.err);
        REQUIRE(cut.exit_code == 130);
        const std::string checkpoint = dir.file("out/checkpoint.mrjam");
        const json partial = json::parse(mrjam_test::slurp(dir.file("cut.json")));
        CHECK(partial["status"] == "interrupted");
        const auto wrong = mrjam_test::mrjam(dir, "asteroid spinup --resume " + mrjam_test::quote(checkpoint) +
                                                      " --report " + mrjam_test::quote(dir.file("wrong.json")));
        CHECK(wrong.exit_code == 2);
        CHECK(wrong.err.find("--resume") != std::string::npos);
        const auto resumed = mrjam_test::mrjam(dir, "asteroid coalesce --resume " + mrjam_test::quote(checkpoint) +
                                                        " --report " + mrjam_test::quote(dir.file("done.json")));
        CAPTURE(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        const json done = json::parse(mrjam_test::slurp(dir.file("done.json")));
        CHECK(done["status"] == "complete");
        const json& series = done["results"]["coalescence"]["series"];
        // The samples before the cut are kept and the run's last sample is at its end.
        CHECK(series.size() > partial["results"]["coalescence"]["series"].size());
        CHECK(series.back()["time_s"].get<double>() == mrjam_test::rel(1000).epsilon(1e-3));
        json su = c;
        su.erase("run");
        su["spin_up"] = {{"settle_time", "100 s"}};
        su["run"] = {{"duration", "100 s"}};
        const auto refused = mrjam_test::run_mode(dir, "asteroid spinup", "su", su);
        CHECK(refused.exit_code == 2);
        CHECK(refused.err.find("/run/duration") != std::string::npos);
    }
}
