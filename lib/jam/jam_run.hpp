#pragma once
// One jam-prediction run: flow without field, field on until the throat's grain flux arrests
// (or the time runs out), then the field off to test the release (Table 3.2's
// "Fail-Irreversible" is a jam that stays). Results follow section 3.4.4 of the source.
#include <nlohmann/json.hpp>

#include "jam/jam_scene.hpp"

namespace mrjam {

struct JamRunOptions {
    int threads = 1;
    bool progress = true;
    std::string picture_path;  // "" for none
    // VTK snapshots (jam/jam_snapshots.hpp): "" for none; every `snapshot_every` seconds.
    std::string snapshot_directory;
    double snapshot_every = 0;
    // Continue from this checkpoint (jam/jam_checkpoint.hpp) instead of building fresh grains.
    std::string resume_checkpoint;
    // The command's record of the seeds, stored in every checkpoint for `--resume`.
    nlohmann::json campaign;
};

struct JamOutcome {
    nlohmann::json report;    // the engine's report with results.jam filled in
    int exit_status = 0;      // 0, 3 blow-up, 130 interrupted (partial flux history kept)
    bool jammed = false;      // the grain flux arrested with the field on
    bool stops_flow = false;  // ... and, with protocol/hold_time, stayed arrested over the hold
    double time_to_arrest = -1;
};

JamOutcome run_jam(const JamScene& scene, long long seed, const JamRunOptions& options);

// Its seed record and progress line: jam/jam_results.hpp.

}  // namespace mrjam
