#pragma once
// The benchmarks of `mrjam-bench` (timing and accuracy tables, not tests), each a subcommand.
#include <CLI/CLI.hpp>

namespace mrjam::cli {

// contact and restitution (bench/src/command_bench.cpp), then the three below.
void add_bench_commands(CLI::App& bench, int& exit_status);
// magnetic and magnetic-accuracy (bench/src/bench_magnetic.cpp).
void add_magnetic_bench_commands(CLI::App& bench, int& exit_status);
// flow (bench/src/bench_flow.cpp): the valve's carrier flows, per call and per update.
void add_flow_bench_command(CLI::App& bench, int& exit_status);
// sphere-pair (bench/src/bench_sphere_pair.cpp): the point dipoles' error between close spheres.
void add_sphere_pair_bench_command(CLI::App& bench, int& exit_status);
// sphere-pair-fem (bench/src/bench_sphere_pair_fem.cpp): the saturating pair force by finite elements.
void add_sphere_pair_fem_bench_command(CLI::App& bench, int& exit_status);
// gravity (bench/src/bench_gravity.cpp): the self-gravity tree's error and cost against direct summation.
void add_gravity_bench_command(CLI::App& bench, int& exit_status);

}  // namespace mrjam::cli
