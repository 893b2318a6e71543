#pragma once
// `mrjam sweep SWEEP.json --out DIR`: runs every point of a sweep (sweep_spec.hpp) as its own
// mrjam process, in DIR/points/pNNNN/ (its scene.json, report.json, log.txt and out/), and
// writes DIR/manifest.json (each point's state and attempts), DIR/table.json and DIR/table.csv.
//
// Resumable: each point's state lives in its own folder (state.json), written by whoever runs
// it, so an interrupted or killed sweep, rerun, skips the points done, resumes a point from its
// checkpoint where the mode writes one, and runs the rest; shards (--shard I/N) of one sweep on
// several machines never write the same file. DIR/sweep.json records the sweep file and the
// points' folders: a changed sweep file against it is refused with the differences named, unless
// --extend only adds points.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "sweep/point_process.hpp"
#include "sweep/sweep_spec.hpp"

namespace mrjam {

struct SweepOptions {
    std::string sweep_path, out_dir;
    int threads = 0;  // passed to each point's run; 0: the machine's cores (shared by the jobs), or 1 a rank under MPI
    int jobs = 1;     // point processes run side by side (not under mpirun: use more ranks)
    bool extend = false;        // accept a sweep file that adds points to DIR's
    bool yes = false;           // run more than kMostPointsUnasked points
    int shard = 0, shards = 1;  // run the points whose number % shards == shard
    bool collect = false;       // only assemble the table from the points' folders
    bool progress = true;
};

inline constexpr std::size_t kMostPointsUnasked = 100;

// Returns the exit status: 0 every point of this run done, 1 some failed (named in the manifest),
// 130 interrupted (rerun to continue). Throws SceneError for bad input (the CLI's exit 2).
int run_sweep(const SweepOptions& options);

// Runs one point whose folder exists and holds its scene.json; `while_waiting` is to be called
// often while it runs (an MPI leader answers the other ranks there). The point is done when it
// returns exit status 0 and its folder holds report.json.
using PointRunner = std::function<ProcessResult(const SweepPoint& point, const std::filesystem::path& folder,
                                                const std::function<void()>& while_waiting)>;

// How a sweep's points run and where they live. The defaults are `mrjam sweep`'s: each point its
// own mrjam process, in DIR/points/pNNNN, spread over mpirun's ranks. A mode that sweeps inside
// itself (the design over its constrictions, the shear mode over its field list) runs its points
// in its own process, in folders it names, in a directory that also holds its own files.
struct SweepEngine {
    std::string label = "sweep";              // of the progress lines: "[sweep] 2/8 ..."
    std::string points_directory = "points";  // the points' folders under DIR ("" for DIR itself)
    std::function<std::string(std::size_t n, const nlohmann::json& values)> folder_name;  // default pNNNN
    PointRunner run_point;                     // default: `mrjam MODE point/scene.json ...` as a process
    bool directory_holds_other_files = false;  // DIR is the mode's own output directory
    bool spread_over_ranks = true;             // under mpirun; else this process runs every point
    bool echo_output = false;                  // a point process's log lines also on stderr, as they come
};

// The sweep `spec` (already read) run into options.out_dir as `engine` says; the same statuses
// as run_sweep. `is_leader` (when given) says whether this process wrote the table.
int run_sweep_spec(const SweepSpec& spec, const SweepOptions& options, const SweepEngine& engine,
                   bool* is_leader = nullptr);

// Where the sweep recorded in `directory` differs from `source` ("/shear_input/field, ..."), or
// "" when there is none there or it is the same.
std::string sweep_changed_at(const std::filesystem::path& directory, const nlohmann::json& source);

// A point's state as the engine keeps it (DIR/<points>/<folder>/state.json): null if absent.
nlohmann::json read_point_state(const std::filesystem::path& folder);

}  // namespace mrjam
