// `mrjam asteroid MODE SCENE.json --report R.json`: magnetised rubble piles (docs/asteroid.md).
// MODE `scaling`: the forces between two touching grains against their radius (surface gravity,
// self-gravity, cohesion, magnetism), where they cross, and section 4.5's claims; instant.
// MODE `coalesce`: a cloud of grains collapsing under self-gravity into a body (section 4.2).
// MODE `spinup`: a body gathered from a cold cloud, spun up in steps until it deforms and sheds (4.3).
// MODE `avalanche`: a magnetised column let out from behind a gate in weak gravity: its heap (4.4).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "asteroid/asteroid_outcome.hpp"
#include "asteroid/avalanche_run.hpp"
#include "asteroid/coalesce_run.hpp"
#include "asteroid/scaling_spec.hpp"
#include "asteroid/scaling_study.hpp"
#include "asteroid/spinup_run.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "core/format.hpp"
#include "core/machine_threads.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

namespace {

struct AsteroidArgs {
    std::string mode;
    std::string scene;
    std::string report = "asteroid_report.json";
    std::string resume;
    std::string fidelity = "quick";
    int threads = kAutoThreads;  // chosen from the grains once they are placed (threads_for)
    bool quiet = false;
};

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
    const std::string svg = plot_beside(args.report, "forces");
    write_scaling_plot(spec, svg);
    report["plots"] = {{"forces", svg}};
    write_json_file(args.report, report);
    if (!args.quiet) print_claims(report["results"]);
    std::cerr << "[asteroid] scaling; report written to " << args.report << "\n";
}

void print_simulation_summary(const std::string& mode, const nlohmann::json& r) {
    if (mode == "coalesce") {
        const nlohmann::json& c = r["results"]["coalescence"];
        if (c.contains("final"))
            std::cerr << "[asteroid] body: " << format_number(100 * c["final"]["body_mass_fraction"].get<double>(), 3)
                      << " % of the mass, porosity " << format_number(c["final"]["porosity"].get<double>(), 3)
                      << ", outside it in chains or clumps "
                      << format_number(100 * c["final"]["outside_in_chains_or_clumps"].get<double>(), 3) << " %\n";
        return;
    }
    if (mode == "avalanche") {
        const nlohmann::json& a = r["results"]["avalanche"];
        auto angle = [&](const char* key) {
            const nlohmann::json& v = a[key]["angle_deg"];
            return v.is_null() ? std::string("not found") : format_number(v.get<double>(), 3) + " deg";
        };
        std::cerr << "[asteroid] angle of repose " << angle("angle_of_repose") << " (upper " << angle("upper_slope")
                  << ", lower " << angle("lower_slope") << "), heap "
                  << format_number(a["heap_volume_m3"].get<double>(), 3) << " m3\n";
        return;
    }
    const nlohmann::json& u = r["results"]["spin_up"];
    auto spin = [&](const char* key) {
        return u.contains(key) && !u[key].is_null() ? format_number(u[key].get<double>() * 1e6, 4) + " urad/s"
                                                    : std::string("none");
    };
    std::cerr << "[asteroid] first deformation: " << spin("first_deformation_rad_s")
              << "; first disruption: " << spin("first_disruption_rad_s")
              << "; rigid-sphere limit: " << spin("rigid_sphere_limit_rad_s") << "\n";
}

// `coalesce` and `spinup`: simulations on the engine, with checkpoints and --resume.
int run_simulation(const AsteroidArgs& args, bool fidelity_given) {
    CoalesceOptions options;
    options.scene_path = args.resume.empty() ? args.scene : args.resume;
    options.report_path = args.report;
    options.fidelity = args.fidelity;
    options.threads = args.threads;
    options.progress = !args.quiet;
    CoalesceOutcome out;
    if (!args.resume.empty()) {
        if (fidelity_given) throw SceneError("--fidelity", "a resumed run keeps the tier it was started with");
        out = args.mode == "coalesce" ? resume_coalescence(args.resume, options)
              : args.mode == "spinup" ? resume_spinup(args.resume, options)
                                      : resume_avalanche(args.resume, options);
    } else {
        const nlohmann::json scene = read_json_file(args.scene);
        out = args.mode == "coalesce" ? run_coalescence(read_coalesce_spec(scene, args.fidelity), options)
              : args.mode == "spinup" ? run_spinup(read_spinup_spec(scene, args.fidelity), options)
                                      : run_avalanche(read_avalanche_spec(scene, args.fidelity), options);
    }
    const nlohmann::json& r = out.report;
    if (out.exit_status == 3) std::cerr << "error: " << r.value("error", std::string("blow-up")) << "\n";
    print_simulation_summary(args.mode, r);
    std::cerr << "[asteroid] " << args.mode << " " << r.value("status", std::string("?")) << "; report written to "
              << args.report << "\n";
    return out.exit_status;
}

}  // namespace

void add_asteroid_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<AsteroidArgs>();
    CLI::App* cmd =
        app.add_subcommand("asteroid", "Magnetised rubble piles: force scaling, coalescence, spin-up, avalanches");
    cmd->add_option("mode", args->mode,
                    "scaling: forces between two touching grains against their radius; coalesce: a cloud "
                    "collapsing into a body under self-gravity; spinup: a body spun up in steps to failure; avalanche: "
                    "a magnetised column run out in weak gravity")
        ->required()
        ->check(CLI::IsMember({"scaling", "coalesce", "spinup", "avalanche"}));
    cmd->add_option("scene", args->scene, "Asteroid scene JSON file (see docs/asteroid.md)");
    cmd->add_option("--resume", args->resume, "coalesce, spinup, avalanche: continue from a checkpoint the mode wrote");
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", args->fidelity,
                        "coalesce, spinup: quick (4,000 grains) or standard/paper (the source's 32,662)")
            ->check(CLI::IsMember({"quick", "standard", "paper"}))
            ->capture_default_str();
    cmd->add_option("--threads", args->threads, kThreadsHelp)->check(CLI::Range(1, 1024));
    cmd->add_option("--report", args->report, "Where to write the JSON report (the plot goes next to it)")
        ->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "Only the report's path on stderr");
    cmd->callback([args, fidelity, &exit_status] {
        if (args->scene.empty() == args->resume.empty())
            throw CLI::ValidationError("asteroid", "give a SCENE file, or --resume CHECKPOINT (not both)");
        if (args->mode == "scaling" && !args->resume.empty())
            throw SceneError("--resume", "the scaling mode is instant and writes no checkpoint");
        prepare_output_file(args->report, "--report", {args->scene, args->resume});
        if (args->mode == "scaling") {
            run_scaling(*args);
            exit_status = 0;
        } else {
            exit_status = run_simulation(*args, fidelity->count() > 0);
        }
    });
}

}  // namespace mrjam::cli
