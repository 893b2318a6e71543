// mrjam: design tool for jamming magnetorheological valves. This file only wires subcommands.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "integrator.hpp"
#include "scene/scene_node.hpp"

int main(int argc, char** argv) {
    CLI::App app{"mrjam " MRJAM_VERSION " - magnetorheological valve jamming design tool (DEM + magnetostatics)"};
    app.set_version_flag("--version", "mrjam " MRJAM_VERSION);
    app.require_subcommand(1);
    int exit_status = 0;
    mrjam::cli::add_run_command(app, exit_status);
    mrjam::cli::add_shear_command(app, exit_status);
    mrjam::cli::add_bench_command(app, exit_status);
    mrjam::cli::add_magnetics_command(app, exit_status);
    mrjam::cli::add_jam_command(app, exit_status);
    mrjam::cli::add_design_command(app, exit_status);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : mrjam::cli::kExitBadInput;
    } catch (const mrjam::SceneError& e) {
        std::cerr << "error in scene: " << e.what() << "\n";
        return mrjam::cli::kExitBadInput;
    } catch (const mrjam::BlowUp& e) {
        std::cerr << "error: " << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return mrjam::cli::kExitError;
    }
    return exit_status;
}
