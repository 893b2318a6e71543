#pragma once
// A scene read from its JSON file: the system to integrate and the protocol to run on it.
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/region.hpp"
#include "io/snapshot.hpp"
#include "system.hpp"
#include "timestep.hpp"

namespace mrjam {

// The Verlet skin's default, of the mean grain diameter (`run/skin`; the jam's `model/neighbour_skin`).
inline constexpr double kDefaultSkinFraction = 0.1;

using json = nlohmann::json;

// One phase of a protocol (settle, freeze the rafts, shear ...). Actions apply at its start.
struct Stage {
    struct RaftForm {
        std::string name;
        Region region;  // grains whose centres lie inside join the raft
        Vec3 velocity;
    };
    std::string name;
    long steps = -1;      // -1 until choose_timestep converts `duration`
    double duration = 0;  // s, when the scene gave a duration instead of steps
    std::string path;     // where the scene gave it: "/run" or "/stages/k"
    std::vector<RaftForm> form_rafts;
    std::vector<std::pair<std::string, Vec3>> raft_velocities;  // for rafts formed earlier
    std::vector<std::string> release;                           // rafts whose grains go free
    std::vector<std::pair<std::string, Vec3>> wall_velocities;
    // Plane walls taken away as the stage starts (a gate lifted): each is moved behind itself, far
    // out of every grain's reach, so the checkpoint's wall positions carry the removal.
    std::vector<std::string> remove_walls;
    std::shared_ptr<FlowField> flow;  // null: keep the current flow
    // A mode's own start actions, after the ones above (the shear cell freezes its rafts and sets
    // a rate's boundaries). `fresh` is false when a run resumes inside the stage: what changes the
    // grains is then in the checkpoint already, and only settings are to be applied again.
    std::function<void(System&, bool fresh)> on_start;
    // true: a fresh stage goes on from the forces and lists the previous stage left (a stage that
    // only changes settings, or whose on_start prepares the system itself); false: prepare() first.
    bool keep_forces = false;
    // > 0: the observer, modifiers and criterion run every `observe_every` steps counted from the
    // stage's first step, and at its last; 0: every RunOptions::observe_every steps of the run.
    long observe_every = 0;
};

struct OutputPlan {
    std::string directory = ".";
    bool snapshots = false;
    SnapshotFormat snapshot_format = SnapshotFormat::vtk_legacy;
    long snapshot_every = 0;
    long checkpoint_every_steps = 0;  // 0: by wall time (below) and on interrupt only
    double checkpoint_every_seconds = 600;
    std::string checkpoint_path;  // empty: <directory>/checkpoint.mrjam
    double progress_interval_s = 5;
};

struct Scene {
    System system;
    std::vector<Stage> stages;
    OutputPlan output;
    std::uint64_t seed = 1;
    double characteristic_speed = 1.0;
    double timestep_safety = 0.1;
    double requested_timestep = 0;                // 0: automatic
    double skin_fraction = kDefaultSkinFraction;  // Verlet skin as a fraction of the mean diameter
    int requested_threads = 0;                    // BuildOptions::threads (0: by the grains, threads_for)
    TimestepLimits limits;
    json resolved;  // the scene with every default filled in, SI numbers
    json fidelity;  // the tier and the defaults it implied
    std::vector<std::string> warnings;
    // Per /grains batch, the largest starting speed over radius of its grains (1/s; empty for a
    // resumed scene): once the step is known, a batch that would cross half a radius in a step is
    // named (the grains are sorted in space after placement, so batches are kept by this).
    std::vector<double> batch_speed_over_radius;
    long total_steps() const;
};

struct BuildOptions {
    bool insert_grains = true;          // false when a checkpoint supplies the grains
    int threads = 1;                    // kAutoThreads (0): chosen by choose_timestep from the grains (threads_for)
    std::string base_directory;         // relative file names in the scene (field maps) are taken from here
    std::string fidelity = "standard";  // tier whose defaults apply (scene settings win)
};

// Reads and checks a scene; throws SceneError (path + expectation) before any work on bad input.
Scene build_scene(const json& input, const BuildOptions& options);

// Sets the time step from the grains present (automatic, or the requested one after checking it
// against the stable limit; a SceneError names /run/timestep and the limit otherwise).
void choose_timestep(Scene& scene);

}  // namespace mrjam
