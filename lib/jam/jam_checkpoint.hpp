#pragma once
// A jam run's checkpoint: the engine state plus, in its history (run/runner.hpp's
// checkpoint_state), the protocol's state (phase, no-field reference flux, arrest window, flux
// and flow-scale histories) and the command's record of the seeds (which seed was running, the
// outcomes of those before it), so `mrjam jam --resume` ends as the uninterrupted run.
#include <nlohmann/json.hpp>
#include <string>

#include "io/checkpoint.hpp"

namespace mrjam {

struct JamCheckpoint {
    // A campaign-only checkpoint (below): no engine state, the seed at `seed_index` starts afresh.
    bool campaign_only = false;
    CheckpointHeader header;
    nlohmann::json stage_log;  // the engine's stages finished so far
    nlohmann::json state;      // run_jam's protocol state
    nlohmann::json campaign;   // the command's record: scene, tier, seeds, runs so far
};

// Throws SceneError("--resume", ...) when the file is not a jam checkpoint.
JamCheckpoint read_jam_checkpoint(const std::string& path);

// Ctrl-C while a later seed places its grains comes before that seed has any state to keep, and
// the seeds before it left no checkpoint (a finished seed removes its own). This writes, where the
// seed's checkpoint would be, a small JSON file of the campaign's record alone (the seeds done, the
// one to start afresh), which `mrjam jam --resume` reads as it reads a checkpoint.
void write_campaign_checkpoint(const std::string& path, const nlohmann::json& campaign);

}  // namespace mrjam
