// `mrjam jam SCENE.json --report R.json [--seeds N]`: will this fluid jam in this constriction
// under this field, how fast, and does it let go when the field is switched off?
#include <cmath>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli_common.hpp"
#include "commands.hpp"
#include "jam/jam_run.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

namespace {
struct JamArgs {
    std::string scene;
    std::string report = "jam_report.json";
    std::string fidelity = "standard";
    int seeds = 1;
    int threads = 1;
    bool quiet = false;
};
}  // namespace

void add_jam_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<JamArgs>();
    CLI::App* cmd = app.add_subcommand("jam", "Jam predictor: grains in the valve's throat under a field (DEM)");
    cmd->add_option("scene", args->scene, "Jam scene JSON (see docs/jam.md)")->required();
    cmd->add_option("--report", args->report, "Where to write the JSON report")->capture_default_str();
    cmd->add_option("--fidelity", args->fidelity, "quick, standard or paper (scene settings win)")
        ->check(CLI::IsMember(jam_tier_names()))->capture_default_str();
    cmd->add_option("--seeds", args->seeds, "Independent packings (seed, seed+1, ...): jam probability")
        ->check(CLI::Range(1, 1000))->capture_default_str();
    cmd->add_option("--threads", args->threads, "OpenMP threads")->check(CLI::Range(1, 1024))->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    cmd->callback([args, &exit_status] {
        const std::string base = std::filesystem::path(args->scene).parent_path().string();
        const JamScene scene = read_jam_scene(read_json_file(args->scene), args->fidelity, base);
        const long long first_seed = scene.engine_scene["seed"].get<long long>();
        const std::filesystem::path report_path(args->report);
        nlohmann::json runs = nlohmann::json::array();
        nlohmann::json report;
        int jams = 0;
        std::vector<double> arrest_times;
        for (int k = 0; k < args->seeds; ++k) {
            JamRunOptions options;
            options.threads = args->threads;
            options.progress = !args->quiet;
            if (k == 0)
                options.picture_path = (report_path.parent_path() / (report_path.stem().string() + "_throat.png")).string();
            if (!args->quiet) std::cerr << "[jam] seed " << first_seed + k << " (" << k + 1 << "/" << args->seeds << ")\n";
            const JamOutcome outcome = run_jam(scene, first_seed + k, options);
            if (k == 0) report = outcome.report;
            runs.push_back({{"seed", first_seed + k}, {"outcome", outcome.report["results"]["outcome"]},
                            {"time_to_arrest_s", outcome.report["results"]["time_to_arrest_s"]},
                            {"status", outcome.report["status"]}});
            if (outcome.jammed) { ++jams; arrest_times.push_back(outcome.time_to_arrest); }
            if (outcome.exit_status != 0) {
                report = outcome.report;
                report["seeds"] = runs;
                report["inputs_jam"] = scene.resolved;
                write_json_file(args->report, report);
                exit_status = outcome.exit_status;
                std::cerr << "[jam] stopped (" << outcome.report["status"].get<std::string>() << "); partial report "
                          << args->report << "\n";
                return;
            }
        }
        double mean = 0, spread = 0;
        for (double t : arrest_times) mean += t / arrest_times.size();
        for (double t : arrest_times) spread += (t - mean) * (t - mean) / std::max<std::size_t>(1, arrest_times.size() - 1);
        report["inputs_jam"] = scene.resolved;
        report["seeds"] = runs;
        report["results"]["jam_probability"] = static_cast<double>(jams) / args->seeds;
        report["results"]["time_to_arrest_mean_s"] = arrest_times.empty() ? nlohmann::json(nullptr) : nlohmann::json(mean);
        report["results"]["time_to_arrest_std_s"] =
            arrest_times.size() < 2 ? nlohmann::json(nullptr) : nlohmann::json(std::sqrt(spread));
        report["fidelity"]["jam_tier"] = scene.tier;
        report["fidelity"]["slab_half_thickness_m"] = scene.slab_half_thickness;
        write_json_file(args->report, report);
        if (!args->quiet)
            std::cerr << "[jam] " << report["results"]["outcome"].get<std::string>() << " (jam probability "
                      << report["results"]["jam_probability"].get<double>() << "); report " << args->report << "\n";
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
