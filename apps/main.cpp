// mrjam: design tool for jamming magnetorheological valves. This file only wires subcommands.
#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
    mrjam::cli::ensure_passive_openmp_wait(argv);
    CLI::App app{"mrjam " MRJAM_VERSION " - magnetorheological valve jamming design tool (DEM + magnetostatics)"};
    app.set_version_flag("--version", "mrjam " MRJAM_VERSION);
    app.require_subcommand(1);
    int exit_status = 0;
    mrjam::cli::add_run_command(app, exit_status);
    mrjam::cli::add_shear_command(app, exit_status);
    mrjam::cli::add_magnetics_command(app, exit_status);
    mrjam::cli::add_jam_command(app, exit_status);
    mrjam::cli::add_design_command(app, exit_status);
    mrjam::cli::add_asteroid_command(app, exit_status);
    mrjam::cli::add_sweep_command(app, exit_status);
    return mrjam::cli::run_cli(app, argc, argv, exit_status);
}
