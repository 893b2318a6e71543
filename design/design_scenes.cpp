#include "design/design_scenes.hpp"

#include <cmath>
#include <limits>
#include <tuple>

#include "core/format.hpp"
#include "scene/output_block.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
std::vector<std::pair<std::string, double>> read_constrictions(const json& list) {
    std::vector<std::pair<std::string, double>> out;
    if (!list.is_array() || list.empty())
        throw SceneError("/constrictions", "give a non-empty list of presets (\"20x\") or diameters (\"1.2 mm\")");
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string path = "/constrictions/" + std::to_string(i);
        if (!list[i].is_string()) throw SceneError(path, "a preset name or a diameter with units");
        const std::string text = list[i].get<std::string>();
        double d = constriction_preset(text);
        if (d == 0) {
            try {
                d = units::parse_as(text, units::length);
            } catch (const std::exception& e) {
                throw SceneError(path, e.what());
            }
        }
        // Each constriction is run under output_directory/<its name>: a repeat would overwrite
        // the first, and two names of one diameter would run it twice.
        for (std::size_t j = 0; j < out.size(); ++j)
            if (out[j].first == text || std::abs(out[j].second - d) <= 1e-12 * d)
                throw SceneError(path, "names the same constriction as /constrictions/" + std::to_string(j) + " (\"" +
                                           out[j].first + "\"); drop one");
        out.push_back({text, d});
    }
    return out;
}

// A block's error named from the design file's root; one without a JSON path (a command-line
// option's) is left as it is.
SceneError in_block(const std::string& block, const SceneError& e) {
    if (e.path().empty() || e.path()[0] != '/') return e;
    return e.at(block + e.path());
}

// Runs a block's scene reader and names its errors from the design file's root: "/jam/protocol/..."
// rather than the block's own "/protocol/...".
template <class Read>
auto within_block(const std::string& block, Read&& read) {
    try {
        return read();
    } catch (const SceneError& e) {
        throw in_block(block, e);
    }
}

// Sets a key of a sub-scene that the design owns for each constriction. A key the user gave there
// would be overwritten without a word, so it is refused with `fix`, where the setting belongs.
void set_design_key(json& scene, const std::string& scene_path, const std::string& key, json value,
                    const std::string& fix) {
    if (scene.is_object() && scene.contains(key)) throw SceneError(scene_path + "/" + key, fix);
    scene[key] = std::move(value);
}

// The design's output block: its directory, and the keys each constriction's jam run takes as its
// own. A checkpoint's path is the jam run's to choose (where --resume looks), so it is refused.
void read_design_output(SceneNode& root, DesignSpec& spec) {
    const json none = json::object();
    json unused;
    std::optional<SceneNode> output = root.optional_object("output");
    const OutputBlock block =
        read_output_block(output ? *output : SceneNode(none, unused, "/output"), "out/design",
                          "each jam run keeps its checkpoint in output/directory/<constriction>/jam, where --resume "
                          "finds it: drop path");
    spec.output_directory = block.directory;
    spec.jam_output = spec.design.contains("output") ? spec.design["output"] : json::object();
    spec.jam_output.erase("directory");
}
}  // namespace

DesignSpec read_design_spec(const json& design, const std::string& design_path) {
    if (!design.is_object()) throw SceneError("", "a design scene is a JSON object");
    DesignSpec spec;
    spec.design = design;
    // The design's own keys; `magnetics` and `jam` are scenes of those modes, checked by their readers.
    SceneNode root(design, spec.resolved, "");
    root.text("description", "");
    if (design.contains("magnetics")) spec.magnetics_block = root.raw("magnetics");
    if (design.contains("jam")) spec.jam_block = root.raw("jam");
    for (const auto& [key, block] :
         {std::pair{"/magnetics", &spec.magnetics_block}, std::pair{"/jam", &spec.jam_block}})
        if (!block->is_object())
            throw SceneError(key, std::string("must be a JSON object (a scene of `mrjam ") + (key + 1) + "`)");
    if (spec.magnetics_block.contains("valve") && !spec.magnetics_block["valve"].is_object())
        throw SceneError("/magnetics/valve", "must be a JSON object (the valve's keys)");
    spec.constrictions = read_constrictions(design.contains("constrictions") ? root.raw("constrictions")
                                                                             : json::array({"20x", "30x", "40x"}));
    spec.required_jam_probability = root.number("required_jam_probability", 1.0, Bounds::open_closed(0.0, 1.0));
    spec.seeds = static_cast<int>(root.integer("seeds", 1, 1, 1000));
    if (root.has("output_directory"))
        root.fail("output_directory",
                  "is now output/directory (one output block with the same keys in every mode; docs/scene.md, "
                  "\"Output\")");
    read_design_output(root, spec);
    root.finish();
    spec.base_directory = fs::path(design_path).parent_path().string();
    return spec;
}

magnetics::MagneticsScene design_magnetics_scene(const DesignSpec& spec, const fs::path& dir, double diameter,
                                                 const std::string& magnetics_tier) {
    json mscene = spec.magnetics_block;
    const std::string from_list =
        "the design takes its constrictions from its own `constrictions` list; remove this key";
    json& valve = mscene["valve"];
    if (valve.is_object() && valve.contains("constriction"))
        throw SceneError("/magnetics/valve/constriction", from_list);
    set_design_key(valve, "/magnetics/valve", "constriction_diameter", diameter, from_list);
    set_design_key(mscene, "/magnetics", "state", "on", "the design solves the magnet's ON state; remove this key");
    // The map the jam runs read is the applied field B0 = mu0 H0 the grains see before their own
    // dipoles, which add the fluid's magnetisation: so the fluid is solved as air unless the design
    // says otherwise (a mu_r = 10 fluid's B would count it twice; docs/jam.md, "The field the grains see").
    // (A materials or fluid key that is not an object is left for the magnetics reader to refuse.)
    if (!mscene.contains("materials") || mscene["materials"].is_object()) {
        json& fluid = mscene["materials"]["fluid"];
        if (fluid.is_null()) fluid = json::object();
        if (fluid.is_object() && !fluid.contains("relative_permeability")) fluid["relative_permeability"] = 1.0;
    }
    set_design_key(mscene, "/magnetics", "output", {{"directory", (dir / "magnetics").string()}},
                   "the design writes each solve under output/directory/<constriction>/magnetics; remove "
                   "this key (set the design's output/directory instead)");
    magnetics::MagneticsScene scene =
        within_block("/magnetics", [&] { return magnetics::read_magnetics_scene(mscene, magnetics_tier); });
    // The jam runs need a field map, which the circuit model does not make: refused before the
    // first solve, not after it ("a field map needs at least 2 nodes along each axis").
    if (scene.request.field_model == magnetics::FieldModel::circuit)
        throw SceneError("/magnetics/model",
                         "the circuit model gives one mean field and no field map, which the jam runs need; use "
                         "\"2d\" or \"3d\" (or drop it: the tier chooses)");
    return scene;
}

json design_jam_inputs(const DesignSpec& spec, const fs::path& dir, json valve, const json& field) {
    json jscene = spec.jam_block;
    for (const char* k : {"upstream_length", "downstream_length"}) valve.erase(k);
    set_design_key(jscene, "/jam", "valve", std::move(valve),
                   "the design's valve is magnetics/valve, one valve for both models; move these keys there "
                   "(the tube lengths modelled are jam/model/upstream_length and downstream_length)");
    set_design_key(jscene, "/jam", "field", field,
                   "the design runs the jam predictor in the field it solved for each constriction; remove this "
                   "key (`mrjam jam` runs a scene in a uniform field or a map of your own)");
    json output = spec.jam_output;
    output["directory"] = (dir / "jam").string();
    set_design_key(jscene, "/jam", "output", std::move(output),
                   "the design writes each jam run under output/directory/<constriction>/jam; remove this key "
                   "(the design's own output block sets the jam runs' progress, checkpoints and snapshots)");
    return jscene;
}

JamScene design_jam_scene(const DesignSpec& spec, const json& jam_inputs, const std::string& jam_tier) {
    return within_block("/jam", [&] { return read_jam_scene(jam_inputs, jam_tier, spec.base_directory); });
}

SceneError for_constriction(const SceneError& e, const DesignSpec& spec, std::size_t index) {
    return SceneError(e.path(), e.message() + " (with /constrictions/" + std::to_string(index) + ", \"" +
                                    spec.constrictions[index].first + "\")");
}

SceneError from_jam_run(const SceneError& e, const DesignSpec& spec, std::size_t index) {
    if (e.path().empty() || e.path()[0] != '/') return e;  // an option's, not the jam block's
    return for_constriction(in_block("/jam", e), spec, index);
}

void check_design_scenes(const DesignSpec& spec, const std::string& magnetics_tier, const std::string& jam_tier) {
    for (std::size_t i = 0; i < spec.constrictions.size(); ++i) try {
            const auto& [name, diameter] = spec.constrictions[i];
            const fs::path dir = spec.output_directory / name;
            const auto ms = design_magnetics_scene(spec, dir, diameter, magnetics_tier);
            const JamScene js = design_jam_scene(
                spec,
                design_jam_inputs(spec, dir, ms.resolved["valve"], json{{"type", "uniform"}, {"flux_density", 0.0}}),
                jam_tier);
            // (A zero uniform field stands in for the map to come.) The field map covers the
            // magnetics valve's tube; the jam run models its own length of it, which must lie inside
            // (found after the solve, this stopped the design there).
            const double up = ms.resolved["valve"]["upstream_length"].get<double>();
            const double down = ms.resolved["valve"]["downstream_length"].get<double>();
            for (const auto& [key, jam_length, field_length] :
                 {std::tuple{"upstream_length", js.valve.upstream_length, up},
                  {"downstream_length", js.valve.downstream_length, down}})
                if (jam_length > field_length * (1 + 1e-9))
                    throw SceneError(std::string("/jam/model/") + key,
                                     "the jam run would model " + format_number(jam_length * 1e3) +
                                         " mm of tube, past the " + format_number(field_length * 1e3) +
                                         " mm the field is solved over (/magnetics/valve/" + key +
                                         "): shorten this, or lengthen that");
            const long long seed = js.engine_scene["seed"].get<long long>();
            if (seed > std::numeric_limits<long long>::max() - (spec.seeds - 1))
                throw SceneError("/jam/seed", "seed + seeds - 1 overflows a 64-bit seed: give a smaller seed");
        } catch (const SceneError& e) {
            const std::string entry = "/constrictions/" + std::to_string(i);
            if (e.path().ends_with("/valve/constriction_diameter")) throw e.at(entry);
            // A block's key that fails for this constriction only (a mesh too coarse for a narrow
            // throat, say): the message says which.
            if (e.path().starts_with("/magnetics") || e.path().starts_with("/jam")) throw for_constriction(e, spec, i);
            throw;
        }
}

}  // namespace mrjam
