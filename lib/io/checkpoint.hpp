#pragma once
// Checkpoints: the resolved scene plus the full dynamic state (grains, contact history, walls,
// rafts, protocol position), enough to continue a run bit for bit.
#include <nlohmann/json.hpp>
#include <string>

#include "system.hpp"

namespace mrjam {

struct Scene;

struct ProtocolPosition {
    std::size_t stage = 0;       // index of the stage in progress
    long step_in_stage = 0;      // steps of it already done
    bool stage_started = false;  // its start actions were applied
};

// Writes atomically (temporary file, then rename), so an interrupted write never leaves a
// corrupt checkpoint behind, and durably (the file synced before the rename, its directory after).
void write_checkpoint(const std::string& path, const nlohmann::json& resolved_scene, const System& system,
                      const ProtocolPosition& position, const nlohmann::json& history);

struct CheckpointHeader {
    nlohmann::json resolved_scene;
    nlohmann::json history;  // observations recorded so far (e.g. a flux history)
    ProtocolPosition position;
    int version = 8;  // the file format (lib/io/checkpoint.cpp); only the current one is read
};

// Reads the scene part; restore_state then fills a system built from that scene. Both throw
// SceneError("--resume", ...) naming the file when it cannot be read.
CheckpointHeader read_checkpoint_header(const std::string& path);
void restore_state(const std::string& path, System& system);

// fsync of a file or a directory (a no-op for a path that cannot be opened).
void sync_to_disk(const std::string& path);

// The resume sequence every mode shares: into a scene built from the checkpoint's resolved scene
// without grains, the saved state; then the time step chosen for those grains; then the saved
// state again, since choosing the step rebuilds the neighbour lists and the checkpoint's lists
// and step must win for the run to go on bit for bit.
void restore_scene(const std::string& path, Scene& scene);

}  // namespace mrjam
