#include "design/design_progress.hpp"

#include <fstream>

#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kDesignFormat = "mrjam design progress 2";
constexpr const char* kConstrictionFormat = "mrjam design constriction progress 1";

// A record this program wrote, checked for its format; a damaged one is bad input to --resume.
json read_record(const fs::path& path, const char* format) {
    std::ifstream in(path);
    json saved;
    try {
        saved = json::parse(in);
    } catch (const json::exception& e) {
        throw SceneError("--resume", path.string() + " is damaged (" + e.what() + "): run the design without --resume");
    }
    if (!saved.is_object() || saved.value("format", "") != format)
        throw SceneError("--resume", path.string() + " is not a record of this version's design (format " + format +
                                         "): run the design without --resume");
    return saved;
}

[[noreturn]] void damaged(const fs::path& path, const json::exception& e) {
    throw SceneError("--resume", path.string() + " is damaged (" + e.what() + "): run the design without --resume");
}

}  // namespace

fs::path design_progress_path(const fs::path& output_directory) { return output_directory / "design_progress.json"; }

void write_design_progress(const fs::path& output_directory, const DesignProgress& p) {
    write_json_file(
        design_progress_path(output_directory).string(),
        {{"format", kDesignFormat}, {"inputs", p.inputs}, {"fidelity", p.fidelity}, {"wall_time_s", p.wall_time_s}});
}

DesignProgress read_design_progress(const fs::path& output_directory, const json& design, const std::string& fidelity) {
    const fs::path path = design_progress_path(output_directory);
    if (!fs::exists(path))
        throw SceneError("--resume", "no design in progress in " + output_directory.string() + " (" +
                                         path.filename().string() + " is missing): run the design without --resume");
    const json saved = read_record(path, kDesignFormat);
    DesignProgress p;
    try {
        p.inputs = saved.at("inputs");
        p.fidelity = saved.at("fidelity").get<std::string>();
        p.wall_time_s = saved.at("wall_time_s").get<double>();
    } catch (const json::exception& e) {
        damaged(path, e);
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

fs::path constriction_progress_path(const fs::path& folder) { return folder / "constriction_progress.json"; }

void write_constriction_progress(const fs::path& folder, const ConstrictionProgress& p) {
    write_json_file(
        constriction_progress_path(folder).string(),
        {{"format", kConstrictionFormat}, {"field", p.field}, {"runs", p.runs}, {"first_report", p.first_report}});
}

ConstrictionProgress read_constriction_progress(const fs::path& folder) {
    const fs::path path = constriction_progress_path(folder);
    ConstrictionProgress p;
    if (!fs::exists(path)) return p;
    const json saved = read_record(path, kConstrictionFormat);
    try {
        p.field = saved.at("field");
        p.runs = saved.at("runs");
        p.first_report = saved.at("first_report");
        if (!p.runs.is_array()) throw json::type_error::create(302, "runs is not a list", nullptr);
    } catch (const json::exception& e) {
        damaged(path, e);
    }
    return p;
}

}  // namespace mrjam
