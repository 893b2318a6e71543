// `mrjam jam SCENE.json --report R.json [--seeds N]`: will this fluid jam in this constriction
// under this field, how fast, and does it let go when the field is switched off?
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/format.hpp"
#include "jam/continuum_tier.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_run.hpp"
#include "jam/seed_tally.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam::cli {

namespace {
struct JamArgs {
    std::string scene;
    std::string report = "jam_report.json";
    std::string fidelity = "standard";
    int seeds = 1;
    int threads = 1;
    bool quiet = false;
    std::string resume;
    std::string snapshots;
    std::string snapshot_every;
};

// Snapshot interval: a time with units ("0.1 ms") or plain seconds; by default 20 frames over
// the no-field and field periods.
double snapshot_interval(const std::string& text, const JamScene& scene) {
    if (text.empty()) return scene.protocol.longest_run_before_arrest() / 20.0;
    char* end = nullptr;
    double t = std::strtod(text.c_str(), &end);  // plain seconds
    if (end != text.c_str() + text.size()) {
        try {
            t = units::parse_as(text, units::time);
        } catch (const std::exception& e) {
            throw SceneError("--snapshot-every", std::string(e.what()) + "; give a time such as \"0.1 ms\"");
        }
    }
    if (!(t > 0) || !std::isfinite(t))
        throw SceneError("--snapshot-every", "must be a positive time, such as \"0.1 ms\"");
    // A frame of a large valve is tens of MB: more than a few thousand is a slip of units.
    const double run = scene.protocol.longest_run_before_arrest();
    constexpr double kMostFrames = 2000;
    if (run / t > kMostFrames)
        throw SceneError("--snapshot-every", "would write more than " + std::to_string(static_cast<int>(kMostFrames)) +
                                                 " snapshots over the run's " + format_number(run * 1e3) +
                                                 " ms; give an interval of at least " +
                                                 format_number(run / kMostFrames * 1e6) + " us");
    if (t > run)
        throw SceneError(
            "--snapshot-every",
            "is longer than the run (" + format_number(run * 1e3) +
                " ms before an arrest), so only the first frame would be written; give a shorter interval");
    return t;
}
// The continuum tier: a Bingham plug with the shear mode's yield stress, no grains (a second).
int run_continuum_tier(const JamArgs& args, const JamScene& scene, bool seeds_given) {
    if (seeds_given || !args.snapshots.empty())
        throw SceneError(seeds_given ? "--seeds" : "--snapshots",
                         "the continuum tier has no grains (no packing to seed, nothing to snapshot): drop it");
    const auto start = std::chrono::steady_clock::now();
    nlohmann::json report = {{"mrjam_version", MRJAM_VERSION},
                             {"mode", "jam"},
                             {"status", "complete"},
                             {"scene_file", args.scene},
                             {"inputs_jam", scene.resolved},
                             {"fidelity", {{"jam_tier", "continuum"}}},
                             {"warnings", nlohmann::json::array()}};
    report["results"] = continuum_results(scene, report["warnings"]);
    report["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_json_file(args.report, report);
    if (!args.quiet) {
        for (const auto& w : report["warnings"]) std::cerr << "[jam] warning: " << w.get<std::string>() << "\n";
        const nlohmann::json& r = report["results"];
        std::cerr << "[jam] continuum: " << r["outcome"].get<std::string>() << "; the plug holds "
                  << format_number(r["continuum"]["hold_pressure_Pa"].get<double>() / 1e3, 3)
                  << " kPa against a supply of " << format_number(scene.flow.supply_pressure / 1e3, 3)
                  << " kPa; report " << args.report << "\n";
    }
    return 0;
}
}  // namespace

void add_jam_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<JamArgs>();
    CLI::App* cmd = app.add_subcommand("jam", "Jam predictor: grains in the valve's throat under a field (DEM)");
    cmd->add_option("scene", args->scene, "Jam scene JSON (see docs/jam.md)");
    cmd->add_option("--resume", args->resume,
                    "Continue an interrupted run (and its remaining seeds) from its checkpoint");
    cmd->add_option("--snapshots", args->snapshots,
                    "Write VTK snapshots (grains with their contact cluster) into this directory");
    cmd->add_option("--snapshot-every", args->snapshot_every,
                    "Simulated time between snapshots, e.g. \"0.1 ms\" (default: 20 frames)");
    cmd->add_option("--report", args->report, "Where to write the JSON report")->capture_default_str();
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", args->fidelity,
                        "quick, standard or paper (DEM; scene settings win), or continuum (a Bingham plug)")
            ->check(CLI::IsMember(jam_tier_names()))
            ->capture_default_str();
    CLI::Option* seeds_option =
        cmd->add_option("--seeds", args->seeds, "Independent packings (seed, seed+1, ...): jam probability")
            ->check(CLI::Range(1, 1000))
            ->capture_default_str();
    cmd->add_option("--threads", args->threads, "OpenMP threads")->check(CLI::Range(1, 1024))->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    cmd->callback([args, fidelity, seeds_option, &exit_status] {
        if (args->scene.empty() == args->resume.empty())
            throw CLI::ValidationError("jam", "give a SCENE file, or --resume CHECKPOINT (not both)");
        // A resumed run finishes the protocol it started: another tier or seed count would not.
        if (!args->resume.empty() && (fidelity->count() > 0 || seeds_option->count() > 0))
            throw SceneError("--resume",
                             "the tier and the number of seeds come from the checkpoint; drop --fidelity and --seeds");
        prepare_output_file(args->report, "--report", {args->scene, args->resume});
        // From here on Ctrl-C or SIGTERM asks for a stop: one during the setup (a large valve packs
        // for a minute) is answered at the first step, with a checkpoint, instead of killing it.
        install_interrupt_handler();
        if (!args->snapshots.empty()) prepare_output_directory(args->snapshots, "--snapshots");
        // The record of the seeds: written into every checkpoint, so a resumed command knows the
        // scene, which seed was running and what the seeds before it gave.
        nlohmann::json campaign;
        int first_index = 0;
        std::string resume_checkpoint;
        if (!args->resume.empty()) {
            if (!args->snapshots.empty() || !args->snapshot_every.empty())
                throw SceneError("--snapshots",
                                 "a resumed run keeps the snapshot settings of the interrupted one; drop "
                                 "--snapshots/--snapshot-every");
            const JamCheckpoint ck = read_jam_checkpoint(args->resume);
            campaign = ck.campaign;
            first_index = campaign.at("seed_index").get<int>();
            resume_checkpoint = args->resume;
        } else {
            const std::string base = std::filesystem::absolute(args->scene).parent_path().string();
            campaign = {{"scene", read_json_file(args->scene)},
                        {"tier", args->fidelity},
                        {"base_directory", base},
                        {"seeds", args->seeds},
                        {"seed_index", 0},
                        {"runs", nlohmann::json::array()},
                        {"first_report", nullptr},
                        {"snapshots", args->snapshots}};
        }
        const JamScene scene = read_jam_scene(campaign["scene"], campaign["tier"].get<std::string>(),
                                              campaign["base_directory"].get<std::string>());
        // The prescribed flow does not use a supply pressure (the design's open-flow estimate
        // does, so this is the jam command's check): given, it would be echoed as if it were.
        const nlohmann::json& fluid_in = campaign["scene"].value("fluid", nlohmann::json::object());
        if (args->resume.empty() && !scene.flow.pressure_driven && fluid_in.is_object() &&
            fluid_in.contains("supply_pressure"))
            throw SceneError("/fluid/supply_pressure",
                             "drives the pressure-driven flows only, and fluid/flow is \"prescribed\": "
                             "give fluid/flow \"pressure\" or \"coupled\", or drop it");
        if (scene.tier == "continuum") {
            exit_status = run_continuum_tier(*args, scene, seeds_option->count() > 0);
            return;
        }
        const int seeds = campaign["seeds"].get<int>();
        if (args->snapshots.empty() && !args->snapshot_every.empty())
            throw SceneError("--snapshot-every", "sets the interval of --snapshots DIR: give that too, or drop it");
        if (args->resume.empty())
            campaign["snapshot_every_s"] =
                args->snapshots.empty() ? 0.0 : snapshot_interval(args->snapshot_every, scene);
        const long long first_seed = scene.engine_scene["seed"].get<long long>();
        if (first_seed > std::numeric_limits<long long>::max() - (seeds - 1))
            throw SceneError("/seed", "seed + --seeds - 1 overflows a 64-bit seed: give a smaller seed");
        const std::filesystem::path report_path(args->report);
        nlohmann::json report = campaign["first_report"];
        for (int k = first_index; k < seeds; ++k) {
            JamRunOptions options;
            options.threads = args->threads;
            options.progress = !args->quiet;
            if (k == 0)
                options.picture_path =
                    (report_path.parent_path() / (report_path.stem().string() + "_throat.png")).string();
            options.snapshot_directory = campaign["snapshots"].get<std::string>();
            options.snapshot_every = campaign["snapshot_every_s"].get<double>();
            campaign["seed_index"] = k;
            options.campaign = campaign;
            options.resume_checkpoint = k == first_index ? resume_checkpoint : "";
            if (!args->quiet)
                std::cerr << "[jam] " << (options.resume_checkpoint.empty() ? "seed " : "resuming seed ")
                          << first_seed + k << " (" << k + 1 << "/" << seeds << ")\n";
            const JamOutcome outcome = run_jam(scene, first_seed + k, options);
            nlohmann::json& runs = campaign["runs"];
            nlohmann::json record = jam_seed_record(outcome);
            record["seed"] = first_seed + k;
            record["status"] = outcome.report["status"];
            runs.push_back(record);
            // Each seed's answer as it comes: a campaign of eight seeds runs for hours.
            if (!args->quiet && seeds > 1 && outcome.exit_status == 0)
                std::cerr << "[jam] seed " << first_seed + k << ": " << seed_summary(record) << "\n";
            if (k == 0) report = outcome.report;
            if (outcome.exit_status != 0) {
                nlohmann::json partial = outcome.report;
                partial["seeds"] = runs;
                partial["inputs_jam"] = scene.resolved;
                if (outcome.exit_status == 130)
                    partial["resume_note"] = "--resume continues seed " + std::to_string(first_seed + k) +
                                             " where it stopped, then runs the " + std::to_string(seeds - k - 1) +
                                             " remaining seed(s)";
                write_json_file(args->report, partial);
                exit_status = outcome.exit_status;
                std::cerr << "[jam] stopped (" << outcome.report["status"].get<std::string>() << "); partial report "
                          << args->report << "\n";
                // Say why: a blow-up's cause and its fixes are in the report's "error".
                if (outcome.report.contains("error"))
                    std::cerr << "[jam] " << outcome.report["error"].get<std::string>() << "\n";
                return;
            }
            if (k == 0) campaign["first_report"] = report;
        }
        const nlohmann::json& runs = campaign["runs"];
        // A seed counts as a jam when its arrest stopped the flow (with a hold: and held); the time
        // to arrest is every arrest's, held or not.
        const SeedTally tally = tally_seeds(runs);
        const std::vector<double>& arrest_times = tally.arrest_times;
        double mean = 0, spread = 0;
        for (double t : arrest_times) mean += t / arrest_times.size();
        for (double t : arrest_times)
            spread += (t - mean) * (t - mean) / std::max<std::size_t>(1, arrest_times.size() - 1);
        report["inputs_jam"] = scene.resolved;
        report["seeds"] = runs;
        // The report is seed 1's with the seeds' tally: the other seeds' warnings (a sparse window
        // in seed 3, say) would otherwise reach stderr only, and with --quiet nowhere.
        for (std::size_t k = 1; k < runs.size(); ++k)
            for (const auto& w : runs[k].value("warnings", nlohmann::json::array()))
                report["warnings"].push_back("seed " + std::to_string(runs[k]["seed"].get<long long>()) + ": " +
                                             w.get<std::string>());
        report["results"].update(seed_probabilities(tally));
        report["results"]["time_to_arrest_mean_s"] =
            arrest_times.empty() ? nlohmann::json(nullptr) : nlohmann::json(mean);
        report["results"]["time_to_arrest_std_s"] =
            arrest_times.size() < 2 ? nlohmann::json(nullptr) : nlohmann::json(std::sqrt(spread));
        report["fidelity"]["jam_tier"] = scene.tier;
        report["fidelity"]["slab_half_thickness_m"] = scene.slab_half_thickness;
        // What the engine did, not what the scene resolves to now: a checkpoint from before held
        // forces resumes evaluating every step whatever the tier's default has become.
        report["fidelity"]["magnetic_update_interval"] = report["results"]["magnetic"]["update_interval_steps"];
        if (report["results"].contains("carrier_flow"))
            report["fidelity"]["flow_lookup_interval"] = report["results"]["carrier_flow"]["lookup_interval_steps"];
        if (!args->resume.empty()) report["resumed_from"] = args->resume;
        write_json_file(args->report, report);
        if (tally.judged < seeds)
            std::cerr
                << "[jam] warning: " << seeds - tally.judged << " of " << seeds
                << " seed(s) undetermined (no grain crossed the throat without field; see the report's warnings), "
                   "left out of the probabilities\n";
        if (tally.judged == 0) {  // nothing was measured: not a result to build on
            std::cerr << "[jam] no seed could be judged; report " << args->report << "\n";
            exit_status = kExitError;
            return;
        }
        if (!args->quiet) {
            const nlohmann::json& res = report["results"];
            std::cerr << "[jam] " << res["outcome"].get<std::string>() << " (jam probability "
                      << res["jam_probability"].get<double>() << ", 95 % interval " << std::fixed
                      << std::setprecision(2) << res["jam_probability_95ci"][0].get<double>() << " to "
                      << res["jam_probability_95ci"][1].get<double>() << std::defaultfloat << std::setprecision(6)
                      << "; arrest probability " << res["arrest_probability"].get<double>() << ")";
            // A flow the field did not stop: how much of it still got through at the end.
            if (res["jammed"] == false && res["flux_share_last_window"].is_number())
                std::cerr << "; grain flux over the last "
                          << res["flux_share_with_field"]["window_s"].get<double>() * 1e3 << " ms of field at "
                          << std::lround(100 * res["flux_share_last_window"].get<double>())
                          << " % of the no-field flux";
            std::cerr << "; report " << args->report << "\n";
        }
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
