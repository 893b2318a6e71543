#pragma once
// Each subcommand registers itself on the application; its callback sets the exit status.
#include <CLI/CLI.hpp>

namespace mrjam::cli {

void add_run_command(CLI::App& app, int& exit_status);
void add_bench_command(CLI::App& app, int& exit_status);
void add_magnetics_command(CLI::App& app, int& exit_status);  // apps/command_magnetics.cpp
void add_jam_command(CLI::App& app, int& exit_status);        // apps/command_jam.cpp
void add_design_command(CLI::App& app, int& exit_status);     // apps/command_design.cpp
void add_shear_command(CLI::App& app, int& exit_status);      // apps/command_shear.cpp, lib/shear/
// `bench magnetic` and `bench magnetic-accuracy` (apps/bench_magnetic.cpp), registered under `bench`.
void add_magnetic_bench_commands(CLI::App& bench, int& exit_status);
// `bench flow` (apps/bench_flow.cpp): the valve's carrier flows, per call and per update.
void add_flow_bench_command(CLI::App& bench, int& exit_status);
// `bench sphere-pair` (apps/bench_sphere_pair.cpp): the point dipoles' error between close spheres.
void add_sphere_pair_bench_command(CLI::App& bench, int& exit_status);

}  // namespace mrjam::cli
