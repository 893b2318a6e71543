// `mrjam run SCENE.json --report REPORT.json`: the generic entry point. Runs any scene the
// engine can express; other modes build their scenes and call the same protocol runner.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/machine_threads.hpp"
#include "integrator.hpp"
#include "io/checkpoint.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/fidelity.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

namespace {
struct RunArgs {
    std::string scene;
    std::string report = "report.json";
    std::string resume;
    int threads = kAutoThreads;  // chosen from the grains once they are placed (threads_for)
    bool quiet = false;
    std::string fidelity = "standard";
};
}  // namespace

void add_run_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<RunArgs>();
    CLI::App* cmd = app.add_subcommand("run", "Run any scene file: DEM grains, walls, fluid, protocol stages");
    cmd->add_option("scene", args->scene, "Scene JSON file (see docs/scene.md)");
    cmd->add_option("--report", args->report, "Where to write the JSON report")->capture_default_str();
    cmd->add_option("--resume", args->resume, "Continue from a checkpoint written by an earlier run");
    cmd->add_option("--threads", args->threads, kThreadsHelp)->check(CLI::Range(1, 1024));
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", args->fidelity, "Tier of defaults: quick, standard or paper (scene settings win)")
            ->check(CLI::IsMember(fidelity_tier_names()))
            ->capture_default_str();
    cmd->callback([args, fidelity, &exit_status] {
        if (args->scene.empty() == args->resume.empty())
            throw CLI::ValidationError("run", "give a SCENE file, or --resume CHECKPOINT (not both)");
        // The checkpoint's scene holds the settings its tier resolved to; another tier would only relabel the report.
        if (!args->resume.empty() && fidelity->count() > 0)
            throw SceneError("--fidelity", "a resumed run keeps the tier it was started with; drop --fidelity");
        prepare_output_file(args->report, "--report", {args->scene, args->resume});
        // From here on Ctrl-C or SIGTERM asks for a stop: one during the setup (a dense scene packs its grains
        // first) is answered at the first step, with a checkpoint, instead of killing it.
        install_interrupt_handler();
        BuildOptions build;
        build.threads = args->threads;
        build.fidelity = args->fidelity;
        Scene scene;
        ProtocolPosition start;
        nlohmann::json resumed_stage_log;
        if (!args->resume.empty()) {
            const CheckpointHeader header = read_checkpoint_header(args->resume);
            // A mode's checkpoint carries protocol state `mrjam run` knows nothing of.
            if (header.history.is_object()) {
                const std::string mode =
                    header.history.value("mode", header.history.contains("shear_input") ? "shear" : "another mode");
                throw SceneError("--resume", args->resume + " was written by `mrjam " + mode +
                                                 "`; resume it with `mrjam " + mode + " --resume " + args->resume +
                                                 "`");
            }
            build.insert_grains = false;
            scene = build_scene(header.resolved_scene, build);
            restore_scene(args->resume, scene);
            start = header.position;
            resumed_stage_log = header.history;
            std::cerr << "[run] resuming from " << args->resume << " at step " << scene.system.step << "\n";
        } else {
            build.base_directory = std::filesystem::path(args->scene).parent_path().string();
            scene = build_scene(read_json_file(args->scene), build);
            choose_timestep(scene);
        }
        RunOptions options;
        options.scene_path = args->resume.empty() ? args->scene : args->resume;
        options.report_path = args->report;
        options.progress = !args->quiet;
        options.resumed_stage_log = resumed_stage_log;
        const RunOutcome outcome = run_protocol(scene, options, start);
        if (outcome.exit_status == 3) std::cerr << "error: " << outcome.report["error"].get<std::string>() << "\n";
        std::cerr << "[run] " << outcome.report["status"].get<std::string>() << "; report written to " << args->report
                  << "\n";
        exit_status = outcome.exit_status;
    });
}

}  // namespace mrjam::cli
