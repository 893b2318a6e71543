#include "design/constriction_run.hpp"

#include <chrono>
#include <iostream>
#include <optional>

#include "core/exit_status.hpp"
#include "core/format.hpp"
#include "design/design_progress.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_results.hpp"
#include "jam/jam_run.hpp"
#include "jam/open_flow.hpp"
#include "jam/seed_tally.hpp"
#include "magnetic/external_field.hpp"
#include "magnetics/field_picture.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Whether a constriction's jam checkpoint is of seed `k` of this design's scene for it.
bool resumes_seed(const JamCheckpoint& ck, const json& jscene, int k) {
    return ck.campaign.is_object() && ck.campaign.value("seed_index", -1) == k &&
           ck.campaign.value("scene", json()) == jscene;
}

// The field on the valve's axis where the arch forms: it can be far from the active region's
// mean (173 mT at the throat under a bracket whose mean is 223 mT), so the report gives it, from
// the map as written and read by the jam scene.
json field_on_axis(const JamScene& js) {
    const FieldMap& map = *js.field_map;
    const double taper_middle_z = js.valve.taper_start_z() + 0.5 * js.valve.taper_length;
    return {{"throat_centre_T", norm(map.flux_density({0, 0, 0}, 0))},
            {"taper_middle_T", norm(map.flux_density({0, 0, taper_middle_z}, 0))},
            {"taper_middle_z_m", taper_middle_z}};
}

// A step that ended the constriction early: its exit status and where it stopped.
struct Stop {
    int status = kExitOk;
    json where;
};

class ConstrictionRun {
public:
    ConstrictionRun(const DesignSpec& spec, const ConstrictionRequest& request, FieldSolver solve)
        : spec_(spec), req_(request), solve_(std::move(solve)) {
        if (req_.resume) progress_ = read_constriction_progress(req_.folder);
    }

    int run() {
        fs::create_directories(req_.folder);
        fs::remove(req_.folder / "report.json");  // this attempt's, when it ends
        std::optional<Stop> stop = run_steps();
        if (stop) {
            const bool interrupted = stop->status == kExitInterrupted;
            write_report(interrupted ? "interrupted" : "failed", {{"stopped", stop->where}});
            return stop->status;
        }
        write_report("complete", {{"row", row_}});
        return kExitOk;
    }

private:
    const std::string& name() const { return spec_.constrictions[req_.index].first; }
    fs::path map_path() const { return req_.folder / "field.map"; }
    fs::path picture_path() const { return req_.folder / "field_B_midplane.svg"; }
    fs::path checkpoint_path() const { return default_checkpoint_path((req_.folder / "jam").string()); }

    std::optional<Stop> run_steps() {
        // 1. The field of this valve, unless an interrupted run solved it already.
        const magnetics::MagneticsScene ms =
            design_magnetics_scene(spec_, req_.folder, spec_.constrictions[req_.index].second, req_.magnetics_tier);
        if (progress_.field.is_null() || !fs::exists(map_path())) {
            if (std::optional<Stop> stop = solve_field(ms)) return stop;
        } else if (req_.progress) {
            std::cerr << "[design] " << name() << ": the field solved before the interruption, " << map_path() << "\n";
        }
        // 2. The jam predictor in that field, with the same valve.
        const json jscene = design_jam_inputs(spec_, req_.folder, ms.resolved["valve"],
                                              json{{"type", "map"}, {"file", fs::absolute(map_path()).string()}});
        const JamScene js = design_jam_scene(spec_, jscene, req_.jam_tier);
        for (int k = static_cast<int>(progress_.runs.size()); k < spec_.seeds; ++k)
            if (std::optional<Stop> stop = run_seed(js, jscene, k)) return stop;
        // 3. The open valve's flow, and the row.
        row_ = finished_row(js);
        return std::nullopt;
    }

    std::optional<Stop> solve_field(magnetics::MagneticsScene ms) {
        ms.request.work_dir = req_.folder / "magnetics" / "solver";
        if (req_.progress) std::cerr << "[design] " << name() << ": solving the field\n";
        std::optional<magnetics::EpmField> solved;
        const json where = {{"constriction", name()}, {"stage", "field solve"}};
        try {
            solved = solve_(ms.request);
        } catch (const std::exception& e) {
            // Ctrl-C reaches gmsh or GetDP too, which then fail: an interruption (below), not a
            // solver fault. A mesh or solver failure fails this constriction.
            if (!interrupt_requested()) {
                json failed = where;
                failed["error"] = e.what();
                std::cerr << "[design] " << name() << ": the field solve failed: " << e.what() << "\n";
                return Stop{kExitError, failed};
            }
        }
        // Interrupted in the solve, or (Ctrl-C that reached mrjam alone) during it: stop before the jam run.
        if (interrupt_requested()) return Stop{kExitInterrupted, where};
        fs::remove_all(ms.request.work_dir);
        const magnetics::FieldGrid& g = solved->fluid_map;
        FieldMap(g.count, g.origin, g.spacing, g.values).write(map_path().string());
        if (magnetics::has_midplane_picture(*solved))
            magnetics::write_midplane_picture(*solved, "|B| on the mid-plane, " + name(), picture_path().string());
        // A checkpoint left here by an earlier design in this directory is not this run's.
        fs::remove(checkpoint_path());
        progress_.field = {{"mean_B_active_T", solved->mean_b_active}, {"max_B_active_T", solved->max_b_active}};
        progress_.runs = json::array();
        progress_.first_report = nullptr;
        write_constriction_progress(req_.folder, progress_);
        return std::nullopt;
    }

    JamRunOptions seed_options(const json& jscene, int k) const {
        JamRunOptions options;
        options.threads = req_.threads;
        options.progress = req_.progress;
        if (k == 0) options.picture_path = (req_.folder / "throat.png").string();
        // This constriction's seeds as `mrjam jam` records them, so an interrupted run's
        // checkpoint resumes with `mrjam design --resume` or `mrjam jam --resume` (that constriction only).
        options.campaign = {{"scene", jscene},
                            {"tier", req_.jam_tier},
                            {"base_directory", spec_.base_directory},
                            {"seeds", spec_.seeds},
                            {"seed_index", k},
                            {"runs", progress_.runs},
                            {"first_report", progress_.first_report},
                            {"snapshots", ""},
                            {"snapshot_every_s", 0.0}};
        // The seed that was running when the design was interrupted (a finished seed leaves no checkpoint).
        const fs::path checkpoint = checkpoint_path();
        if (req_.resume && fs::exists(checkpoint) &&
            resumes_seed(read_jam_checkpoint(checkpoint.string()), jscene, k)) {
            options.resume_checkpoint = checkpoint.string();
            if (req_.progress)
                std::cerr << "[design] " << name() << ": resuming seed " << k + 1 << " from " << checkpoint << "\n";
        }
        return options;
    }

    std::optional<Stop> run_seed(const JamScene& js, const json& jscene, int k) {
        const long long seed = js.engine_scene["seed"].get<long long>() + k;
        if (req_.progress)
            std::cerr << "[design] " << name() << ": seed " << seed << " (" << k + 1 << "/" << spec_.seeds << ")\n";
        json where = {{"constriction", name()}, {"seed", seed}, {"seed_index", k}};
        JamOutcome o;
        try {
            o = run_jam(js, seed, seed_options(jscene, k));
        } catch (const SceneError& e) {
            throw from_jam_run(e, spec_, req_.index);
        } catch (const SetupInterrupted&) {
            // Ctrl-C while this seed placed its grains: it has no checkpoint, and --resume starts it
            // afresh after what the design kept (the field, the seeds before it).
            where["stage"] = "grain placement";
            return Stop{kExitInterrupted, where};
        }
        // Every seed's own report (flux and flow histories, clusters) stays beside the map, named
        // by the seed itself, as the design report's runs name it.
        const fs::path seed_report =
            req_.folder / (k == 0 ? "jam_report.json" : "jam_report_seed" + std::to_string(seed) + ".json");
        json jam_report = o.report;
        jam_report["inputs_jam"] = js.resolved;
        write_json_file(seed_report.string(), jam_report);
        where["jam_report"] = seed_report.string();
        if (o.exit_status == kExitInterrupted) {
            where["stage"] = "jam run";
            where["checkpoint"] = checkpoint_path().string();
            return Stop{kExitInterrupted, where};
        }
        if (o.exit_status != 0) return stopped_by_jam_run(o, where);
        json record = jam_seed_record(o, seed);
        if (k == 0) progress_.first_report = o.report;
        record["jam_report"] = seed_report.string();
        progress_.runs.push_back(record);
        if (req_.progress)
            std::cerr << "[design] " << name() << " seed " << seed << ": " << seed_summary(record) << "\n";
        write_constriction_progress(req_.folder, progress_);
        return std::nullopt;
    }

    // A jam run that stopped this constriction (a blow-up): say why (the cause and its fixes are
    // in the seed report's "error").
    Stop stopped_by_jam_run(const JamOutcome& o, json where) const {
        std::cerr << "[design] the jam run for " << name() << " stopped; its partial report is "
                  << where["jam_report"].get<std::string>() << "\n";
        if (o.report.contains("error")) std::cerr << "[design] " << o.report["error"].get<std::string>() << "\n";
        where["stage"] = "jam run";
        where["exit_status"] = o.exit_status;
        where["status"] = o.report.value("status", std::string("failed"));
        return Stop{o.exit_status, where};
    }

    json finished_row(const JamScene& js) const {
        const double diameter = spec_.constrictions[req_.index].second;
        const double phi = js.resolved["grains"].value("volume_fraction", 0.345);
        const double mu = js.resolved["fluid"].value("viscosity", 0.16);
        const double rho_s = phi * js.resolved["material"].value("density", 7800.0) + (1 - phi) * 850.0;  // mineral oil
        const OpenFlowEstimate flow = open_flow_estimate(js.valve, mu, phi, rho_s, js.flow.supply_pressure);
        // Seeds without a no-field flux are left out (with a hold, only arrests that held are jams).
        const SeedTally tally = tally_seeds(progress_.runs);
        if (tally.judged < spec_.seeds)
            std::cerr << "[design] warning: " << name() << ": " << spec_.seeds - tally.judged << " of " << spec_.seeds
                      << " seed(s) undetermined (no grain crossed without field), left out\n";
        json row = {{"constriction", name()},
                    {"diameter_m", diameter},
                    {"mean_B_active_T", progress_.field["mean_B_active_T"]},
                    {"max_B_active_T", progress_.field["max_B_active_T"]},
                    {"B_on_axis", field_on_axis(js)},
                    {"runs", progress_.runs},
                    {"open_flow_rate_m3_s", flow.flow_rate},
                    {"open_flow_rate_ml_min", flow.flow_rate * 6e7},
                    {"open_throat_speed_m_s", flow.throat_speed},
                    {"suspension_viscosity_Pa_s", flow.suspension_viscosity},
                    {"field_map", map_path().string()}};
        // The pictures, where this run (or the interrupted one it resumes) drew them.
        if (fs::exists(picture_path())) row["field_picture"] = picture_path().string();
        if (fs::exists(req_.folder / "throat.png")) row["throat_picture"] = (req_.folder / "throat.png").string();
        row.update(seed_probabilities(tally));
        if (req_.progress)
            std::cerr << "[design] " << name() << ": " << tally.jams << " jam(s) in " << tally.judged
                      << " seed(s) judged; open flow " << format_number(flow.flow_rate * 6e7, 3) << " ml/min\n";
        return row;
    }

    void write_report(const std::string& status, const json& details) const {
        json report = {
            {"mode", "design"},
            {"part", "constriction"},
            {"status", status},
            {"constriction", name()},
            {"wall_time_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count()}};
        report.update(details);
        write_json_file((req_.folder / "report.json").string(), report);
    }

    const DesignSpec& spec_;
    ConstrictionRequest req_;
    FieldSolver solve_;
    ConstrictionProgress progress_;
    json row_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_constriction(const DesignSpec& spec, const ConstrictionRequest& request, const FieldSolver& solve) {
    return ConstrictionRun(spec, request, solve).run();
}

}  // namespace mrjam
