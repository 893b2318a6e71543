#pragma once
// The `output` block, read with the same keys by every mode (docs/scene.md, "Output"):
//
//   "output": {"directory": "out/x", "progress_interval": "5 s",
//              "checkpoint": {"every_steps": 0, "every_seconds": "600 s", "path": "..."},
//              "snapshots": {"format": "vtk" | "vtp" | "lammps", "every": <steps>}}
//
// The flat keys of earlier versions (checkpoint_every_seconds, checkpoint_every_steps,
// snapshot_every_steps) are refused with the key that replaced them, and a mode that chooses its
// checkpoint's path itself refuses `checkpoint/path` with the reason.
#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

struct OutputBlock {
    std::string directory;
    double progress_interval = 5;     // s of wall time between progress lines
    long checkpoint_every_steps = 0;  // 0: by wall time and on Ctrl-C only
    double checkpoint_every_seconds = 600;
    std::string checkpoint_path;  // "": the mode's default
    bool snapshots = false;
    std::string snapshot_format = "vtk";
    long snapshot_every = 0;  // steps
};

// Reads `node` (the output block, or an empty stand-in when the scene has none). A non-empty
// `path_refusal` is why this mode refuses checkpoint/path.
OutputBlock read_output_block(SceneNode node, const std::string& default_directory,
                              const std::string& path_refusal = "");

// The engine scene's output block (docs/scene.md) for a mode that builds one.
nlohmann::json engine_output_json(const OutputBlock& out);

// The run loop's plan from the block, for a mode that builds its engine scene itself.
OutputPlan output_plan(const OutputBlock& out);

}  // namespace mrjam
