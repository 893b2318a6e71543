// Taking grains out of a running system (lib/engine/grain_removal.hpp) must leave the rest of the run
// as if those grains had never been there: two piles far apart, one removed mid-run, against a
// run of the other pile alone, bit for bit (contact and wall histories, lists, order).
#include <doctest/doctest.h>

#include <cstring>

#include "grain_removal.hpp"
#include "integrator.hpp"
#include "scene/scene.hpp"
#include "test_support.hpp"

namespace {

// A pile of 1 mm frictional, rolling-resisting grains in a region, falling onto the floor.
mrjam::json pile(double x_lo, double x_hi) {
    return {{"size", {{"distribution", "single"}, {"diameter", 0.001}}},
            {"placement",
             {{"method", "random"},
              {"volume_fraction", 0.35},
              {"region", {{"lo", {x_lo, 0, 0}}, {"hi", {x_hi, 0.006, 0.008}}}}}},
            {"random_velocity", 0.05}};
}

// Both piles, or only the first: the box, walls and grid are the same either way.
mrjam::json two_piles_scene(bool with_second) {
    // The kept pile is listed first (it draws the same random numbers in both scenes) but lies at
    // the larger x, so the spatial sort puts the removed pile's grains first and the removal
    // renumbers every kept grain.
    mrjam::json grains = mrjam::json::array({pile(0.010, 0.018)});
    if (with_second) grains.push_back(pile(0, 0.004));
    return {
        {"seed", 5},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {0.018, 0.006, 0.008}}, {"periodic", "y"}}},
        {"materials", mrjam::json::array({mrjam_test::soft_rolling_glass()})},
        {"contact", {{"rolling", "epsd"}}},
        {"gravity", {0, 0, -9.81}},
        {"walls",
         {{{"name", "floor"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
          {{"name", "left"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {1, 0, 0}}},
          {{"name", "right"}, {"type", "plane"}, {"point", {0.018, 0, 0}}, {"normal", {-1, 0, 0}}}}},
        {"grains", grains},
        {"run", {{"steps", 1}}},
    };
}

mrjam::System start(bool with_second) {
    mrjam::Scene scene = mrjam::build_scene(two_piles_scene(with_second), mrjam::BuildOptions{});
    mrjam::choose_timestep(scene);
    mrjam::prepare(scene.system);
    return scene.system;
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("grain removal: the remaining grains run on as if the removed ones had never been there") {
        mrjam::System both = start(true), alone = start(false);
        REQUIRE(both.particles.size() > alone.particles.size());
        alone.dt = both.dt;  // the time step follows the grains' speeds; keep the one both runs share
        // The second pile is held still (a raft at rest): a moving one would trigger neighbour-list
        // rebuilds the lone pile does not have, and a rebuild at another step lists other pairs and
        // sums the forces in another order, a round-off difference the piles' collisions amplify.
        both.rafts.push_back({"held", {}, {}, 0});
        for (std::size_t i = 0; i < both.particles.size(); ++i)
            if (both.particles.position[i].x < 0.007) {
                both.particles.raft[i] = 0;
                both.particles.velocity[i] = both.particles.angular_velocity[i] = mrjam::Vec3{};
                ++both.rafts[0].members;
            }
        mrjam::advance_steps(both, 2000);
        mrjam::advance_steps(alone, 2000);
        // The second pile goes; the first keeps its contacts (with their tangential springs and
        // rolling histories), its wall contacts and its place in the lists.
        std::vector<char> remove(both.particles.size(), 0);
        for (std::size_t i = 0; i < remove.size(); ++i) remove[i] = both.particles.position[i].x < 0.007;
        const std::size_t pairs_before = both.contacts.pair_count();
        {  // the comparison is fair: up to here the first pile ran the same in both systems
            std::size_t k = 0;
            bool same = true;
            for (std::size_t i = 0; i < remove.size(); ++i)
                if (!remove[i])
                    same = same && std::memcmp(&both.particles.position[i], &alone.particles.position[k++],
                                               sizeof(mrjam::Vec3)) == 0;
            REQUIRE(same);
        }
        CHECK(mrjam::remove_grains(both, remove) == remove.size() - alone.particles.size());
        REQUIRE(both.particles.size() == alone.particles.size());
        CHECK(both.contacts.pair_count() < pairs_before);
        CHECK(both.contacts.pair_count() == alone.contacts.pair_count());
        CHECK(both.rafts[0].members == 0);
        mrjam::advance_steps(both, 3000);
        mrjam::advance_steps(alone, 3000);
        REQUIRE(alone.contact_stats.contacts > 20);  // the pile really has lasting contacts
        const auto bytes = alone.particles.size() * sizeof(mrjam::Vec3);
        CHECK(std::memcmp(both.particles.position.data(), alone.particles.position.data(), bytes) == 0);
        CHECK(std::memcmp(both.particles.velocity.data(), alone.particles.velocity.data(), bytes) == 0);
        CHECK(std::memcmp(both.particles.angular_velocity.data(), alone.particles.angular_velocity.data(), bytes) == 0);
        CHECK(both.contacts.builds() > 1);  // the lists were rebuilt after the removal, histories carried
    }

    TEST_CASE("grain removal: the surviving index keeps the order and counts what stays") {
        std::size_t kept = 0;
        const auto index = mrjam::surviving_index({0, 1, 1, 0, 0, 1}, kept);
        CHECK(kept == 3);
        CHECK(index == std::vector<std::int64_t>{0, -1, -1, 1, 2, -1});
        std::vector<int> a{10, 11, 12, 13, 14, 15};
        mrjam::compact_by_index(a, index, kept);
        CHECK(a == std::vector<int>{10, 13, 14});
    }
}
