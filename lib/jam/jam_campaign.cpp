#include "jam/jam_campaign.hpp"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>

#include "core/exit_status.hpp"
#include "core/format.hpp"
#include "jam/continuum_tier.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_results.hpp"
#include "jam/jam_run.hpp"
#include "jam/seed_tally.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

namespace {

using nlohmann::json;

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
int run_continuum_tier(const JamCampaignRequest& req, const JamScene& scene) {
    if (req.seeds_given || !req.snapshots.empty())
        throw SceneError(req.seeds_given ? "--seeds" : "--snapshots",
                         "the continuum tier has no grains (no packing to seed, nothing to snapshot): drop it");
    const auto start = std::chrono::steady_clock::now();
    json report = {{"mrjam_version", MRJAM_VERSION}, {"mode", "jam"},
                   {"status", "complete"},           {"scene_file", req.scene_path},
                   {"inputs_jam", scene.resolved},   {"fidelity", {{"jam_tier", "continuum"}}},
                   {"warnings", json::array()}};
    report["results"] = continuum_results(scene, report["warnings"]);
    report["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_json_file(req.report_path, report);
    if (req.progress) {
        for (const auto& w : report["warnings"]) std::cerr << "[jam] warning: " << w.get<std::string>() << "\n";
        const json& r = report["results"];
        std::cerr << "[jam] continuum: " << r["outcome"].get<std::string>() << "; the plug holds "
                  << format_number(r["continuum"]["hold_pressure_Pa"].get<double>() / 1e3, 3)
                  << " kPa against a supply of " << format_number(scene.flow.supply_pressure / 1e3, 3)
                  << " kPa; report " << req.report_path << "\n";
    }
    return kExitOk;
}

// The record of the seeds, written into every checkpoint so a resumed campaign knows the scene,
// which seed was running and what the seeds before it gave: the checkpoint's, or a fresh one.
json campaign_record(const JamCampaignRequest& req) {
    if (!req.resume.empty()) {
        if (!req.snapshots.empty() || !req.snapshot_every.empty())
            throw SceneError("--snapshots",
                             "a resumed run keeps the snapshot settings of the interrupted one; drop "
                             "--snapshots/--snapshot-every");
        JamCheckpoint checkpoint = read_jam_checkpoint(req.resume);
        // A campaign-only checkpoint has no engine state: its seed starts afresh (JamCampaign::run).
        if (checkpoint.campaign_only) checkpoint.campaign["start_afresh"] = true;
        return checkpoint.campaign;
    }
    const std::string base = std::filesystem::absolute(req.scene_path).parent_path().string();
    return {{"scene", req.scene}, {"tier", req.fidelity},  {"base_directory", base},  {"seeds", req.seeds},
            {"seed_index", 0},    {"runs", json::array()}, {"first_report", nullptr}, {"snapshots", req.snapshots}};
}

// The prescribed flow does not use a supply pressure (the design's open-flow estimate does, so
// this is the jam command's check): given, it would be echoed as if it were.
void check_supply_pressure_used(const json& campaign, const JamScene& scene) {
    const json& fluid_in = campaign["scene"].value("fluid", json::object());
    if (!scene.flow.pressure_driven && fluid_in.is_object() && fluid_in.contains("supply_pressure"))
        throw SceneError("/fluid/supply_pressure",
                         "drives the pressure-driven flows only, and fluid/flow is \"prescribed\": "
                         "give fluid/flow \"pressure\" or \"coupled\", or drop it");
}

class JamCampaign {
public:
    JamCampaign(const JamCampaignRequest& req, json campaign, const JamScene& scene)
        : req_(req), campaign_(std::move(campaign)), scene_(scene), seeds_(campaign_["seeds"].get<int>()) {
        first_seed_ = scene.engine_scene["seed"].get<long long>();
        if (first_seed_ > std::numeric_limits<long long>::max() - (seeds_ - 1))
            throw SceneError("/seed", "seed + --seeds - 1 overflows a 64-bit seed: give a smaller seed");
    }

    int run() {
        const int first_index = campaign_.at("seed_index").get<int>();
        const bool afresh = campaign_.value("start_afresh", false);
        campaign_.erase("start_afresh");
        report_ = campaign_["first_report"];
        for (int k = first_index; k < seeds_; ++k) {
            const std::string resume = k == first_index && !afresh ? req_.resume : "";
            if (const int status = run_seed(k, resume); status != kExitOk) return status;
        }
        return finish();
    }

private:
    JamRunOptions seed_options(int k, const std::string& resume_checkpoint) {
        JamRunOptions options;
        options.threads = req_.threads;
        options.progress = req_.progress;
        const std::filesystem::path report_path(req_.report_path);
        if (k == 0)
            options.picture_path = (report_path.parent_path() / (report_path.stem().string() + "_throat.png")).string();
        options.snapshot_directory = campaign_["snapshots"].get<std::string>();
        options.snapshot_every = campaign_["snapshot_every_s"].get<double>();
        campaign_["seed_index"] = k;
        options.campaign = campaign_;
        options.resume_checkpoint = resume_checkpoint;
        return options;
    }

    int run_seed(int k, const std::string& resume_checkpoint) {
        const long long seed = first_seed_ + k;
        if (req_.progress)
            std::cerr << "[jam] " << (resume_checkpoint.empty() ? "seed " : "resuming seed ") << seed << " (" << k + 1
                      << "/" << seeds_ << ")\n";
        JamOutcome outcome;
        if (req_.before_seed) req_.before_seed(k);
        try {
            outcome = run_jam(scene_, seed, seed_options(k, resume_checkpoint));
        } catch (const SetupInterrupted&) {
            // Ctrl-C while this seed placed its grains: with no seed done there is nothing to
            // keep (exit 130 at once); after one, keep the seeds done (write_campaign_checkpoint).
            if (campaign_["runs"].empty()) throw;
            return stopped_placing(k);
        }
        const json record = jam_seed_record(outcome, seed);
        campaign_["runs"].push_back(record);
        // Each seed's answer as it comes: a campaign of eight seeds runs for hours.
        if (req_.progress && seeds_ > 1 && outcome.exit_status == 0)
            std::cerr << "[jam] seed " << seed << ": " << seed_summary(record) << "\n";
        if (k == 0) report_ = outcome.report;
        if (outcome.exit_status != 0) return stopped(outcome, k);
        if (k == 0) campaign_["first_report"] = report_;
        return kExitOk;
    }

    // A seed that stopped (interrupted, blew up): its partial report, with the seeds so far.
    int stopped(const JamOutcome& outcome, int k) const {
        json partial = outcome.report;
        partial["seeds"] = campaign_["runs"];
        partial["inputs_jam"] = scene_.resolved;
        if (outcome.exit_status == kExitInterrupted)
            partial["resume_note"] = "--resume continues seed " + std::to_string(first_seed_ + k) +
                                     " where it stopped, then runs the " + std::to_string(seeds_ - k - 1) +
                                     " remaining seed(s)";
        write_json_file(req_.report_path, partial);
        std::cerr << "[jam] stopped (" << outcome.report["status"].get<std::string>() << "); partial report "
                  << req_.report_path << "\n";
        // Say why: a blow-up's cause and its fixes are in the report's "error".
        if (outcome.report.contains("error"))
            std::cerr << "[jam] " << outcome.report["error"].get<std::string>() << "\n";
        return outcome.exit_status;
    }

    // Interrupted while seed k placed its grains, after earlier seeds finished: the campaign's
    // record goes where the seed's checkpoint would have, so the usual --resume starts seed k.
    int stopped_placing(int k) {
        const std::string checkpoint =
            default_checkpoint_path(scene_.engine_scene["output"]["directory"].get<std::string>());
        const std::string resume_with = "mrjam jam --resume " + checkpoint + " --report " + req_.report_path;
        campaign_["seed_index"] = k;
        std::filesystem::create_directories(std::filesystem::path(checkpoint).parent_path());
        write_campaign_checkpoint(checkpoint, campaign_);
        json partial = report_;
        partial["status"] = "interrupted";
        partial["partial"] = true;
        partial["seeds"] = campaign_["runs"];
        partial["inputs_jam"] = scene_.resolved;
        partial["resume_note"] = "--resume starts seed " + std::to_string(first_seed_ + k) + " afresh (Ctrl-C came " +
                                 "while it placed its grains), then runs the " + std::to_string(seeds_ - k - 1) +
                                 " remaining seed(s)";
        partial["resume_with"] = resume_with;
        write_json_file(req_.report_path, partial);
        std::cerr << "[jam] interrupted while seed " << first_seed_ + k << " placed its grains; the " << k
                  << " seed(s) done are kept in " << checkpoint << "; continue with: " << resume_with << "\n";
        return kExitInterrupted;
    }

    // The report is seed 1's with the seeds' tally. A seed counts as a jam when its arrest
    // stopped the flow (with a hold: and held); the time to arrest is every arrest's, held or not.
    void write_tally(const SeedTally& tally) {
        const json& runs = campaign_["runs"];
        const std::vector<double>& times = tally.arrest_times;
        double mean = 0, spread = 0;
        for (double t : times) mean += t / times.size();
        for (double t : times) spread += (t - mean) * (t - mean) / std::max<std::size_t>(1, times.size() - 1);
        report_["inputs_jam"] = scene_.resolved;
        report_["seeds"] = runs;
        // The other seeds' warnings (a sparse window in seed 3, say) would otherwise reach stderr
        // only, and with --quiet nowhere.
        for (std::size_t k = 1; k < runs.size(); ++k)
            for (const auto& w : runs[k].value("warnings", json::array()))
                report_["warnings"].push_back("seed " + std::to_string(runs[k]["seed"].get<long long>()) + ": " +
                                              w.get<std::string>());
        report_["results"].update(seed_probabilities(tally));
        report_["results"]["time_to_arrest_mean_s"] = times.empty() ? json(nullptr) : json(mean);
        report_["results"]["time_to_arrest_std_s"] = times.size() < 2 ? json(nullptr) : json(std::sqrt(spread));
        report_["fidelity"]["jam_tier"] = scene_.tier;
        report_["fidelity"]["slab_half_thickness_m"] = scene_.slab_half_thickness;
        // What the engine did, not what the scene resolves to now.
        report_["fidelity"]["magnetic_update_interval"] = report_["results"]["magnetic"]["update_interval_steps"];
        if (report_["results"].contains("carrier_flow"))
            report_["fidelity"]["flow_lookup_interval"] = report_["results"]["carrier_flow"]["lookup_interval_steps"];
        if (!req_.resume.empty()) report_["resumed_from"] = req_.resume;
        write_json_file(req_.report_path, report_);
    }

    void print_answer() const {
        const json& res = report_["results"];
        std::cerr << "[jam] " << res["outcome"].get<std::string>() << " (jam probability "
                  << res["jam_probability"].get<double>() << ", 95 % interval " << std::fixed << std::setprecision(2)
                  << res["jam_probability_95ci"][0].get<double>() << " to "
                  << res["jam_probability_95ci"][1].get<double>() << std::defaultfloat << std::setprecision(6)
                  << "; arrest probability " << res["arrest_probability"].get<double>() << ")";
        // A flow the field did not stop: how much of it still got through at the end.
        if (res["jammed"] == false && res["flux_share_last_window"].is_number())
            std::cerr << "; grain flux over the last " << res["flux_share_with_field"]["window_s"].get<double>() * 1e3
                      << " ms of field at " << std::lround(100 * res["flux_share_last_window"].get<double>())
                      << " % of the no-field flux";
        std::cerr << "; report " << req_.report_path << "\n";
    }

    int finish() {
        const SeedTally tally = tally_seeds(campaign_["runs"]);
        write_tally(tally);
        if (tally.judged < seeds_)
            std::cerr
                << "[jam] warning: " << seeds_ - tally.judged << " of " << seeds_
                << " seed(s) undetermined (no grain crossed the throat without field; see the report's warnings), "
                   "left out of the probabilities\n";
        if (tally.judged == 0) {  // nothing was measured: not a result to build on
            std::cerr << "[jam] no seed could be judged; report " << req_.report_path << "\n";
            return kExitError;
        }
        if (req_.progress) print_answer();
        return kExitOk;
    }

    const JamCampaignRequest& req_;
    json campaign_;
    const JamScene& scene_;
    int seeds_;
    long long first_seed_ = 0;
    json report_;
};

}  // namespace

int run_jam_campaign(const JamCampaignRequest& req) {
    json campaign = campaign_record(req);
    const JamScene scene = read_jam_scene(campaign["scene"], campaign["tier"].get<std::string>(),
                                          campaign["base_directory"].get<std::string>());
    if (req.resume.empty()) check_supply_pressure_used(campaign, scene);
    if (scene.tier == "continuum") return run_continuum_tier(req, scene);
    if (req.snapshots.empty() && !req.snapshot_every.empty())
        throw SceneError("--snapshot-every", "sets the interval of --snapshots DIR: give that too, or drop it");
    if (req.resume.empty())
        campaign["snapshot_every_s"] = req.snapshots.empty() ? 0.0 : snapshot_interval(req.snapshot_every, scene);
    return JamCampaign(req, std::move(campaign), scene).run();
}

}  // namespace mrjam
