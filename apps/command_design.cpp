// `mrjam design DESIGN.json --report R.json`: parses the command line and runs the design chain
// (design/design_workflow.hpp).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/machine_threads.hpp"
#include "design/design_workflow.hpp"

namespace mrjam::cli {

void add_design_command(CLI::App& app, int& exit_status) {
    auto req = std::make_shared<DesignRequest>();
    auto quiet = std::make_shared<bool>(false);
    CLI::App* cmd =
        app.add_subcommand("design", "Magnetics -> field map -> jam predictor, for a list of constrictions");
    cmd->add_option("scene", req->scene_path, "Design JSON (see docs/jam.md)")->required();
    cmd->add_option("--report", req->report_path, "Where to write the JSON report")->capture_default_str();
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", req->fidelity, "Tier for both models: quick, standard or paper")
            ->check(CLI::IsMember(std::vector<std::string>{"quick", "standard", "paper"}))
            ->capture_default_str();
    req->threads = kAutoThreads;  // chosen from the grains once they are placed (threads_for)
    cmd->add_option("--threads", req->threads, kThreadsHelp)->check(CLI::Range(1, 1024));
    cmd->add_flag("--quiet", *quiet, "No progress lines on stderr");
    cmd->add_flag("--resume", req->resume,
                  "Continue the interrupted design of this file: finished constrictions and solved fields are kept, "
                  "the running seed resumes from its checkpoint");
    cmd->callback([req, quiet, fidelity, &exit_status] {
        prepare_output_file(req->report_path, "--report", {req->scene_path});
        req->design = read_json_file(req->scene_path);
        req->fidelity_given = fidelity->count() > 0;
        req->progress = !*quiet;
        exit_status = run_design(*req);
    });
}

}  // namespace mrjam::cli
