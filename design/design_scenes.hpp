#pragma once
// A `mrjam design` file: its own keys, and the two scenes it makes for each constriction (the
// magnetics scene whose field is solved, and the jam scene run in that field). Every error is
// named from the design file's root ("/jam/protocol/arrest_fraction", "/constrictions/1").
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "jam/jam_scene.hpp"
#include "magnetics/magnetics_scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

struct DesignSpec {
    nlohmann::json design;                                      // the file as read
    nlohmann::json resolved;                                    // the design's own keys with their defaults
    nlohmann::json magnetics_block = nlohmann::json::object();  // a `mrjam magnetics` scene, less what the design sets
    nlohmann::json jam_block = nlohmann::json::object();        // a `mrjam jam` scene, less what the design sets
    std::vector<std::pair<std::string, double>> constrictions;  // as written ("20x", "1.2 mm") and in metres
    double required_jam_probability = 1.0;
    int seeds = 1;
    std::filesystem::path output_directory;  // output/directory
    // The rest of the design's output block (progress_interval, checkpoint, snapshots), given to
    // every jam run as its own, so the block has the same keys as in every other mode.
    nlohmann::json jam_output = nlohmann::json::object();
    std::string base_directory;  // the design file's directory: relative paths in the jam block start there
};

// Checks the design's own keys; the blocks are checked by check_design_scenes.
DesignSpec read_design_spec(const nlohmann::json& design, const std::string& design_path);

// The magnetics scene of one constriction, its solve under `dir`/magnetics.
magnetics::MagneticsScene design_magnetics_scene(const DesignSpec& spec, const std::filesystem::path& dir,
                                                 double diameter, const std::string& magnetics_tier);

// The jam scene of one constriction as written (also what `mrjam jam --resume` reads back from its
// checkpoint): the jam block with the magnetics valve, `field` and an output under `dir`/jam.
nlohmann::json design_jam_inputs(const DesignSpec& spec, const std::filesystem::path& dir, nlohmann::json valve,
                                 const nlohmann::json& field);
JamScene design_jam_scene(const DesignSpec& spec, const nlohmann::json& jam_inputs, const std::string& jam_tier);

// Every constriction's two scenes, read before the first solve: a bad jam block must not cost a
// field solve. A throat the valve or the grains cannot take is named by its list entry.
// A block's error that holds for one constriction only, saying which: "... (with /constrictions/1, \"30x\")".
SceneError for_constriction(const SceneError& e, const DesignSpec& spec, std::size_t index);
// An error the jam run finds once its step is known (a flux observed too rarely, a protocol time
// past the step budget), named from the design file's root: "/jam/protocol/...", and the constriction.
SceneError from_jam_run(const SceneError& e, const DesignSpec& spec, std::size_t index);

void check_design_scenes(const DesignSpec& spec, const std::string& magnetics_tier, const std::string& jam_tier);

}  // namespace mrjam
