#pragma once
// What the simulated asteroid modes (coalesce, spinup, avalanche) share around the run loop: the
// report's envelope, the plot's path beside the report, and reading back a checkpoint the mode wrote.
#include <nlohmann/json.hpp>
#include <string>

#include "io/checkpoint.hpp"
#include "run/runner.hpp"
#include "system.hpp"

namespace mrjam {

// The runner's report relabelled for the mode: the mode's own scene as `inputs`, the engine scene
// it built as `engine_inputs`, the tier.
nlohmann::json asteroid_report(const RunOutcome& outcome, const char* mode, const nlohmann::json& inputs,
                               const std::string& fidelity);

// REPORT.json -> REPORT_<suffix>.svg, next to it.
std::string plot_beside(const std::string& report_path, const std::string& suffix);

// The heaviest contact cluster drawn along and across the spin axis, coloured by distance from
// its centre of mass, as REPORT_<suffix>.svg next to the report; returns the path, or an empty
// string (and a warning on stderr) if it could not be written: a picture never costs the run.
std::string body_views_beside(const std::string& report_path, const std::string& suffix, const System& s,
                              const std::string& title);

// The checkpoint's header, refused at --resume unless `mode` wrote it.
CheckpointHeader read_mode_checkpoint(const std::string& path, const char* mode);

}  // namespace mrjam
