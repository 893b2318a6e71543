#include "design/design_workflow.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>

#include "core/exit_status.hpp"
#include "core/format.hpp"
#include "design/design_progress.hpp"
#include "design/design_scenes.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_results.hpp"
#include "jam/jam_run.hpp"
#include "jam/open_flow.hpp"
#include "jam/seed_tally.hpp"
#include "magnetic/external_field.hpp"
#include "magnetics/getdp_problem.hpp"
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

// What happened to a constriction's step: go on, or stop the design (the status says how).
struct Step {
    bool stop = false;
    int status = kExitOk;
};

class DesignWorkflow {
public:
    DesignWorkflow(const DesignRequest& request, FieldSolver solve)
        : req_(request), spec_(read_design_spec(request.design, request.scene_path)), solve_(std::move(solve)) {
        if (req_.resume) {
            progress_ =
                read_design_progress(spec_.output_directory, req_.design, req_.fidelity_given ? req_.fidelity : "");
            req_.fidelity = progress_.fidelity;
        } else {
            progress_.inputs = req_.design;
            progress_.fidelity = req_.fidelity;
        }
        magnetics_tier_ = req_.fidelity == "paper" ? "paper" : "standard";  // 2D is too far off to design with
        resume_hint_ = "mrjam design " + req_.scene_path + " --resume --report " + req_.report_path;
    }

    int run() {
        if (!solve_) {
            if (magnetics::find_getdp().empty()) {
                std::cerr << "error: getdp was not found on PATH; install it with `apt-get install getdp`\n";
                return kExitBadInput;
            }
            solve_ = [](const magnetics::EpmFieldRequest& r) { return magnetics::compute_epm_field(r); };
        }
        check_design_scenes(spec_, magnetics_tier_, req_.fidelity);
        prepare_output_directory(spec_.output_directory.string(), "/output_directory");
        // Ctrl-C from here on writes the design report of what is done (exit 130); without the
        // handler, an interrupt during a field solve would end the process with nothing written.
        install_interrupt_handler();
        started_ = std::chrono::steady_clock::now();
        save_progress();
        for (std::size_t c = progress_.rows.size(); c < spec_.constrictions.size(); ++c) {
            const Step step = run_constriction(c);
            if (step.stop) return step.status;
        }
        write_report("complete", nullptr);
        if (req_.progress)
            std::cerr << "[design] widest constriction that jams reliably: "
                      << (progress_.widest.empty() ? "none" : progress_.widest) << "; report " << req_.report_path
                      << "\n";
        return kExitOk;
    }

private:
    const std::string& name(std::size_t c) const { return spec_.constrictions[c].first; }
    fs::path directory(std::size_t c) const { return spec_.output_directory / name(c); }
    fs::path map_path(std::size_t c) const { return directory(c) / "field.map"; }
    fs::path checkpoint_path(std::size_t c) const { return default_checkpoint_path((directory(c) / "jam").string()); }

    Step run_constriction(std::size_t c) {
        const fs::path dir = directory(c);
        fs::create_directories(dir);
        // 1. The field of this valve, unless an interrupted run solved it already.
        const magnetics::MagneticsScene ms =
            design_magnetics_scene(spec_, dir, spec_.constrictions[c].second, magnetics_tier_);
        if (progress_.field.is_null() || !fs::exists(map_path(c))) {
            if (const Step step = solve_field(c, ms); step.stop) return step;
        } else if (req_.progress) {
            std::cerr << "[design] " << name(c) << ": the field solved before the interruption, " << map_path(c)
                      << "\n";
        }
        // 2. The jam predictor in that field, with the same valve.
        const json jscene = design_jam_inputs(spec_, dir, ms.resolved["valve"],
                                              json{{"type", "map"}, {"file", fs::absolute(map_path(c)).string()}});
        const JamScene js = design_jam_scene(spec_, jscene, req_.fidelity);
        for (int k = static_cast<int>(progress_.runs.size()); k < spec_.seeds; ++k)
            if (const Step step = run_seed(c, js, jscene, k); step.stop) return step;
        // 3. The open valve's flow, and the row.
        finish_constriction(c, js);
        return {};
    }

    Step solve_field(std::size_t c, magnetics::MagneticsScene ms) {
        ms.request.work_dir = directory(c) / "magnetics" / "solver";
        if (req_.progress) std::cerr << "[design] " << name(c) << ": solving the field\n";
        std::optional<magnetics::EpmField> solved;
        try {
            solved = solve_(ms.request);
        } catch (const std::exception& e) {
            // Ctrl-C reaches gmsh or GetDP too, which then fail: an interruption (below), not a
            // solver fault. A mesh or solver failure: keep what is done, then fail.
            if (!interrupt_requested()) {
                write_report("failed", {{"constriction", name(c)}, {"stage", "field solve"}, {"error", e.what()}});
                throw;
            }
        }
        // Interrupted in the solve, or (Ctrl-C that reached mrjam alone) during it: stop before the jam run.
        if (interrupt_requested()) return interrupted({{"constriction", name(c)}, {"stage", "field solve"}});
        fs::remove_all(ms.request.work_dir);
        const magnetics::FieldGrid& g = solved->fluid_map;
        FieldMap(g.count, g.origin, g.spacing, g.values).write(map_path(c).string());
        // A checkpoint left here by an earlier design in this directory is not this run's.
        fs::remove(checkpoint_path(c));
        progress_.field = {{"mean_B_active_T", solved->mean_b_active}, {"max_B_active_T", solved->max_b_active}};
        progress_.runs = json::array();
        progress_.first_report = nullptr;
        save_progress();
        return {};
    }

    JamRunOptions seed_options(std::size_t c, const json& jscene, int k) const {
        JamRunOptions options;
        options.threads = req_.threads;
        options.progress = req_.progress;
        if (k == 0) options.picture_path = (directory(c) / "throat.png").string();
        // This constriction's seeds as `mrjam jam` records them, so an interrupted run's
        // checkpoint resumes with `mrjam design --resume` or `mrjam jam --resume` (that constriction only).
        options.campaign = {{"scene", jscene},
                            {"tier", req_.fidelity},
                            {"base_directory", spec_.base_directory},
                            {"seeds", spec_.seeds},
                            {"seed_index", k},
                            {"runs", progress_.runs},
                            {"first_report", progress_.first_report},
                            {"snapshots", ""},
                            {"snapshot_every_s", 0.0}};
        // The seed that was running when the design was interrupted (a finished seed leaves no checkpoint).
        const fs::path checkpoint = checkpoint_path(c);
        if (req_.resume && fs::exists(checkpoint) &&
            resumes_seed(read_jam_checkpoint(checkpoint.string()), jscene, k)) {
            options.resume_checkpoint = checkpoint.string();
            if (req_.progress)
                std::cerr << "[design] " << name(c) << ": resuming seed " << k + 1 << " from " << checkpoint << "\n";
        }
        return options;
    }

    Step run_seed(std::size_t c, const JamScene& js, const json& jscene, int k) {
        const long long seed = js.engine_scene["seed"].get<long long>() + k;
        if (req_.progress)
            std::cerr << "[design] " << name(c) << ": seed " << seed << " (" << k + 1 << "/" << spec_.seeds << ")\n";
        const json where = {{"constriction", name(c)}, {"seed", seed}, {"seed_index", k}};
        JamOutcome o;
        try {
            o = run_jam(js, seed, seed_options(c, jscene, k));
        } catch (const SceneError& e) {
            throw from_jam_run(e, spec_, c);
        } catch (const SetupInterrupted&) {
            // Ctrl-C while this seed placed its grains: it has no checkpoint, and --resume starts it
            // afresh after what the design kept (the field, the seeds before it).
            json stopped = where;
            stopped["stage"] = "grain placement";
            return interrupted(stopped);
        }
        // Every seed's own report (flux and flow histories, clusters) stays beside the map, named
        // by the seed itself, as the design report's runs name it.
        const fs::path seed_report =
            directory(c) / (k == 0 ? "jam_report.json" : "jam_report_seed" + std::to_string(seed) + ".json");
        json jam_report = o.report;
        jam_report["inputs_jam"] = js.resolved;
        write_json_file(seed_report.string(), jam_report);
        if (o.exit_status == kExitInterrupted) {
            json stopped = where;
            stopped["jam_report"] = seed_report.string();
            stopped["stage"] = "jam run";
            stopped["checkpoint"] = checkpoint_path(c).string();
            return interrupted(stopped);
        }
        if (o.exit_status != 0) return stopped_by_jam_run(o, where, seed_report);
        json record = jam_seed_record(o, seed);
        if (k == 0) progress_.first_report = o.report;
        record["jam_report"] = seed_report.string();
        progress_.runs.push_back(record);
        if (req_.progress)
            std::cerr << "[design] " << name(c) << " seed " << seed << ": " << seed_summary(record) << "\n";
        save_progress();
        return {};
    }

    // A jam run that stopped the design (a blow-up): say why (the cause and its fixes are in the
    // seed report's "error") and keep the constrictions finished before it.
    Step stopped_by_jam_run(const JamOutcome& o, json where, const fs::path& seed_report) {
        std::cerr << "[design] the jam run for " << where["constriction"].get<std::string>()
                  << " stopped; its partial report is " << seed_report << "\n";
        if (o.report.contains("error")) std::cerr << "[design] " << o.report["error"].get<std::string>() << "\n";
        where["exit_status"] = o.exit_status;
        where["jam_report"] = seed_report.string();
        write_report(o.report.value("status", std::string("failed")), where);
        std::cerr << "[design] the constrictions finished before it are in " << req_.report_path << "\n";
        return {true, o.exit_status};
    }

    void finish_constriction(std::size_t c, const JamScene& js) {
        const double diameter = spec_.constrictions[c].second;
        const double phi = js.resolved["grains"].value("volume_fraction", 0.345);
        const double mu = js.resolved["fluid"].value("viscosity", 0.16);
        const double rho_s = phi * js.resolved["material"].value("density", 7800.0) + (1 - phi) * 850.0;  // mineral oil
        const OpenFlowEstimate flow = open_flow_estimate(js.valve, mu, phi, rho_s, js.flow.supply_pressure);
        // Seeds without a no-field flux are left out (with a hold, only arrests that held are
        // jams); a constriction with none judged cannot be named.
        const SeedTally tally = tally_seeds(progress_.runs);
        if (tally.judged > 0 && static_cast<double>(tally.jams) / tally.judged >= spec_.required_jam_probability &&
            diameter > progress_.widest_diameter) {
            progress_.widest_diameter = diameter;
            progress_.widest = name(c);
        }
        if (tally.judged < spec_.seeds)
            std::cerr << "[design] warning: " << name(c) << ": " << spec_.seeds - tally.judged << " of " << spec_.seeds
                      << " seed(s) undetermined (no grain crossed without field), left out\n";
        json row = {{"constriction", name(c)},
                    {"diameter_m", diameter},
                    {"mean_B_active_T", progress_.field["mean_B_active_T"]},
                    {"max_B_active_T", progress_.field["max_B_active_T"]},
                    {"B_on_axis", field_on_axis(js)},
                    {"runs", progress_.runs},
                    {"open_flow_rate_m3_s", flow.flow_rate},
                    {"open_flow_rate_ml_min", flow.flow_rate * 6e7},
                    {"open_throat_speed_m_s", flow.throat_speed},
                    {"suspension_viscosity_Pa_s", flow.suspension_viscosity},
                    {"field_map", map_path(c).string()}};
        row.update(seed_probabilities(tally));
        if (req_.progress)
            std::cerr << "[design] " << name(c) << ": " << tally.jams << " jam(s) in " << tally.judged
                      << " seed(s) judged; open flow " << format_number(flow.flow_rate * 6e7, 3) << " ml/min\n";
        progress_.rows.push_back(row);
        progress_.field = nullptr;
        progress_.runs = json::array();
        progress_.first_report = nullptr;
        save_progress();
    }

    double wall_time() const {
        return progress_.wall_time_s +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    }

    // The design report, written when the design ends and also when a jam run stops it (a
    // blow-up, Ctrl-C): the constrictions finished by then are not lost.
    void write_report(const std::string& status, const json& stopped) const {
        json report = {
            {"mrjam_version", MRJAM_VERSION},
            {"mode", "design"},
            {"status", status},
            {"scene_file", req_.scene_path},
            {"inputs", req_.design},
            {"inputs_design", spec_.resolved},
            {"fidelity", {{"jam_tier", req_.fidelity}, {"magnetics_tier", magnetics_tier_}}},
            {"results",
             {{"constrictions", progress_.rows},
              {"widest_reliable_constriction", progress_.widest.empty() ? json(nullptr) : json(progress_.widest)},
              {"required_jam_probability", spec_.required_jam_probability},
              {"open_flow_model",
               "Krieger-Dougherty suspension viscosity, Poiseuille bore and throat, "
               "sharp orifice loss (C_d 0.61); mineral oil 850 kg/m3"}}},
            {"wall_time_s", wall_time()}};
        if (!stopped.is_null()) report["stopped"] = stopped;
        if (status == "interrupted") report["resume_with"] = resume_hint_;
        if (req_.resume) report["resumed"] = true;
        write_json_file(req_.report_path, report);
    }

    // Saved after every field solve and every seed; the wall time counts every run of the design.
    void save_progress() const {
        DesignProgress saved = progress_;
        saved.wall_time_s = wall_time();
        write_design_progress(spec_.output_directory, saved);
    }

    Step interrupted(const json& stopped) const {
        write_report("interrupted", stopped);
        std::cerr << "[design] interrupted at the " << stopped["stage"].get<std::string>() << " for "
                  << stopped["constriction"].get<std::string>() << "; the constrictions finished before it are in "
                  << req_.report_path << "; continue with: " << resume_hint_ << "\n";
        return {true, kExitInterrupted};
    }

    DesignRequest req_;
    DesignSpec spec_;
    FieldSolver solve_;
    DesignProgress progress_;
    std::string magnetics_tier_, resume_hint_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_design(const DesignRequest& request, const FieldSolver& solve_field) {
    return DesignWorkflow(request, solve_field).run();
}

}  // namespace mrjam
