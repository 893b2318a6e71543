// Monolayer (2D) cells: the random disc packing (area fraction, no overlaps, one plane), the
// integrator's planar constraint (an out-of-plane force or velocity never moves a grain off its
// plane, spin survives only about the normal, the in-plane motion is untouched), and energy and
// momentum of an elastic gas of discs.
#include <doctest/doctest.h>

#include <cmath>

#include "contact/restitution.hpp"
#include "core/random.hpp"
#include "geometry/disc_packing.hpp"
#include "integrator.hpp"
#include "observers.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"

using mrjam_test::rel;

using namespace mrjam;
using json = nlohmann::json;

TEST_SUITE("unit") {
    TEST_CASE("monolayer: random disc packing reaches the area fraction in one plane without overlaps") {
        const auto sizes =
            SizeDistribution::table({2e-6, 5e-6, 10e-6}, {0.5, 0.35, 0.15}, SizeDistribution::FrequencyBasis::number);
        for (const bool periodic_z : {true, false}) {
            CAPTURE(periodic_z);
            Domain d;
            d.lo = {0, 0, 0};
            d.hi = {120e-6, 10e-6, 100e-6};
            d.periodic = {true, false, periodic_z};
            Rng rng(5);
            const double phi = 0.7;
            const DiscPackingResult r = random_disc_packing(d, 1, sizes, phi, rng);
            REQUIRE(r.discs.size() > 100);
            double area = 0, worst = 0;
            for (std::size_t i = 0; i < r.discs.size(); ++i) {
                const Sphere& a = r.discs[i];
                area += M_PI * a.radius * a.radius;
                CHECK(a.centre.y == 5e-6);
                if (!periodic_z) {
                    CHECK(a.centre.z >= a.radius * (1 - 1e-12));
                    CHECK(a.centre.z <= 100e-6 - a.radius * (1 - 1e-12));
                }
                for (std::size_t j = i + 1; j < r.discs.size(); ++j) {
                    const Sphere& b = r.discs[j];
                    const Vec3 sep = d.separation(a.centre, b.centre);
                    worst = std::max(worst, (a.radius + b.radius - norm(sep)) / std::min(a.radius, b.radius));
                }
            }
            // The last disc drawn rounds the total: within half the largest disc's area of the target.
            const double plane = 120e-6 * 100e-6;
            CHECK(std::abs(area - phi * plane) <= 0.5 * M_PI * 25e-12 + 1e-20);
            CHECK(r.achieved_area_fraction == rel(area / plane).epsilon(1e-12));
            CHECK(worst < 1e-3);  // the default overlap tolerance
        }
        Domain d;
        d.hi = {100e-6, 10e-6, 100e-6};
        d.periodic = {true, false, true};
        Rng rng(1);
        CHECK_THROWS_AS(random_disc_packing(d, 1, sizes, 0.85, rng), std::invalid_argument);
        d.periodic = {true, true, true};
        CHECK_THROWS_AS(random_disc_packing(d, 1, sizes, 0.5, rng), std::invalid_argument);  // periodic normal
    }

}  // TEST_SUITE

TEST_SUITE("physics") {
    TEST_CASE(
        "monolayer: out-of-plane force and velocity never move a grain off its plane; in-plane motion is free fall") {
        // Gravity with a component along the normal y, an initial velocity and spin with out-of-plane
        // parts. The constraint removes v_y and the spin about x and z at the first half kick; the
        // in-plane motion is the exact parabola (velocity Verlet is exact for a constant force) and
        // the spin about y, with no torque, stays.
        const Vec3 g{1.5, -9.81, 2.5}, v0{0.1, 0.5, -0.2}, w0{3, 4, 5};
        const json scene = {
            {"domain", {{"lo", {0, 0, 0}}, {"hi", {"1 mm", "1 mm", "1 mm"}}, {"periodic", "xz"}, {"monolayer", "y"}}},
            {"materials", {{{"name", "steel"}, {"density", "7800 kg/m3"}, {"youngs_modulus", "200 GPa"}}}},
            {"gravity", {g.x, g.y, g.z}},
            {"grains",
             {{{"size", {{"distribution", "single"}, {"diameter", "0.1 mm"}}},
               {"velocity", {v0.x, v0.y, v0.z}},
               {"angular_velocity", {w0.x, w0.y, w0.z}},
               {"placement", {{"method", "list"}, {"positions", {{"0.5 mm", "0.5 mm", "0.5 mm"}}}}}}}},
            {"run", {{"steps", 0}}}};
        Scene sc = build_scene(scene, BuildOptions{});
        choose_timestep(sc);
        System& s = sc.system;
        prepare(s);
        const long steps = 2000;
        advance_steps(s, steps);
        const double t = s.time;
        const Vec3 x = s.particles.position[0], v = s.particles.velocity[0], w = s.particles.angular_velocity[0];
        CHECK(x.y == 0.5e-3);
        CHECK(v.y == 0.0);
        CHECK(w.x == 0.0);
        CHECK(w.z == 0.0);
        CHECK(w.y == w0.y);
        CHECK(x.x == rel(0.5e-3 + v0.x * t + 0.5 * g.x * t * t).epsilon(1e-10));
        CHECK(x.z == rel(0.5e-3 + v0.z * t + 0.5 * g.z * t * t).epsilon(1e-10));
        CHECK(v.x == rel(v0.x + g.x * t).epsilon(1e-10));
        CHECK(v.z == rel(v0.z + g.z * t).epsilon(1e-10));
    }

    TEST_CASE("monolayer: an elastic gas of discs keeps its energy and in-plane momentum, in its plane") {
        // Grains of 0.9-1.1 mm at area fraction 0.5 in a 10 mm square, periodic in x and z, velocity
        // components uniform in +-0.1 m/s, restitution 1, no friction: as the 3D elastic gas of
        // tests/test_conservation.cpp, with its step t_c / 80 (energy drift below 1e-5 there; 1e-4
        // asserted). The out-of-plane velocity is removed at the first half kick, so the reference
        // energy and momentum are taken after the first step.
        const json scene = {
            {"seed", 99},
            {"domain",
             {{"lo", {0, 0, 0}}, {"hi", {"10 mm", "1.1 mm", "10 mm"}}, {"periodic", "xz"}, {"monolayer", "y"}}},
            {"materials",
             {{{"name", "glass"},
               {"density", "2500 kg/m3"},
               {"youngs_modulus", "100 MPa"},
               {"poisson_ratio", 0.3},
               {"restitution", 1},
               {"friction", 0}}}},
            {"grains",
             {{{"size",
                {{"distribution", "table"}, {"diameters", {"0.9 mm", "1 mm", "1.1 mm"}}, {"frequencies", {1, 1, 1}}}},
               {"placement", {{"method", "monolayer"}, {"area_fraction", 0.5}}},
               {"random_velocity", "0.1 m/s"}}}},
            {"run", {{"steps", 0}, {"characteristic_speed", "0.35 m/s"}}}};
        Scene sc = build_scene(scene, BuildOptions{});
        choose_timestep(sc);
        System& s = sc.system;
        std::size_t k = 0;
        for (std::size_t i = 0; i < s.particles.size(); ++i)
            if (s.particles.radius[i] < s.particles.radius[k]) k = i;
        s.dt = hertz_contact_duration(0.5 * s.particles.mass[k], 0.5 * s.particles.radius[k],
                                      s.pairs(0, 0).effective_youngs, 0.35) /
               80;
        REQUIRE(s.particles.size() > 50);
        prepare(s);
        advance(s);
        auto momentum = [&] {
            Vec3 m{};
            for (std::size_t i = 0; i < s.particles.size(); ++i) m += s.particles.velocity[i] * s.particles.mass[i];
            return m;
        };
        double scale = 0;
        for (std::size_t i = 0; i < s.particles.size(); ++i)
            scale += s.particles.mass[i] * norm(s.particles.velocity[i]);
        const double e0 = energy(s).total();
        const Vec3 p0 = momentum();
        std::size_t contacts = 0;
        double drift = 0;
        for (long n = 1; n <= 30000; ++n) {
            advance(s);
            contacts = std::max(contacts, s.contact_stats.contacts);
            if (n % 500 == 0) drift = std::max(drift, std::abs(energy(s).total() - e0) / e0);
        }
        const Vec3 p1 = momentum();
        MESSAGE(s.particles.size() << " discs, largest relative energy drift " << drift << ", up to " << contacts
                                   << " contacts");
        CHECK(contacts > 3);
        CHECK(drift < 1e-4);
        CHECK(norm(p1 - p0) < 1e-12 * scale);
        for (std::size_t i = 0; i < s.particles.size(); ++i) {
            CHECK(s.particles.position[i].y == 0.55e-3);
            CHECK(s.particles.velocity[i].y == 0.0);
        }
    }

}  // TEST_SUITE
