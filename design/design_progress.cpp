#include "design/design_progress.hpp"

#include <fstream>

#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path design_progress_path(const fs::path& output_directory) { return output_directory / "design_progress.json"; }

void write_design_progress(const fs::path& output_directory, const DesignProgress& p) {
    write_json_file(design_progress_path(output_directory).string(), {{"format", "mrjam design progress 1"},
                                                                      {"inputs", p.inputs},
                                                                      {"fidelity", p.fidelity},
                                                                      {"rows", p.rows},
                                                                      {"widest", p.widest},
                                                                      {"widest_diameter_m", p.widest_diameter},
                                                                      {"wall_time_s", p.wall_time_s},
                                                                      {"field", p.field},
                                                                      {"runs", p.runs},
                                                                      {"first_report", p.first_report}});
}

DesignProgress read_design_progress(const fs::path& output_directory, const json& design, const std::string& fidelity) {
    const fs::path path = design_progress_path(output_directory);
    std::ifstream in(path);
    if (!in)
        throw SceneError("--resume", "no design in progress in " + output_directory.string() + " (" +
                                         path.filename().string() + " is missing): run the design without --resume");
    json saved;
    try {
        saved = json::parse(in);
    } catch (const json::exception& e) {
        throw SceneError("--resume", path.string() + " is damaged (" + e.what() + "): run the design without --resume");
    }
    if (!saved.is_object() || saved.value("format", "") != "mrjam design progress 1")
        throw SceneError("--resume",
                         path.string() + " is not a design's progress record: run the design without --resume");
    DesignProgress p;
    try {
        p.inputs = saved.at("inputs");
        p.fidelity = saved.at("fidelity").get<std::string>();
        p.rows = saved.at("rows");
        p.widest = saved.at("widest").get<std::string>();
        p.widest_diameter = saved.at("widest_diameter_m").get<double>();
        p.wall_time_s = saved.at("wall_time_s").get<double>();
        p.field = saved.at("field");
        p.runs = saved.at("runs");
        p.first_report = saved.at("first_report");
    } catch (const json::exception& e) {
        throw SceneError("--resume", path.string() + " is damaged (" + e.what() + "): run the design without --resume");
    }
    // Another design in the same directory would mix two designs' constrictions in one report.
    if (p.inputs != design)
        throw SceneError("--resume", "the design file has changed since the run in " + output_directory.string() +
                                         " was interrupted: restore it, or run the changed design without --resume");
    if (!fidelity.empty() && fidelity != p.fidelity)
        throw SceneError("--fidelity",
                         "the interrupted design ran at the " + p.fidelity + " tier: drop --fidelity to resume it");
    return p;
}

}  // namespace mrjam
