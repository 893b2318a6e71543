#pragma once
// `mrjam asteroid coalesce`: a spherical cloud of rubble grains collapsing under its own gravity
// into a body (section 4.2 of the source), on the engine's run loop: self-gravity and permanent
// dipoles as force terms, the grains beyond the escape radius taken out by a modifier, the body
// diagnosed at every sample, checkpoint and resume as every mode.
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/coalesce_spec.hpp"

namespace mrjam {

struct CoalesceOptions {
    std::string scene_path;   // echoed into the report
    std::string report_path;  // the JSON report; the plot goes next to it
    std::string fidelity = "quick";
    int threads = 1;
    bool progress = true;
};

struct CoalesceOutcome {
    nlohmann::json report;
    int exit_status = 0;  // 0 done, 130 interrupted (checkpoint written), 3 blow-up
};

CoalesceOutcome run_coalescence(const CoalesceSpec& spec, const CoalesceOptions& options);
// From a checkpoint the mode wrote (its scene and samples inside): SceneError("--resume") otherwise.
CoalesceOutcome resume_coalescence(const std::string& checkpoint, const CoalesceOptions& options);

}  // namespace mrjam
