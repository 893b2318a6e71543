// `mrjam asteroid MODE SCENE.json --report R.json`: magnetised rubble piles (docs/asteroid.md).
// MODE `scaling`: the forces between two touching grains against their radius (surface gravity,
// self-gravity, cohesion, magnetism), where they cross, and section 4.5's claims; instant.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "asteroid/scaling_spec.hpp"
#include "asteroid/scaling_study.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "run/runner.hpp"

namespace mrjam::cli {

namespace {

struct AsteroidArgs {
    std::string mode;
    std::string scene;
    std::string report = "asteroid_report.json";
    bool quiet = false;
};

// REPORT.json -> REPORT_forces.svg, next to it.
std::string plot_path(const std::string& report) {
    std::filesystem::path p(report);
    return (p.parent_path() / (p.stem().string() + "_forces.svg")).string();
}

void print_claims(const nlohmann::json& results) {
    for (const auto& c : results["claims"])
        std::cerr << "[asteroid] " << (c["holds"].get<bool>() ? "holds:    " : "does not: ")
                  << c["claim"].get<std::string>() << "\n";
}

void run_scaling(const AsteroidArgs& args) {
    const nlohmann::json scene = read_json_file(args.scene);
    const ScalingSpec spec = read_scaling_spec(scene);
    nlohmann::json report;
    report["mrjam_version"] = MRJAM_VERSION;
    report["mode"] = "asteroid scaling";
    report["scene_file"] = args.scene;
    report["inputs"] = spec.resolved;
    report["results"] = scaling_results(spec);
    report["notes"] = {
        "Self-gravity of two touching equal spheres is G m^2 / (2R)^2 (two_spheres, the default); the source's "
        "Eq. 4.14 (printed) is four times smaller.",
        "Every force is a power law of R, so crossovers are closed forms; magnetism decides the bands with the "
        "dominance_model named in results."};
    const std::string svg = plot_path(args.report);
    write_scaling_plot(spec, svg);
    report["plots"] = {{"forces", svg}};
    write_json_file(args.report, report);
    if (!args.quiet) print_claims(report["results"]);
    std::cerr << "[asteroid] scaling; report written to " << args.report << "\n";
}

}  // namespace

void add_asteroid_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<AsteroidArgs>();
    CLI::App* cmd = app.add_subcommand("asteroid", "Magnetised rubble piles: force scaling against grain size");
    cmd->add_option("mode", args->mode, "scaling: forces between two touching grains against their radius")
        ->required()
        ->check(CLI::IsMember({"scaling"}));
    cmd->add_option("scene", args->scene, "Asteroid scene JSON file (see docs/asteroid.md)")->required();
    cmd->add_option("--report", args->report, "Where to write the JSON report (the plot goes next to it)")
        ->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "Only the report's path on stderr");
    cmd->callback([args, &exit_status] {
        prepare_output_file(args->report, "--report", {args->scene});
        run_scaling(*args);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
