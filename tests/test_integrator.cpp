// The fused integrator pass must not change a run: advance_steps(n) gives the same bits as n
// calls to advance(), so results do not depend on how the runner groups steps.
#include <doctest/doctest.h>

#include <cstring>

#include "integrator.hpp"
#include "scene/scene.hpp"
#include "test_support.hpp"

namespace {

mrjam::json dense_gas_scene() {
    return {
        {"seed", 11},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {0.012, 0.012, 0.012}}, {"periodic", "xy"}}},
        {"materials", mrjam::json::array({mrjam_test::soft_rolling_glass()})},
        {"contact", {{"rolling", "epsd"}}},
        {"gravity", {0, 0, -9.81}},
        {"walls",
         {{{"name", "floor"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
          {{"name", "lid"}, {"type", "plane"}, {"point", {0, 0, 0.012}}, {"normal", {0, 0, -1}}}}},
        {"grains",
         {{{"size", {{"distribution", "lognormal"}, {"median_diameter", 0.001}, {"sigma_ln", 0.2}}},
           {"placement", {{"method", "random"}, {"volume_fraction", 0.4}}},
           {"random_velocity", 0.2}}}},
        {"run", {{"steps", 1}}},
    };
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("integrator: fused steps are bit-identical to single steps") {
        for (int threads : {1, 2}) {
            CAPTURE(threads);
            mrjam::BuildOptions options;
            options.threads = threads;
            mrjam::Scene a = mrjam::build_scene(dense_gas_scene(), options);
            mrjam::choose_timestep(a);
            mrjam::prepare(a.system);
            mrjam::System b = a.system;  // same state, stepped differently below
            mrjam::advance_steps(a.system, 300);
            for (int k = 0; k < 300; ++k) mrjam::advance(b);
            REQUIRE(a.system.particles.size() == b.particles.size());
            REQUIRE(a.system.contact_stats.contacts > 0);  // the scene really exercises contacts
            const auto bytes = a.system.particles.size() * sizeof(mrjam::Vec3);
            CHECK(std::memcmp(a.system.particles.position.data(), b.particles.position.data(), bytes) == 0);
            CHECK(std::memcmp(a.system.particles.velocity.data(), b.particles.velocity.data(), bytes) == 0);
            CHECK(std::memcmp(a.system.particles.angular_velocity.data(), b.particles.angular_velocity.data(), bytes) ==
                  0);
            CHECK(a.system.step == b.step);
        }
    }
}
