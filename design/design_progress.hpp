#pragma once
// What a `mrjam design` run has done so far, so that `mrjam design DESIGN.json --resume`
// continues an interrupted design where it stopped: finished constrictions are not run again, a
// solved field is not solved again, and the seed that was running resumes from its checkpoint.
//
// The design's constrictions are the points of a sweep (lib/sweep), whose registry and point
// states say which constrictions are done. Beside them the design keeps two records:
// OUTPUT_DIRECTORY/design_progress.json (the design file and tier a resume must match, the wall
// time spent so far) and, in each constriction's folder, constriction_progress.json (its solved
// field, its finished seeds), rewritten after every field solve and every seed.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace mrjam {

struct DesignProgress {
    nlohmann::json inputs;   // the design file as read: a resume must run the same design
    std::string fidelity;    // the jam tier it was started with
    double wall_time_s = 0;  // spent by the earlier, interrupted runs
};

std::filesystem::path design_progress_path(const std::filesystem::path& output_directory);

void write_design_progress(const std::filesystem::path& output_directory, const DesignProgress& progress);

// The progress of an interrupted design in `output_directory`, checked against the design file
// (`design`) and the tier now asked for (`fidelity`, "" when not given). Throws SceneError naming
// `--resume` when there is nothing to resume or when the design has changed since.
DesignProgress read_design_progress(const std::filesystem::path& output_directory, const nlohmann::json& design,
                                    const std::string& fidelity);

// One constriction in progress.
struct ConstrictionProgress {
    nlohmann::json field = nullptr;                 // its solved field's summary once its map is written
    nlohmann::json runs = nlohmann::json::array();  // its finished seeds' records
    nlohmann::json first_report = nullptr;          // its first seed's jam report (for `mrjam jam --resume`)
};

std::filesystem::path constriction_progress_path(const std::filesystem::path& folder);

void write_constriction_progress(const std::filesystem::path& folder, const ConstrictionProgress& progress);

// The record in `folder`, or an empty one when there is none (the constriction had not started).
// Throws SceneError naming `--resume` when the record is damaged.
ConstrictionProgress read_constriction_progress(const std::filesystem::path& folder);

}  // namespace mrjam
