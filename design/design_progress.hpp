#pragma once
// What a `mrjam design` run has done so far, kept in OUTPUT_DIRECTORY/design_progress.json and
// rewritten after every field solve and every seed, so that `mrjam design DESIGN.json --resume`
// continues an interrupted design where it stopped: finished constrictions are not run again, a
// solved field is not solved again, and the seed that was running resumes from its checkpoint.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace mrjam {

struct DesignProgress {
    nlohmann::json inputs;                          // the design file as read: a resume must run the same design
    std::string fidelity;                           // the jam tier it was started with
    nlohmann::json rows = nlohmann::json::array();  // the finished constrictions' report rows, in order
    std::string widest;                             // the widest of them that jams reliably ("" for none yet)
    double widest_diameter = 0;
    double wall_time_s = 0;  // spent by the earlier, interrupted runs
    // The constriction in progress (the one after the finished rows):
    nlohmann::json field = nullptr;                 // its solved field's summary once its map is written
    nlohmann::json runs = nlohmann::json::array();  // its finished seeds' records
    nlohmann::json first_report = nullptr;          // its first seed's jam report (for `mrjam jam --resume`)
};

std::filesystem::path design_progress_path(const std::filesystem::path& output_directory);

void write_design_progress(const std::filesystem::path& output_directory, const DesignProgress& progress);

// The progress of an interrupted design in `output_directory`, checked against the design file
// (`design`) and the tier now asked for (`fidelity`, "" when not given). Throws SceneError naming
// `--resume` when there is nothing to resume or when the design has changed since.
DesignProgress read_design_progress(const std::filesystem::path& output_directory, const nlohmann::json& design,
                                    const std::string& fidelity);

}  // namespace mrjam
