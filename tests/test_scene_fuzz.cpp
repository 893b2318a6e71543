// Hostile input, as a class: every scene reader that only reads (jam, shear, magnetics, design,
// asteroid scaling) is fed thousands of mutations of the bundled examples - a key deleted or
// renamed, a value swapped for another type, an absurd number (0, -1, 1e308, 4294967297), a
// malformed quantity ("0x10 mm", "12 furlongs", "nan T", a NUL byte), deep nesting - and must
// either accept the scene or refuse it with a SceneError naming a JSON path. Anything else (a
// std::out_of_range from a missing check, a nlohmann type error, a crash) fails the test with the
// mutated scene printed. Deterministic: the mutations come from a fixed seed.
//
// The `run` reader builds grains, whose cost grows with the grain count the input asks for (the
// memory estimate and plausibility checks bound it: test_scene_bounds.cpp); it is fuzzed as a
// resumed scene reads, every block checked and nothing packed (BuildOptions::insert_grains off).
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "asteroid/scaling_spec.hpp"
#include "design/design_scenes.hpp"
#include "jam/jam_scene.hpp"
#include "magnetics/magnetics_scene.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "shear/shear_spec.hpp"

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const fs::path kExamples = fs::path(MRJAM_SOURCE_DIR) / "examples";

json read_example(const fs::path& relative) {
    std::ifstream in(kExamples / relative);
    REQUIRE_MESSAGE(in, "missing example " << relative);
    return json::parse(in);
}

// Every JSON pointer in the scene (objects and arrays alike), the root excluded.
void collect_pointers(const json& j, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
    if (j.is_object())
        for (const auto& [key, value] : j.items()) {
            out.push_back(at / key);
            collect_pointers(value, at / key, out);
        }
    else if (j.is_array())
        for (std::size_t i = 0; i < j.size(); ++i) {
            out.push_back(at / i);
            collect_pointers(j[i], at / i, out);
        }
}

json hostile_value(std::mt19937_64& rng) {
    static const std::vector<json> values = {0,
                                             -1,
                                             1e308,
                                             -1e308,
                                             4294967297LL,
                                             1e-320,
                                             0.5,
                                             true,
                                             nullptr,
                                             "",
                                             "0x10 mm",
                                             "12 furlongs",
                                             "nan T",
                                             "inf mm",
                                             "1e400 Pa",
                                             std::string("5 mm\0", 5),
                                             "-3 ms",
                                             "41 kPa kPa",
                                             "  ",
                                             json::array(),
                                             json::object(),
                                             json::array({1, 2}),
                                             json::array({"a", nullptr}),
                                             json::object({{"x", 1}}),
                                             "saturating",
                                             "map",
                                             1e9,
                                             -0.0};
    return values[std::uniform_int_distribution<std::size_t>(0, values.size() - 1)(rng)];
}

// One mutation of a copy of `base`: replace, delete, rename or nest a random member.
json mutate(const json& base, std::mt19937_64& rng) {
    json j = base;
    std::vector<json::json_pointer> pointers;
    collect_pointers(j, json::json_pointer(), pointers);
    if (pointers.empty()) return j;
    const auto& p = pointers[std::uniform_int_distribution<std::size_t>(0, pointers.size() - 1)(rng)];
    json& parent = j.at(p.parent_pointer());
    switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
        case 0:
        case 1:
        case 2:
            j.at(p) = hostile_value(rng);
            break;
        case 3:  // delete
            if (parent.is_object())
                parent.erase(p.back());
            else
                parent.erase(std::stoul(p.back()));
            break;
        case 4:  // rename (a misspelt key)
            if (parent.is_object()) {
                json moved = parent[p.back()];
                parent.erase(p.back());
                parent[p.back() + "s"] = std::move(moved);
            }
            break;
        default: {  // nest the value 40 levels deep
            json nested = j.at(p);
            for (int k = 0; k < 40; ++k) nested = json::array({nested});
            j.at(p) = std::move(nested);
        }
    }
    return j;
}

// Feeds `rounds` mutations of the example to the reader; only acceptance or a SceneError passes.
void fuzz(const std::string& label, const json& base, int rounds, const std::function<void(const json&)>& reader) {
    std::mt19937_64 rng(std::hash<std::string>{}(label));
    int refused = 0;
    for (int r = 0; r < rounds; ++r) {
        const json scene = mutate(base, rng);
        try {
            reader(scene);
        } catch (const mrjam::SceneError& e) {
            ++refused;
            if (std::string(e.what()).find('/') == std::string::npos)
                FAIL_CHECK(label << ": a refusal without a JSON path: " << e.what() << "\nscene: " << scene.dump());
        } catch (const std::exception& e) {
            FAIL_CHECK(label << ": not a SceneError: " << e.what() << "\nscene: " << scene.dump());
        }
    }
    // The mutations must reach the checks: at least a fifth are refusals (deleting an optional key,
    // or nesting a free-text description, leaves a valid scene; the examples are 25-80 % refused).
    CHECK_MESSAGE(refused > rounds / 5, label << ": only " << refused << " of " << rounds << " refused");
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("hostile input: mutated scenes are accepted or refused by path, never anything else") {
        const std::string jam_dir = (kExamples / "table32").string();
        fuzz("jam", read_example("table32/mix2_20x.json"), 1500,
             [&](const json& s) { (void)mrjam::read_jam_scene(s, "quick", jam_dir); });
        fuzz("jam-hold", read_example("table32/hold_mix2_20x.json"), 500,
             [&](const json& s) { (void)mrjam::read_jam_scene(s, "quick", jam_dir); });
        fuzz("shear", read_example("calibration/mix2_100mT.json"), 1500,
             [](const json& s) { (void)mrjam::read_shear_spec(s, "quick"); });
        fuzz("magnetics", read_example("epm_curved_on.json"), 1500,
             [](const json& s) { (void)mrjam::magnetics::read_magnetics_scene(s, "quick"); });
        fuzz("design", read_example("design_quick.json"), 1000,
             [](const json& s) { (void)mrjam::read_design_spec(s, (kExamples / "design_quick.json").string()); });
        fuzz("asteroid", read_example("asteroid/scaling_fig4_15.json"), 1500,
             [](const json& s) { (void)mrjam::read_scaling_spec(s); });
        mrjam::BuildOptions read_only;
        read_only.insert_grains = false;
        read_only.base_directory = kExamples.string();
        read_only.fidelity = "quick";
        for (const char* example : {"settle_column.json", "chains_600mT.json", "couette_rafts.json"})
            fuzz(std::string("run ") + example, read_example(example), 600,
                 [&](const json& s) { (void)mrjam::build_scene(s, read_only); });
    }
}
