// `mrjam shear SCENE.json --report R.json`: the shear-cell calibration mode (docs/shear.md).
// Runs the study (lib/shear), writes the report and the flow-curve plot next to it, and with
// --calibrate fits named model parameters to measured flow-curve points.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/machine_threads.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"
#include "shear/calibration.hpp"
#include "shear/convergence.hpp"
#include "shear/shear_cell.hpp"
#include "shear/shear_plots.hpp"
#include "shear/shear_spec.hpp"
#include "shear/shear_tiers.hpp"

namespace mrjam::cli {

namespace {
struct ShearArgs {
    std::string scene;
    std::string report = "shear_report.json";
    std::string resume;
    std::string calibrate;
    std::vector<std::string> parameters;
    int max_runs = 8;
    bool converge = false;
    int jobs = 0;
    int threads = kAutoThreads;  // chosen from the grains once they are placed (threads_for)
    bool quiet = false;
    std::string fidelity = "standard";
};

nlohmann::json report_of(const ShearSpec& spec, const ShearOutcome& out, const std::string& scene_file, int threads) {
    nlohmann::json report;
    report["mrjam_version"] = MRJAM_VERSION;
    report["mode"] = "shear";
    report["scene_file"] = scene_file;
    report["seed"] = spec.seed;
    // The count the first cell ran on (chosen from its grains unless --threads); a checkpoint
    // written before it was recorded gives the one asked for.
    report["threads"] = out.engine.is_object() && out.engine.contains("threads")
                            ? out.engine["threads"].get<int>()
                            : (threads > 0 ? threads : machine_threads());
    report["inputs"] = spec.resolved;
    nlohmann::json fid = describe(shear_tier(spec.tier));
    // The first cell's engine scene (null from a checkpoint written before it was recorded there).
    auto engine = [&](const char* key) {
        return out.engine.is_object() ? out.engine.value(key, nlohmann::json()) : nlohmann::json();
    };
    fid["engine"] = engine("fidelity");
    fid["stiffness_scale_used"] = spec.stiffness_scale;
    fid["density_scale_used"] = spec.density_scale;
    if (spec.hold_magnetic_pull) fid["pull_holding"] = describe(spec.pull_holding);
    fid["heavier_below_diameter_m"] = spec.heavier_below;
    fid["heavier_grains_stokes_number"] = spec.heavier_stokes_number;
    report["fidelity"] = fid;
    report["timestep"] = engine("timestep");
    report["engine_scene"] = engine("inputs");
    report["status"] = out.status;
    report["partial"] = out.status != "complete";
    if (!out.error.empty()) report["error"] = out.error;
    if (!out.checkpoint.empty()) {
        report["checkpoint"] = out.checkpoint;
        report["resume_with"] = "mrjam shear --resume " + out.checkpoint + " --report REPORT.json";
    }
    report["results"] = out.results;
    report["wall_time_s"] = out.wall_time;
    report["performance"] = out.performance;
    return report;
}
// `--converge`: the study at every cell size and seed, its report and pictures.
int run_convergence_report(const ShearSpec& spec, const ShearOptions& options, const ShearArgs& args) {
    const ConvergenceOutcome out = run_convergence(spec, options);
    nlohmann::json report;
    report["mrjam_version"] = MRJAM_VERSION;
    report["mode"] = "shear-converge";
    report["scene_file"] = args.scene;
    report["inputs"] = spec.resolved;
    report["fidelity"] = describe(shear_tier(spec.tier));
    report["status"] = out.status;
    report["results"] = out.results;
    report["runs_directory"] = out.directory;
    if (out.status == "interrupted") report["resume_with"] = "the same command: finished runs are kept";
    report["wall_time_s"] = out.wall_time;
    report["plots"] = write_convergence_plots(args.report, report);
    write_json_file(args.report, report);
    const auto& r = report["results"];
    if (r["yield_stress_Pa"].is_number())
        std::fprintf(stderr, "[shear] %s: yield stress %.1f +- %.1f kPa (%s)\n", out.status.c_str(),
                     r["yield_stress_Pa"].get<double>() * 1e-3, r["yield_stress_error_Pa"].get<double>() * 1e-3,
                     r["converged"].get<bool>() ? "converged" : "not converged: the largest cell's");
    std::cerr << "[shear] convergence " << out.status << "; report written to " << args.report << "\n";
    return out.exit_status;
}

}  // namespace

void add_shear_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<ShearArgs>();
    CLI::App* cmd = app.add_subcommand(
        "shear", "Shear-cell calibration: flow curve, yield stress fits, field sweep, parameter fitting");
    cmd->add_option("scene", args->scene, "Shear scene JSON file (see docs/shear.md)");
    cmd->add_option("--report", args->report, "Where to write the JSON report (the plot goes next to it)")
        ->capture_default_str();
    cmd->add_option("--resume", args->resume, "Continue a study from its checkpoint (finished rates are not redone)");
    cmd->add_option("--calibrate", args->calibrate,
                    "Measured flow curve (JSON or CSV of shear rate in 1/s, stress in Pa) to fit parameters to");
    cmd->add_option("--parameter", args->parameters,
                    "With --calibrate: NAME=MIN:MAX, one or two of rolling_friction, friction, "
                    "cohesion_energy_density, field_scale, "
                    "or a JSON pointer into the shear scene such as /material/restitution");
    CLI::Option* max_runs = cmd->add_option("--max-runs", args->max_runs, "With --calibrate: most shear studies to run")
                                ->check(CLI::Range(2, 200))
                                ->capture_default_str();
    cmd->add_flag("--converge", args->converge,
                  "Run the study at several cell sizes and seeds (the scene's convergence block) and report the "
                  "yield stress each gives and where it stops changing; rerun to continue an interrupted one");
    CLI::Option* jobs = cmd->add_option("--jobs", args->jobs,
                                        "With --converge: runs side by side (default: the machine's cores, their "
                                        "threads sharing them unless --threads)")
                            ->check(CLI::Range(1, 1024));
    CLI::Option* threads = cmd->add_option("--threads", args->threads, kThreadsHelp)->check(CLI::Range(1, 1024));
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", args->fidelity, "Tier of defaults: quick, standard or paper (scene settings win)")
            ->check(CLI::IsMember(shear_tier_names()))
            ->capture_default_str();
    cmd->callback([args, fidelity, max_runs, jobs, threads, &exit_status] {
        if (jobs->count() > 0 && !args->converge)
            throw SceneError("--jobs", "sets how many runs of --converge go side by side: give --converge, or drop it");
        if (args->scene.empty() == args->resume.empty())
            throw CLI::ValidationError("shear", "give a SCENE file, or --resume CHECKPOINT (not both)");
        if (!args->calibrate.empty() && !args->resume.empty())
            throw CLI::ValidationError("shear",
                                       "--calibrate starts fresh studies; it cannot be combined with --resume");
        if (args->converge && (!args->resume.empty() || !args->calibrate.empty()))
            throw SceneError("--converge",
                             "runs its own studies (rerun it to continue): drop --resume and --calibrate");
        if (args->calibrate.empty() && !args->parameters.empty())
            throw SceneError("--parameter", "sets what --calibrate fits: give --calibrate DATA too, or drop it");
        if (args->calibrate.empty() && max_runs->count() > 0)
            throw SceneError("--max-runs",
                             "limits the studies --calibrate runs: give --calibrate DATA too, or drop it");
        // A resumed study finishes at the tier it started with.
        if (!args->resume.empty() && fidelity->count() > 0)
            throw SceneError("--fidelity", "a resumed study keeps the tier it was started with; drop --fidelity");
        prepare_output_file(args->report, "--report", {args->scene, args->resume, args->calibrate});
        // From here on Ctrl-C or SIGTERM asks for a stop: one during the setup (a cell packs its grains
        // first) is answered at the first step, with a checkpoint, instead of killing it.
        install_interrupt_handler();
        ShearOptions options;
        options.threads = args->threads;
        options.progress = !args->quiet;
        ShearSpec spec;
        if (!args->calibrate.empty()) {
            spec = read_shear_spec(read_json_file(args->scene), args->fidelity);
            const CalibrationData data = read_calibration_data(args->calibrate);
            const auto params = parse_calibration_parameters(args->parameters, spec);
            const nlohmann::json result = calibrate(spec, data, params, args->max_runs, options);
            nlohmann::json report = result;
            report["mrjam_version"] = MRJAM_VERSION;
            report["mode"] = "shear-calibrate";
            report["scene_file"] = args->scene;
            report["data_file"] = args->calibrate;
            report["inputs"] = spec.resolved;
            report["fidelity"] = describe(shear_tier(spec.tier));
            report["plots"] = {{"calibration", write_calibration_plot(args->report, report, data)}};
            write_json_file(args->report, report);
            std::cerr << "[shear] calibration " << report["status"].get<std::string>() << "; report written to "
                      << args->report << "\n";
            exit_status = report.value("exit_status", 0);
            return;
        }
        if (args->converge) {
            options.jobs = args->jobs;
            options.threads_given = threads->count() > 0;
            spec = read_shear_spec(read_json_file(args->scene), args->fidelity);
            exit_status = run_convergence_report(spec, options, *args);
            return;
        }
        ShearOutcome out;
        if (!args->resume.empty()) {
            out = resume_shear_study(args->resume, options, spec);
        } else {
            spec = read_shear_spec(read_json_file(args->scene), args->fidelity);
            if (spec.input.contains("convergence") && !args->quiet)
                std::cerr << "[shear] note: the scene's convergence block is read by --converge; running one study\n";
            out = run_shear_study(spec, options);
        }
        nlohmann::json report = report_of(spec, out, args->resume.empty() ? args->scene : args->resume, args->threads);
        const auto plots = write_shear_plots(args->report, report);
        report["plots"] = plots;
        write_json_file(args->report, report);
        if (out.exit_status == 3) std::cerr << "error: " << out.error << "\n";
        std::cerr << "[shear] " << out.status << "; report written to " << args->report << "\n";
        exit_status = out.exit_status;
    });
}

}  // namespace mrjam::cli
