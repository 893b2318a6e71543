#pragma once
// The shear-cell protocol (chapter 2, sec. 2.4): magnetise until the chains settle, freeze the top
// and bottom layers into rafts, then shear through a decreasing ladder of rates with the Couette
// background flow, sampling the raft and bulk stresses. A study is the main ladder at the scene's
// field plus, optionally, one cell per field of a field sweep at a single rate (Fig. 2.15).
//
// Progress goes to stderr; a checkpoint holds the engine state and the study's progress (finished
// cells and rates with their samples), so a resumed study never redoes a finished rate.
#include <nlohmann/json.hpp>
#include <string>

#include "shear/shear_spec.hpp"

namespace mrjam {

struct ShearOptions {
    int threads = 1;
    bool threads_given = true;  // false: a study of several runs shares the cores among them
    int jobs = 0;               // runs side by side in a convergence study; 0: the machine's cores
    bool progress = true;
    std::string checkpoint_path;  // "" : <output directory>/shear_checkpoint.mrjam
    std::string label = "shear";  // progress prefix
};

struct ShearOutcome {
    nlohmann::json results;           // flow_curve, fits, field_sweep, magnetisation, cell ...
    nlohmann::json engine;            // timestep, engine fidelity and inputs of the main cell
    std::string status = "complete";  // complete, interrupted, failed
    std::string error;
    std::string checkpoint;  // written on interrupt
    int exit_status = 0;     // 0, 130 interrupted, 3 blow-up
    double wall_time = 0;
    // Speed of the main ladder's cells this command stepped (a resumed study counts from its
    // resume; a field sweep's runs report their own): steps_run, grain_steps_per_s,
    // core_us_per_grain_step, as run mode's report gives them.
    nlohmann::json performance;
};

// Builds the engine scene of `spec`'s first cell without its grains, as a cheap check that the
// engine takes every value; throws SceneError with the shear scene's path otherwise.
void check_engine_accepts(const ShearSpec& spec);

// Runs a study from the start. Throws SceneError on input the engine refuses (paths of the shear
// scene), before any stepping.
ShearOutcome run_shear_study(const ShearSpec& spec, const ShearOptions& options);

// Continues a study from its checkpoint; the shear scene and tier come from the checkpoint.
ShearOutcome resume_shear_study(const std::string& checkpoint, const ShearOptions& options, ShearSpec& spec_out);

}  // namespace mrjam
