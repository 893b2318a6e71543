// `mrjam asteroid coalesce` (lib/asteroid/cloud, body_diagnostics, coalesce_*): the lattice cloud
// and its motion against what they are built to be (sites nearest the origin, a centre of mass at
// rest, the rigid spin's angular momentum, Maxwell speeds), the binding energy of a uniform sphere,
// the equivalent ellipsoid of a lattice ellipsoid, a cold cloud collapsing into one body with its
// momentum and angular momentum conserved, and the refusals of a cloud that cannot collapse.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "asteroid/body_diagnostics.hpp"
#include "asteroid/cloud.hpp"
#include "asteroid/coalesce_run.hpp"
#include "asteroid/coalesce_spec.hpp"
#include "gravity/self_gravity.hpp"
#include "particles.hpp"
#include "rel_approx.hpp"
#include "scene/scene_node.hpp"
#include "test_support.hpp"

using namespace mrjam;
using json = nlohmann::json;
using mrjam_test::rel;

namespace {

// Equal grains (radius r, density rho) at the given centres, at rest.
Particles grains_at(const std::vector<Vec3>& x, double r, double rho) {
    Particles p;
    p.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        p.position[i] = x[i];
        p.radius[i] = r;
        p.mass[i] = rho * 4.0 / 3.0 * M_PI * r * r * r;
        p.inertia[i] = 0.4 * p.mass[i] * r * r;
    }
    return p;
}

// A small coalescence scene: 1 m grains 1.05 m apart (a free-fall time of about 1,800 s).
json small_cloud(long count, double magnetisation, double duration_s) {
    return {{"description", "test cloud"},
            {"grains",
             {{"diameter", "1 m"},
              {"material",
               {{"density", "3000 kg/m3"},
                {"youngs_modulus", "1 MPa"},
                {"restitution", 0.1},
                {"friction", 0.4},
                {"magnetisation", magnetisation}}}}},
            {"cloud", {{"count", count}, {"lattice_spacing", "1.05 m"}, {"thermal_speed", 0.0}}},
            {"run", {{"duration", duration_s}, {"sample_every", duration_s / 10}}}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("coalesce cloud: the lattice sites nearest the origin, clear of the seed grain") {
        const auto x = lattice_cloud(500, 2.0, 1.0, 0.0);
        REQUIRE(x.size() == 500);
        double r_max = 0;
        for (const Vec3& v : x) r_max = std::max(r_max, norm(v));
        // Every site of the full cube within r_max - spacing must be in the set (nearest first).
        long inside = 0;
        for (int i = -10; i <= 10; ++i)
            for (int j = -10; j <= 10; ++j)
                for (int k = -10; k <= 10; ++k)
                    if (2.0 * std::sqrt(double(i * i + j * j + k * k)) < r_max - 1e-9) ++inside;
        long counted = 0;
        for (const Vec3& v : x) counted += norm(v) < r_max - 1e-9;
        CHECK(counted == inside);
        const auto seeded = lattice_cloud(500, 2.0, 1.0, 3.0);  // a 6 m seed: sites within 3.5 m left out
        for (const Vec3& v : seeded) CHECK(norm(v) >= 3.5);
        const auto again = lattice_cloud(500, 2.0, 1.0, 3.0);  // deterministic
        REQUIRE(again.size() == seeded.size());
        for (std::size_t i = 0; i < again.size(); ++i) CHECK(norm(again[i] - seeded[i]) == 0.0);
    }

    TEST_CASE("coalesce cloud: thermal motion at rest on average, the spin's angular momentum, Maxwell spread") {
        Particles p = grains_at(lattice_cloud(4000, 2.0, 1.0, 0.0), 0.5, 3000);
        const std::vector<char> thermal(p.size(), 1);
        const double sigma = 1e-3, omega = 5e-5;
        give_cloud_motion(p, thermal, sigma, omega, 7);
        Vec3 momentum{}, angular{};
        double mass = 0, sum2 = 0, i_zz = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            momentum += p.velocity[i] * p.mass[i];
            mass += p.mass[i];
            const Vec3 spin_part = cross(Vec3{0, 0, omega}, p.position[i]);
            sum2 += norm2(p.velocity[i] - spin_part);
            angular += cross(p.position[i], p.velocity[i]) * p.mass[i];
            i_zz += p.mass[i] * (p.position[i].x * p.position[i].x + p.position[i].y * p.position[i].y);
        }
        CHECK(norm(momentum) / (mass * sigma) < 1e-12);
        // 12,000 normal deviates: their spread is sigma within 3 % (the standard error is 0.65 %).
        CHECK(std::sqrt(sum2 / (3.0 * p.size())) == rel(sigma).epsilon(0.03));
        // The thermal part's angular momentum is a random walk of 4,000 terms, under 5 % of the spin's here.
        CHECK(angular.z == rel(i_zz * omega).epsilon(0.05));
    }

    TEST_CASE("coalesce cloud: binding energy of a uniform lattice sphere is 3 G M^2 / (5 R)") {
        const auto x = lattice_cloud(4000, 2.0, 1.0, 0.0);
        const Particles p = grains_at(x, 0.5, 3000);
        const CloudEnergetics e = cloud_energetics(p, 0.0, kNewtonG);
        // The lattice's own sphere has the volume of 4,000 cells: R = (3 N / 4 pi)^(1/3) a. The
        // discreteness (the surface's staircase, the pair sum's self-exclusion) is under 2 %.
        const double R = std::cbrt(3.0 * 4000 / (4.0 * M_PI)) * 2.0;
        CHECK(e.binding == rel(0.6 * kNewtonG * e.mass * e.mass / R).epsilon(0.02));
        CHECK(e.kinetic == 0.0);
        CHECK(e.virial_ratio == 0.0);
        const double rho = e.mass / (4.0 / 3.0 * M_PI * std::pow(e.radius, 3));
        CHECK(e.free_fall_time == rel(std::sqrt(3 * M_PI / (32 * kNewtonG * rho))).epsilon(1e-12));
    }

    TEST_CASE("coalesce body: the equivalent ellipsoid of grains filling an ellipsoid is that ellipsoid") {
        const double a = 12, b = 8, c = 5, h = 0.25;
        std::vector<Vec3> x;
        for (double i = -a; i <= a; i += h)
            for (double j = -b; j <= b; j += h)
                for (double k = -c; k <= c; k += h)
                    if ((i * i) / (a * a) + (j * j) / (b * b) + (k * k) / (c * c) <= 1.0) x.push_back({k, i, j});
        const Particles p = grains_at(x, 1e-3, 1000);  // point-like grains: no self term to speak of
        std::vector<std::size_t> all(p.size());
        for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
        Vec3 centre;
        double axes[3];
        equivalent_ellipsoid(p, all, centre, axes);
        // The staircase surface of a grid of step h: the axes within h / 2 of the true ones.
        CHECK(std::fabs(axes[0] - a) < 0.5 * h);
        CHECK(std::fabs(axes[1] - b) < 0.5 * h);
        CHECK(std::fabs(axes[2] - c) < 0.5 * h);
        CHECK(norm(centre) < 1e-9);
    }

    TEST_CASE("coalesce scene: the source's temperature rule, an unbound cloud, a hold and an escape radius refused") {
        // sigma = sqrt(k_B 8e20 d^3 / m) = 2.65 mm/s at 3000 kg/m3 for any d (section 4.2's cloud).
        CHECK(thermal_speed_from_temperature(3000) == rel(2.6518e-3).epsilon(1e-3));
        json s = small_cloud(300, 0, 100);
        s["cloud"]["escape_radius"] = 1.0;
        CHECK_THROWS_WITH_AS(read_coalesce_spec(s, "quick"), doctest::Contains("/cloud/escape_radius"), SceneError);
        s = small_cloud(300, 0, 100);
        s["grains"]["material"]["magnetisation"] = "2 MA/m";
        CHECK_THROWS_WITH_AS(read_coalesce_spec(s, "quick"), doctest::Contains("/grains/material/magnetisation"),
                             SceneError);
    }
}

TEST_SUITE("physics") {
    TEST_CASE("coalesce: a cold cloud gathers into one body, conserving momentum and angular momentum") {
        mrjam_test::TempDir dir;
        json s = small_cloud(300, 0, 2700);          // 1.5 free-fall times
        s["cloud"]["spin"] = "20 urad/s";            // a tenth of the edge's orbital rate
        s["self_gravity"] = {{"method", "direct"}};  // pairwise forces: the conservation laws exact
        s["output"] = {{"directory", dir.file("out")}};
        CoalesceOptions o;
        o.progress = false;
        o.report_path = dir.file("report.json");
        const CoalesceOutcome out = run_coalescence(read_coalesce_spec(s, "quick"), o);
        REQUIRE(out.exit_status == 0);
        const json& c = out.report["results"]["coalescence"];
        // Cold, slowly spinning, contacts dissipating: by 1.5 t_ff most of the mass is one body.
        CHECK(c["final"]["body_mass_fraction"].get<double>() > 0.8);
        // Contacts and direct gravity (held 100 steps) are pairwise, and the escaped grains' share
        // is counted: the momentum is conserved to round-off. The angular momentum within 1e-3:
        // forces held while the grains move are no longer exactly central.
        CHECK(c["largest_momentum_drift"].get<double>() < 1e-9);
        CHECK(c["largest_angular_momentum_drift"].get<double>() < 1e-3);
        // The final body drawn in two views: one disc per body grain in each.
        const std::string svg = mrjam_test::slurp(out.report["plots"]["final_body"].get<std::string>());
        std::size_t circles = 0;
        for (std::size_t at = svg.find("<circle"); at != std::string::npos; at = svg.find("<circle", at + 1)) ++circles;
        CHECK(circles % 2 == 0);
        CHECK(circles >= 2 * 0.8 * 300);
        CHECK(circles <= 2 * 300);
    }
}

TEST_SUITE("cli") {
    TEST_CASE("mrjam asteroid coalesce: an unbound cloud is refused by key, exit 2; allow_unbound runs it") {
        mrjam_test::TempDir dir;
        json s = small_cloud(200, 0, 30);
        s["cloud"]["thermal_speed"] = "5 cm/s";
        s["output"] = {{"directory", dir.file("out")}};
        auto r = mrjam_test::run_mode(dir, "asteroid coalesce", "unbound", s);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("/cloud/thermal_speed") != std::string::npos);
        CHECK(r.err.find("unbound") != std::string::npos);
        s["cloud"]["allow_unbound"] = true;
        r = mrjam_test::run_mode(dir, "asteroid coalesce", "unbound_allowed", s);
        CHECK(r.exit_code == 0);
        const json report = json::parse(mrjam_test::slurp(dir.file("unbound_allowed_report.json")));
        CHECK(report["cloud"]["kinetic_over_binding"].get<double>() > 1.0);
        s["self_gravity"] = {{"update_interval", 100000}};
        r = mrjam_test::run_mode(dir, "asteroid coalesce", "held", s);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("/self_gravity/update_interval") != std::string::npos);
    }
}
