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
#include <string>

namespace mrjam {

struct SweepOptions {
    std::string sweep_path, out_dir;
    int threads = 0;            // passed to each point's run; 0: the machine's cores, or 1 a rank under MPI
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

}  // namespace mrjam
