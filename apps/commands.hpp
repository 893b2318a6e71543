#pragma once
// Each subcommand registers itself on the application; its callback sets the exit status.
#include <CLI/CLI.hpp>

namespace mrjam::cli {

void add_run_command(CLI::App& app, int& exit_status);
void add_bench_command(CLI::App& app, int& exit_status);
// `shear`: the shear-cell calibration mode (apps/command_shear.cpp, lib/shear/).
void add_shear_command(CLI::App& app, int& exit_status);
// `bench magnetic` and `bench magnetic-accuracy` (apps/bench_magnetic.cpp), registered under `bench`.
void add_magnetic_bench_commands(CLI::App& bench, int& exit_status);

}  // namespace mrjam::cli
