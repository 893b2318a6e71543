// Bounds checked before any work (issue #43): the pair lists' memory against the machine's, a
// starting speed against the step, a grain's weight against the contact stiffness. Each refusal
// names the key that would fix it.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "scene/memory_estimate.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

using namespace mrjam;
using json = nlohmann::json;

namespace {

// A closed box of side `side` with grains of diameter d at volume fraction phi.
json box_scene(double side, double d, double phi) {
    return {{"domain", {{"lo", {0, 0, 0}}, {"hi", {side, side, side}}}},
            {"materials",
             {{{"name", "iron"}, {"density", 7800}, {"youngs_modulus", 1e9}, {"relative_permeability", 1000}}}},
            {"grains",
             {{{"material", "iron"},
               {"size", {{"distribution", "single"}, {"diameter", d}}},
               {"placement", {{"method", "random"}, {"volume_fraction", phi}}}}}},
            {"run", {{"steps", 1}}}};
}

std::string refusal(const json& scene) {
    try {
        Scene s = build_scene(scene, BuildOptions{});
        choose_timestep(s);
    } catch (const SceneError& e) {
        return e.path();
    }
    return "accepted";
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("memory: pair lists are estimated before they are built; a cutoff that lists every pair is refused") {
        // 60,000 grains of 10 um with a magnetic reach of 1 mm beyond contact: every grain lists
        // every other, 1.8e9 pairs, about 47 GB; the same grains with the usual reach are fine.
        json s = box_scene(0.47e-3, 10e-6, 0.3);
        s["magnetic"] = {{"field", {{"type", "uniform"}, {"flux_density", {0, 0, 0.1}}}},
                         {"cutoff", {{"beyond_contact", 1e-3}}}};
        CHECK(refusal(s) == "/magnetic/cutoff");
        s["magnetic"]["cutoff"] = {{"diameters", 2}};
        Scene ok = build_scene(s, BuildOptions{});
        choose_timestep(ok);
        const PairMemoryEstimate e = estimate_pair_memory(ok.system);
        CHECK(e.magnetic_pairs > e.contact_pairs);
        CHECK(e.bytes < 0.1 * physical_memory_bytes());
    }

    TEST_CASE("magnetic cutoff: diameters with beyond_contact give the shorter range; other pairs are refused") {
        json s = box_scene(0.2e-3, 10e-6, 0.2);
        s["magnetic"] = {{"field", {{"type", "uniform"}, {"flux_density", {0, 0, 0.1}}}},
                         {"cutoff", {{"diameters", 2}, {"beyond_contact", "8 um"}}}};
        Scene both = build_scene(s, BuildOptions{});
        choose_timestep(both);  // sets up the pair lists
        const NeighborList::Settings& st = both.system.magnetic.pairs.settings();
        CHECK(st.cutoff_scale == 1.0);
        CHECK(st.cutoff_extra == doctest::Approx(8e-6).epsilon(1e-12));
        CHECK(st.cutoff_max_scale == 2.0);
        // 10 um grains: min(2 x 10, 10 + 8) um = 18 um; 2 um grains: min(4, 10) um = 4 um.
        CHECK(both.system.magnetic.pairs.interaction_range(5e-6, 5e-6) == doctest::Approx(18e-6).epsilon(1e-12));
        CHECK(both.system.magnetic.pairs.interaction_range(1e-6, 1e-6) == doctest::Approx(4e-6).epsilon(1e-12));
        s["magnetic"]["cutoff"] = {{"diameters", 2}, {"length", "30 um"}};
        CHECK(refusal(s) == "/magnetic/cutoff/diameters");
        s["magnetic"]["cutoff"] = {{"beyond_contact", "8 um"}, {"length", "30 um"}};
        CHECK(refusal(s) == "/magnetic/cutoff/diameters");
        s["magnetic"]["cutoff"] = {{"diameters", 0.5}, {"beyond_contact", "8 um"}};
        CHECK(refusal(s) == "/magnetic/cutoff/diameters");
    }

    TEST_CASE("plausibility: a starting speed that crosses half a radius in a step is refused at its batch") {
        json s = box_scene(5e-3, 0.5e-3, 0.05);
        s["grains"][0]["placement"]["region"] = {{"shape", "box"}, {"lo", {0, 0, 0}}, {"hi", {5e-3, 5e-3, 2e-3}}};
        s["grains"].push_back(s["grains"][0]);
        s["grains"][1]["placement"]["region"] = {{"shape", "box"}, {"lo", {0, 0, 3e-3}}, {"hi", {5e-3, 5e-3, 5e-3}}};
        s["grains"][1]["random_velocity"] = "1e6 m/s";
        CHECK(refusal(s) == "/grains/1");
        s["grains"][1]["random_velocity"] = "0.1 m/s";
        CHECK(refusal(s) == "accepted");
    }

    TEST_CASE(
        "plausibility: a gravity whose weight the contacts cannot hold, or that falls a radius a step, is refused") {
        json s = box_scene(5e-3, 0.5e-3, 0.1);
        s["gravity"] = {0, 0, "-9.81 m/s2"};
        CHECK(refusal(s) == "accepted");
        s["gravity"] = {0, 0, -1e308};
        CHECK(refusal(s) == "/gravity");
        // 1e7 m/s2 on 1 GPa grains of 0.5 mm: the weight alone overlaps them about 0.2 radii.
        s["gravity"] = {0, 0, "-1e7 m/s2"};
        CHECK(refusal(s) == "/gravity");
        s["contact"] = {{"model", "none"}};
        s["run"]["timestep"] = "1 us";
        s["gravity"] = {0, 0, "-1e6 m/s2"};  // falls 1e-6 m in a step: 0.004 radii, fine without contacts
        CHECK(refusal(s) == "accepted");
    }
}
