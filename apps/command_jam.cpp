// `mrjam jam SCENE.json --report R.json [--seeds N]`: parses the command line and runs the
// campaign (lib/jam/jam_campaign.hpp): will this fluid jam in this constriction under this
// field, how fast, and does it let go when the field is switched off?
#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/machine_threads.hpp"
#include "jam/jam_campaign.hpp"
#include "jam/jam_scene.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

void add_jam_command(CLI::App& app, int& exit_status) {
    auto req = std::make_shared<JamCampaignRequest>();
    auto quiet = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand("jam", "Jam predictor: grains in the valve's throat under a field (DEM)");
    cmd->add_option("scene", req->scene_path, "Jam scene JSON (see docs/jam.md)");
    cmd->add_option("--resume", req->resume,
                    "Continue an interrupted run (and its remaining seeds) from its checkpoint");
    cmd->add_option("--snapshots", req->snapshots,
                    "Write VTK snapshots (grains with their contact cluster) into this directory");
    cmd->add_option("--snapshot-every", req->snapshot_every,
                    "Simulated time between snapshots, e.g. \"0.1 ms\" (default: 20 frames)");
    cmd->add_option("--report", req->report_path, "Where to write the JSON report")->capture_default_str();
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", req->fidelity,
                        "quick, standard or paper (DEM; scene settings win), or continuum (a Bingham plug)")
            ->check(CLI::IsMember(jam_tier_names()))
            ->capture_default_str();
    CLI::Option* seeds_option =
        cmd->add_option("--seeds", req->seeds, "Independent packings (seed, seed+1, ...): jam probability")
            ->check(CLI::Range(1, 1000))
            ->capture_default_str();
    req->threads = kAutoThreads;  // chosen from the grains once they are placed (threads_for)
    cmd->add_option("--threads", req->threads, kThreadsHelp)->check(CLI::Range(1, 1024));
    cmd->add_flag("--quiet", *quiet, "No progress lines on stderr");
    cmd->callback([req, quiet, fidelity, seeds_option, &exit_status] {
        if (req->scene_path.empty() == req->resume.empty())
            throw CLI::ValidationError("jam", "give a SCENE file, or --resume CHECKPOINT (not both)");
        // A resumed run finishes the protocol it started: another tier or seed count would not.
        if (!req->resume.empty() && (fidelity->count() > 0 || seeds_option->count() > 0))
            throw SceneError("--resume",
                             "the tier and the number of seeds come from the checkpoint; drop --fidelity and --seeds");
        prepare_output_file(req->report_path, "--report", {req->scene_path, req->resume});
        // From here on Ctrl-C or SIGTERM asks for a stop: one during the setup (a large valve packs
        // for a minute) is answered at the first step, with a checkpoint, instead of killing it.
        install_interrupt_handler();
        if (!req->snapshots.empty()) prepare_output_directory(req->snapshots, "--snapshots");
        if (req->resume.empty()) req->scene = read_json_file(req->scene_path);
        req->seeds_given = seeds_option->count() > 0;
        req->progress = !*quiet;
        exit_status = run_jam_campaign(*req);
    });
}

}  // namespace mrjam::cli
