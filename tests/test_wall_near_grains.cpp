// Each wall tests only the grains found near it at the last neighbour rebuild (Wall::near). That
// is a speed-up only: a run must be bit for bit the run that tests every grain against every wall
// every step. Grains thrown about inside a cylinder, on a floor, under a moving lid (which is
// always tested against every grain).
#include <doctest/doctest.h>

#include <algorithm>

#include "integrator.hpp"
#include "scene/scene.hpp"
#include "test_support.hpp"

namespace {

mrjam::json tumbler_scene() {
    return {
        {"seed", 11},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {0.006, 0.006, 0.008}}}},
        {"materials", mrjam::json::array({mrjam_test::soft_rolling_glass()})},
        {"contact", {{"rolling", "epsd"}}},
        {"gravity", {0, 0, -9.81}},
        {"walls",
         {{{"name", "drum"}, {"type", "cylinder"}, {"point", {0.003, 0.003, 0}}, {"radius", 0.0028}},
          {{"name", "floor"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
          {{"name", "lid"},
           {"type", "plane"},
           {"point", {0, 0, 0.0075}},
           {"normal", {0, 0, -1}},
           {"velocity", {0, 0, -0.02}}}}},
        {"grains",
         {{{"size", {{"distribution", "single"}, {"diameter", 0.0005}}},
           {"placement",
            {{"method", "random"},
             {"volume_fraction", 0.3},
             {"region", {{"lo", {0.0012, 0.0012, 0.0005}}, {"hi", {0.0048, 0.0048, 0.007}}}}}},
           {"random_velocity", 0.2}}}},
        {"run", {{"steps", 1}}},
    };
}

bool same_bits(const std::vector<mrjam::Vec3>& a, const std::vector<mrjam::Vec3>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].z != b[i].z) return false;
    return true;
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("walls: testing only the grains near each wall changes no bit of a run") {
        mrjam::Scene scene = mrjam::build_scene(tumbler_scene(), mrjam::BuildOptions{});
        mrjam::choose_timestep(scene);
        mrjam::prepare(scene.system);
        for (const int threads : {1, 2}) {
            CAPTURE(threads);
            mrjam::System near = scene.system, every = scene.system;
            near.threads = every.threads = threads;
            const std::size_t n = near.particles.size();
            REQUIRE(n > 200);
            double drum_force = 0;
            std::size_t most_near = 0;
            const long builds_at_start = near.contacts.builds();
            for (int step = 0; step < 4000; ++step) {
                for (mrjam::Wall& w : every.walls) w.near.valid = false;  // every grain, every wall, every step
                mrjam::advance(every);
                mrjam::advance(near);
                REQUIRE(near.walls[0].near_grains_hold(n));
                CHECK_FALSE(near.walls[2].near_grains_hold(n));  // the lid moves
                most_near = std::max(most_near, near.walls[0].near.index.size());
                drum_force = std::max(drum_force, norm(near.walls[0].force));
            }
            // The test means something: the lists were rebuilt, the drum was hit, and its near grains
            // were a minority of all.
            CHECK(near.contacts.builds() > builds_at_start + 10);
            CHECK(drum_force > 0);
            CHECK(most_near < n / 2);
            MESSAGE(n << " grains, at most " << most_near << " near the drum, "
                      << near.contacts.builds() - builds_at_start << " rebuilds");
            CHECK(same_bits(near.particles.position, every.particles.position));
            CHECK(same_bits(near.particles.velocity, every.particles.velocity));
            CHECK(same_bits(near.particles.angular_velocity, every.particles.angular_velocity));
            for (std::size_t w = 0; w < near.walls.size(); ++w) {
                CAPTURE(w);
                std::vector<mrjam::Vec3> a, b;
                for (const auto& h : near.walls[w].history) a.push_back(h.tangential);
                for (const auto& h : every.walls[w].history) b.push_back(h.tangential);
                CHECK(same_bits(a, b));
            }
        }
    }
}
