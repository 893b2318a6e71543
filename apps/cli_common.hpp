#pragma once
// Shared by the subcommands: reading a scene file and mapping failures to exit codes.
#include <CLI/CLI.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/exit_status.hpp"
#include "core/proportion_interval.hpp"
#include "scene/scene_file.hpp"

namespace mrjam::cli {

// Exit codes: 0 done, 1 internal or I/O error, 2 bad input (scene or command line),
// 3 the run blew up, 130 interrupted (checkpoint written).
using mrjam::kExitBadInput;
using mrjam::kExitError;
using mrjam::kExitInterrupted;

// OpenMP threads that spin at their barriers (libgomp's default) collapse when the machine has
// other work: two threads beside two busy jobs ran the chained magnetic bench 15 times slower
// than one thread. Unless the user chose a policy (OMP_WAIT_POLICY or GOMP_SPINCOUNT), this sets
// the passive one and re-executes the program, because libgomp reads it only when it loads (the
// process keeps its pid; if /proc/self/exe cannot be run, the program goes on as it is).
// docs/benchmarks.md, "Threads on a busy machine", measures both policies.
void ensure_passive_openmp_wait(char** argv);

// --threads, the same in every mode.
inline constexpr const char* kThreadsHelp =
    "OpenMP threads (default: one per 800 grains, at most the machine's cores, or OMP_NUM_THREADS)";

// Parses the command line and runs the chosen subcommand's callback, turning what it throws into
// the exit status: bad input (a CLI error, a SceneError naming the key) 2, a blow-up 3, another
// fault 1; otherwise the status the callback set.
int run_cli(CLI::App& app, int argc, char** argv, const int& exit_status);

// A report file named by a command-line option (`option`, e.g. "--report"): refused before any
// work if it is empty, a directory, under a file, or one of the command's `inputs` (the scene,
// the checkpoint: written over, the input would be lost); its directory is created. A long run
// must not find out at its end that its report cannot be written.
void prepare_output_file(const std::string& path, const std::string& option,
                         const std::vector<std::string>& inputs = {});

// A probability's interval in a report: [low, high].
inline nlohmann::json interval_json(const ProportionInterval& ci) { return nlohmann::json::array({ci.low, ci.high}); }

}  // namespace mrjam::cli
