// mrjam-bench: the benchmarks, apart from the product binary (docs/benchmarks.md gives their
// figures and how to run them side by side with LIGGGHTS).
#include <CLI/CLI.hpp>

#include "bench_commands.hpp"
#include "cli_common.hpp"

int main(int argc, char** argv) {
    mrjam::cli::ensure_passive_openmp_wait(argv);
    CLI::App app{"mrjam-bench " MRJAM_VERSION " - benchmarks of the mrjam engine (timing, not tests)"};
    app.set_version_flag("--version", "mrjam-bench " MRJAM_VERSION);
    app.require_subcommand(1);
    int exit_status = 0;
    mrjam::cli::add_bench_commands(app, exit_status);
    return mrjam::cli::run_cli(app, argc, argv, exit_status);
}
