#pragma once
// Executes a scene's protocol: stages in order, progress on stderr, snapshots, checkpoints,
// interrupt handling, and the JSON report.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "scene/scene.hpp"

namespace mrjam {

// A modifier changes the state between steps (LAMMPS's end-of-step fix, HOOMD's updater): an
// outlet that takes grains out, a carrier flow set from the grains, a supply that follows the
// protocol. It runs at every observation, after the observers have read the state the steps
// produced and before the stage's criterion is tested.
struct Modifier {
    std::string name;
    std::function<void(System&, std::size_t stage)> apply;
};

struct RunOptions {
    std::string scene_path;   // echoed into the report
    std::string report_path;  // where the report goes ("" for none)
    bool progress = true;     // progress lines on stderr
    std::string mode = "run";
    // When resuming: the stage log the checkpoint carried (CheckpointHeader::history), so the
    // report and later checkpoints still list the stages finished before it. Null otherwise.
    nlohmann::json resumed_stage_log;
    // The observer, the modifiers and stage_finished run every `observe_every` steps: 1 for
    // per-step statistics; larger keeps the fused multi-step integrator pass.
    long observe_every = 1;
    std::vector<Modifier> modifiers;  // in the order they apply
    // Checked at each observation: true ends the current stage early (a mode's stopping
    // criterion, such as flow arrest). The stage log records the steps actually run.
    std::function<bool(const System&, std::size_t stage)> stage_finished;
    // A mode whose protocol keeps state outside the engine (a jam run's flux count and arrest
    // window) returns it here; every checkpoint then stores the object
    //     {"mode": MODE, "stage_log": [...], "state": checkpoint_state()}
    // as its history instead of the bare stage log, so the mode can resume exactly.
    std::function<nlohmann::json()> checkpoint_state;
    // true: a checkpoint at the end of every stage too, so a finished stage is never run again
    // (the shear cell's rates); by default only by wall time, step count and on interrupt.
    bool checkpoint_each_stage = false;
};

// What a run stepped: its steps, its grain-steps (summed chunk by chunk, as grains may leave) and
// its wall time from the first step.
struct RunSpeed {
    long steps_run = 0;
    double grain_steps = 0;
    double wall_s = 0;
};

// The reports' `performance` block of `speed` on `threads` threads.
nlohmann::json performance_json(const RunSpeed& speed, int threads);

struct RunOutcome {
    nlohmann::json report;
    int exit_status = 0;  // 0 complete, 130 interrupted (checkpoint written), 3 blow-up
    RunSpeed speed;
};

// Called after every `RunOptions::observe_every` steps; a mode uses it to observe (flux, stress
// samples). It reads the state only (a change is a Modifier's). It receives the stage index and
// the step within the stage.
using StepObserver = std::function<void(const System&, std::size_t stage, long step_in_stage)>;

// Runs from `start` (the beginning, or a checkpoint's position after restore_state).
RunOutcome run_protocol(Scene& scene, const RunOptions& options, ProtocolPosition start = {},
                        const StepObserver& observer = {});

// Creates a run's output directory, or throws SceneError(`json_path`) saying why it cannot be.
void prepare_output_directory(const std::string& directory, const std::string& json_path);
// Checks, before a run, that its checkpoint can be written at `path` (its directory created and
// writable, the path not a directory): found out at Ctrl-C, the run would end with nothing saved.
void check_checkpoint_path(const std::string& path, const std::string& json_path);
// Where a run writes its checkpoint when its scene names no path: DIRECTORY/checkpoint.mrjam.
std::string default_checkpoint_path(const std::string& output_directory);
// Deletes the checkpoint of a run that completed: resumed, it would only run the end again.
void discard_checkpoint(const std::string& path);

// Writes a JSON file atomically (temporary file, then rename).
void write_json_file(const std::string& path, const nlohmann::json& value);

}  // namespace mrjam
