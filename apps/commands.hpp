#pragma once
// Each subcommand registers itself on the application; its callback sets the exit status.
#include <CLI/CLI.hpp>

namespace mrjam::cli {

void add_run_command(CLI::App& app, int& exit_status);
void add_magnetics_command(CLI::App& app, int& exit_status);  // apps/command_magnetics.cpp
void add_jam_command(CLI::App& app, int& exit_status);        // apps/command_jam.cpp
void add_design_command(CLI::App& app, int& exit_status);     // apps/command_design.cpp
void add_shear_command(CLI::App& app, int& exit_status);      // apps/command_shear.cpp, lib/shear/
void add_asteroid_command(CLI::App& app, int& exit_status);   // apps/command_asteroid.cpp, lib/asteroid/
void add_sweep_command(CLI::App& app, int& exit_status);      // apps/command_sweep.cpp, lib/sweep/

}  // namespace mrjam::cli
