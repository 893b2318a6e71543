// Every bundled example is accepted by the reader of the mode it is written for, at that mode's
// default tier and the tiers the docs run it at: an example a newcomer copies must not be refused.
// The readers are what each command runs before any work (the same checks, the same messages),
// so this costs seconds where running the examples would cost hours. A new example in a folder
// or with a prefix no rule below names fails the test until its mode is added.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "asteroid/avalanche_spec.hpp"
#include "asteroid/coalesce_spec.hpp"
#include "asteroid/scaling_spec.hpp"
#include "asteroid/spinup_spec.hpp"
#include "design/design_scenes.hpp"
#include "jam/jam_scene.hpp"
#include "magnetics/magnetics_scene.hpp"
#include "scene/scene.hpp"
#include "scene/scene_file.hpp"
#include "shear/shear_spec.hpp"
#include "sweep/sweep_spec.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

bool starts(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// Reads `file` (its path inside examples/ is `name`) with its mode's reader; returns the mode, or
// "" when no rule names it.
std::string check_example(const fs::path& file, const std::string& name) {
    const json scene = mrjam::read_json_file(file.string());
    const std::string dir = file.parent_path().string(), stem = file.stem().string();
    if (starts(name, "asteroid/")) {
        if (starts(stem, "avalanche"))
            (void)mrjam::read_avalanche_spec(scene, "standard");
        else if (starts(stem, "coalesce"))
            (void)mrjam::read_coalesce_spec(scene, "standard");
        else if (starts(stem, "spinup"))
            (void)mrjam::read_spinup_spec(scene, "standard");
        else if (starts(stem, "scaling"))
            (void)mrjam::read_scaling_spec(scene);
        else
            return "";
        return "asteroid";
    }
    if (starts(name, "calibration/") || starts(name, "shear_")) {
        for (const char* tier : {"quick", "standard"}) (void)mrjam::read_shear_spec(scene, tier);
        return "shear";
    }
    if (starts(name, "table32/") || starts(name, "valve_")) {
        for (const char* tier : {"quick", "standard"}) (void)mrjam::read_jam_scene(scene, tier, dir);
        // The continuum tier needs the fluid's yield stress, which the scenes meant for it give.
        if (scene.contains("continuum")) (void)mrjam::read_jam_scene(scene, "continuum", dir);
        return "jam";
    }
    if (starts(name, "design_")) {
        const mrjam::DesignSpec spec = mrjam::read_design_spec(scene, file.string());
        for (const char* tier : {"quick", "standard"}) mrjam::check_design_scenes(spec, "standard", tier);
        return "design";
    }
    if (starts(name, "epm_")) {
        for (const char* tier : {"quick", "standard"}) (void)mrjam::magnetics::read_magnetics_scene(scene, tier);
        return "magnetics";
    }
    if (starts(name, "sweeps/")) {
        (void)mrjam::read_sweep(scene, dir);
        return "sweep";
    }
    if (name == "settle_column.json" || name == "chains_600mT.json" || name == "couette_rafts.json") {
        mrjam::BuildOptions options;
        options.base_directory = dir;
        (void)mrjam::build_scene(scene, options);
        return "run";
    }
    return "";
}

}  // namespace

TEST_SUITE("examples") {
    TEST_CASE("examples: every bundled scene is accepted by its mode") {
        const fs::path root = fs::path(MRJAM_SOURCE_DIR) / "examples";
        std::vector<fs::path> files;
        for (const auto& entry : fs::recursive_directory_iterator(root))
            if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
        std::sort(files.begin(), files.end());
        REQUIRE(files.size() > 50);  // the folder was found and read
        int checked = 0;
        for (const fs::path& file : files) {
            const std::string name = fs::relative(file, root).generic_string();
            CAPTURE(name);
            try {
                const std::string mode = check_example(file, name);
                CHECK_MESSAGE(!mode.empty(), "no rule names this example's mode: add one to tests/test_examples.cpp");
                checked += !mode.empty();
            } catch (const std::exception& e) {
                FAIL_CHECK("refused: " << std::string(e.what()));
            }
        }
        MESSAGE(checked << " examples accepted by their modes");
        CHECK(checked == static_cast<int>(files.size()));
    }
}
