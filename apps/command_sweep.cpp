// `mrjam sweep SWEEP.json --out DIR`: any mode over parameter axes, resumable, shardable across
// machines (lib/sweep/sweep_run.hpp; docs/sweep.md).
#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "commands.hpp"
#include "scene/scene_node.hpp"
#include "sweep/sweep_run.hpp"

namespace mrjam::cli {
namespace {

// "I/N" -> shard I of N.
void parse_shard(const std::string& text, SweepOptions& o) {
    const auto slash = text.find('/');
    try {
        if (slash == std::string::npos) throw std::invalid_argument("no slash");
        std::size_t used_i = 0, used_n = 0;
        o.shard = std::stoi(text.substr(0, slash), &used_i);
        o.shards = std::stoi(text.substr(slash + 1), &used_n);
        if (used_i != slash || used_n != text.size() - slash - 1) throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
        throw SceneError("--shard", "\"" + text + "\" is not I/N, e.g. 0/4 for the first of four shards");
    }
}

}  // namespace

void add_sweep_command(CLI::App& app, int& exit_status) {
    auto o = std::make_shared<SweepOptions>();
    auto quiet = std::make_shared<bool>(false);
    auto shard = std::make_shared<std::string>();
    CLI::App* cmd = app.add_subcommand("sweep", "Any mode over parameter axes, each point its own run (resumable)");
    cmd->add_option("sweep", o->sweep_path, "Sweep JSON file (see docs/sweep.md)")->required();
    cmd->add_option("--out", o->out_dir, "The sweep's folder: points, manifest, table")->required();
    cmd->add_option("--threads", o->threads,
                    "OpenMP threads of each point's run (default: the machine's cores; 1 per MPI rank)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--jobs", o->jobs,
                    "Points run side by side (default 1; their threads share the machine's cores unless --threads)")
        ->check(CLI::Range(1, 1024));
    cmd->add_flag("--extend", o->extend, "Accept a sweep file that only adds points to the folder's");
    cmd->add_flag("--yes", o->yes, "Run a sweep of more than 100 points");
    cmd->add_option("--shard", *shard, "I/N: run only the points whose number modulo N is I");
    cmd->add_flag("--collect", o->collect, "Only assemble the table from the points' folders (after shards)");
    cmd->add_flag("--quiet", *quiet, "No progress lines on stderr");
    cmd->callback([o, quiet, shard, &exit_status] {
        if (!shard->empty()) parse_shard(*shard, *o);
        o->progress = !*quiet;
        exit_status = run_sweep(*o);
    });
}

}  // namespace mrjam::cli
