// `mrjam design DESIGN.json --report R.json`: the whole chain for a valve designer. For each
// constriction: solve the EPM's field (magnetics/), write its field map, run the jam predictor
// in that field, estimate the open valve's flow rate at the supply pressure; then name the
// widest constriction that still jams reliably.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "core/format.hpp"
#include "design_progress.hpp"
#include "design_scenes.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_run.hpp"
#include "jam/open_flow.hpp"
#include "magnetic/external_field.hpp"
#include "magnetics/getdp_problem.hpp"
#include "magnetics/magnetics_scene.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"
#include "seed_tally.hpp"

namespace mrjam::cli {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
struct DesignArgs {
    std::string scene;
    std::string report = "design_report.json";
    std::string fidelity = "quick";
    int threads = 1;
    bool quiet = false;
    bool resume = false;
};

// Whether a constriction's jam checkpoint is of seed `k` of this design's scene for it.
bool resumes_seed(const JamCheckpoint& ck, const json& jscene, int k) {
    return ck.campaign.is_object() && ck.campaign.value("seed_index", -1) == k &&
           ck.campaign.value("scene", json()) == jscene;
}
}  // namespace

void add_design_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<DesignArgs>();
    CLI::App* cmd =
        app.add_subcommand("design", "Magnetics -> field map -> jam predictor, for a list of constrictions");
    cmd->add_option("scene", args->scene, "Design JSON (see docs/jam.md)")->required();
    cmd->add_option("--report", args->report, "Where to write the JSON report")->capture_default_str();
    CLI::Option* fidelity =
        cmd->add_option("--fidelity", args->fidelity, "Tier for both models: quick, standard or paper")
            ->check(CLI::IsMember(std::vector<std::string>{"quick", "standard", "paper"}))
            ->capture_default_str();
    cmd->add_option("--threads", args->threads, "OpenMP threads")->check(CLI::Range(1, 1024))->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    cmd->add_flag("--resume", args->resume,
                  "Continue the interrupted design of this file: finished constrictions and solved fields are kept, "
                  "the running seed resumes from its checkpoint");
    cmd->callback([args, fidelity, &exit_status] {
        prepare_output_file(args->report, "--report", {args->scene});
        const json design = read_json_file(args->scene);
        const DesignSpec spec = read_design_spec(design, args->scene);
        const auto& constrictions = spec.constrictions;
        const fs::path& out_dir = spec.output_directory;
        const int seeds = spec.seeds;
        // What is done already: all of it read back with --resume, nothing otherwise.
        DesignProgress progress;
        if (args->resume) {
            progress = read_design_progress(out_dir, design, fidelity->count() > 0 ? args->fidelity : "");
            args->fidelity = progress.fidelity;
        } else {
            progress.inputs = design;
            progress.fidelity = args->fidelity;
        }
        const std::string magnetics_tier =
            args->fidelity == "paper" ? "paper" : "standard";  // 2D is too far off to design with
        if (magnetics::find_getdp().empty()) {
            std::cerr << "error: getdp was not found on PATH; install it with `apt-get install getdp`\n";
            exit_status = kExitBadInput;
            return;
        }
        check_design_scenes(spec, magnetics_tier, args->fidelity);
        prepare_output_directory(out_dir.string(), "/output_directory");

        // Ctrl-C from here on writes the design report of what is done (exit 130); without the
        // handler, an interrupt during a field solve would end the process with nothing written.
        install_interrupt_handler();
        const auto started = std::chrono::steady_clock::now();
        const std::string resume_hint = "mrjam design " + args->scene + " --resume --report " + args->report;
        // The design report, written when the design ends and also when a jam run stops it
        // (a blow-up, Ctrl-C): the constrictions finished by then are not lost.
        auto write_report = [&](const std::string& status, const json& stopped) {
            const double wall = progress.wall_time_s +
                                std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            json report = {
                {"mrjam_version", MRJAM_VERSION},
                {"mode", "design"},
                {"status", status},
                {"scene_file", args->scene},
                {"inputs", design},
                {"inputs_design", spec.resolved},
                {"fidelity", {{"jam_tier", args->fidelity}, {"magnetics_tier", magnetics_tier}}},
                {"results",
                 {{"constrictions", progress.rows},
                  {"widest_reliable_constriction", progress.widest.empty() ? json(nullptr) : json(progress.widest)},
                  {"required_jam_probability", spec.required_jam_probability},
                  {"open_flow_model",
                   "Krieger-Dougherty suspension viscosity, Poiseuille bore and throat, "
                   "sharp orifice loss (C_d 0.61); mineral oil 850 kg/m3"}}},
                {"wall_time_s", wall}};
            if (!stopped.is_null()) report["stopped"] = stopped;
            if (status == "interrupted") report["resume_with"] = resume_hint;
            if (args->resume) report["resumed"] = true;
            write_json_file(args->report, report);
        };
        // Saved after every field solve and every seed; the wall time counts every run of the design.
        auto save_progress = [&] {
            DesignProgress saved = progress;
            saved.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            write_design_progress(out_dir, saved);
        };
        auto interrupted = [&](const json& stopped) {
            write_report("interrupted", stopped);
            std::cerr << "[design] interrupted at the " << stopped["stage"].get<std::string>() << " for "
                      << stopped["constriction"].get<std::string>() << "; the constrictions finished before it are in "
                      << args->report << "; continue with: " << resume_hint << "\n";
            exit_status = kExitInterrupted;
        };
        save_progress();
        for (std::size_t c = 0; c < constrictions.size(); ++c) {
            const auto& [name, diameter] = constrictions[c];
            if (c < progress.rows.size()) continue;  // finished before the interruption
            const fs::path dir = out_dir / name;
            const fs::path map = dir / "field.map";
            const fs::path checkpoint = dir / "jam" / "checkpoint.mrjam";
            fs::create_directories(dir);
            // 1. The field of this valve, unless an interrupted run solved it already.
            auto ms = design_magnetics_scene(spec, dir, diameter, magnetics_tier);
            if (progress.field.is_null() || !fs::exists(map)) {
                ms.request.work_dir = dir / "magnetics" / "solver";
                if (!args->quiet) std::cerr << "[design] " << name << ": solving the field\n";
                std::optional<decltype(magnetics::compute_epm_field(ms.request))> solved;
                try {
                    solved = magnetics::compute_epm_field(ms.request);
                } catch (const std::exception& e) {
                    // Ctrl-C reaches gmsh or GetDP too, which then fail: an interruption (below), not a
                    // solver fault. A mesh or solver failure: keep what is done, then fail.
                    if (!interrupt_requested()) {
                        write_report("failed", {{"constriction", name}, {"stage", "field solve"}, {"error", e.what()}});
                        throw;
                    }
                }
                // Interrupted in the solve, or (Ctrl-C that reached mrjam alone) during it: stop before the jam run.
                if (interrupt_requested()) return interrupted({{"constriction", name}, {"stage", "field solve"}});
                const auto& field = *solved;
                fs::remove_all(ms.request.work_dir);
                const FieldMap field_map(field.fluid_map.count, field.fluid_map.origin, field.fluid_map.spacing,
                                         field.fluid_map.values);
                field_map.write(map.string());
                // A checkpoint left here by an earlier design in this directory is not this run's.
                fs::remove(checkpoint);
                progress.field = {{"mean_B_active_T", field.mean_b_active}, {"max_B_active_T", field.max_b_active}};
                progress.runs = json::array();
                progress.first_report = nullptr;
                save_progress();
            } else if (!args->quiet) {
                std::cerr << "[design] " << name << ": the field solved before the interruption, " << map << "\n";
            }
            // 2. The jam predictor in that field, with the same valve.
            const json jscene = design_jam_inputs(spec, dir, ms.resolved["valve"],
                                                  json{{"type", "map"}, {"file", fs::absolute(map).string()}});
            const JamScene js = design_jam_scene(spec, jscene, args->fidelity);
            // Where the arch forms the field can be far from the active region's mean (docs/notes/jam_measurements.md:
            // 173 mT at the throat under a bracket whose mean is 223 mT), so the axis values are
            // reported, from the map as written (17 digits: as solved) and read by the jam scene.
            const FieldMap& field_map = *js.field_map;
            const double taper_middle_z = js.valve.taper_start_z() + 0.5 * js.valve.taper_length;
            const json field_on_axis = {{"throat_centre_T", norm(field_map.flux_density({0, 0, 0}, 0))},
                                        {"taper_middle_T", norm(field_map.flux_density({0, 0, taper_middle_z}, 0))},
                                        {"taper_middle_z_m", taper_middle_z}};
            for (int k = static_cast<int>(progress.runs.size()); k < seeds; ++k) {
                JamRunOptions options;
                options.threads = args->threads;
                options.progress = !args->quiet;
                if (k == 0) options.picture_path = (dir / "throat.png").string();
                // This constriction's seeds as `mrjam jam` records them, so an interrupted run's
                // checkpoint resumes with `mrjam design --resume` or `mrjam jam --resume` (that constriction only).
                options.campaign = {{"scene", jscene},
                                    {"tier", args->fidelity},
                                    {"base_directory", spec.base_directory},
                                    {"seeds", seeds},
                                    {"seed_index", k},
                                    {"runs", progress.runs},
                                    {"first_report", progress.first_report},
                                    {"snapshots", ""},
                                    {"snapshot_every_s", 0.0}};
                // The seed that was running when the design was interrupted (a finished seed leaves no checkpoint).
                if (args->resume && fs::exists(checkpoint) &&
                    resumes_seed(read_jam_checkpoint(checkpoint.string()), jscene, k)) {
                    options.resume_checkpoint = checkpoint.string();
                    if (!args->quiet)
                        std::cerr << "[design] " << name << ": resuming seed " << k + 1 << " from " << checkpoint
                                  << "\n";
                }
                const long long seed = js.engine_scene["seed"].get<long long>() + k;
                if (!args->quiet)
                    std::cerr << "[design] " << name << ": seed " << seed << " (" << k + 1 << "/" << seeds << ")\n";
                const JamOutcome o = [&] {
                    try {
                        return run_jam(js, seed, options);
                    } catch (const SceneError& e) {
                        throw from_jam_run(e, spec, c);
                    }
                }();
                // Every seed's own report (flux and flow histories, clusters) stays beside the map.
                // Named by the seed itself, as the design report's runs name it.
                const fs::path seed_report =
                    dir / (k == 0 ? "jam_report.json" : "jam_report_seed" + std::to_string(seed) + ".json");
                json jam_report = o.report;
                jam_report["inputs_jam"] = js.resolved;
                write_json_file(seed_report.string(), jam_report);
                if (o.exit_status == kExitInterrupted)
                    return interrupted({{"constriction", name},
                                        {"stage", "jam run"},
                                        {"seed", seed},
                                        {"seed_index", k},
                                        {"jam_report", seed_report.string()},
                                        {"checkpoint", checkpoint.string()}});
                if (o.exit_status != 0) {
                    exit_status = o.exit_status;
                    // Say why it stopped: a blow-up's cause and its fixes are in the report's "error".
                    std::cerr << "[design] the jam run for " << name << " stopped; its partial report is "
                              << seed_report << "\n";
                    if (o.report.contains("error"))
                        std::cerr << "[design] " << o.report["error"].get<std::string>() << "\n";
                    write_report(o.report.value("status", std::string("failed")), {{"constriction", name},
                                                                                   {"seed", seed},
                                                                                   {"seed_index", k},
                                                                                   {"jam_report", seed_report.string()},
                                                                                   {"exit_status", o.exit_status}});
                    std::cerr << "[design] the constrictions finished before it are in " << args->report << "\n";
                    return;
                }
                json record = jam_seed_record(o);
                if (k == 0) progress.first_report = o.report;
                record["seed"] = seed;
                record["status"] = o.report["status"];
                record["jam_report"] = seed_report.string();
                progress.runs.push_back(record);
                if (!args->quiet) {
                    std::cerr << "[design] " << name << " seed " << seed << ": " << seed_summary(record) << "\n";
                }
                save_progress();
            }
            // 3. The open valve's flow at the supply pressure.
            const double phi = js.resolved["grains"].value("volume_fraction", 0.345);
            const double mu = js.resolved["fluid"].value("viscosity", 0.16);
            const double rho_s =
                phi * js.resolved["material"].value("density", 7800.0) + (1 - phi) * 850.0;  // mineral oil
            const OpenFlowEstimate flow = open_flow_estimate(js.valve, mu, phi, rho_s, js.flow.supply_pressure);
            // Seeds without a no-field flux are left out (with a hold, only arrests that held are
            // jams); a constriction with none judged cannot be named.
            const SeedTally tally = tally_seeds(progress.runs);
            if (tally.judged > 0 && static_cast<double>(tally.jams) / tally.judged >= spec.required_jam_probability &&
                diameter > progress.widest_diameter) {
                progress.widest_diameter = diameter;
                progress.widest = name;
            }
            if (tally.judged < seeds)
                std::cerr << "[design] warning: " << name << ": " << seeds - tally.judged << " of " << seeds
                          << " seed(s) undetermined (no grain crossed without field), left out\n";
            json row = {{"constriction", name},
                        {"diameter_m", diameter},
                        {"mean_B_active_T", progress.field["mean_B_active_T"]},
                        {"max_B_active_T", progress.field["max_B_active_T"]},
                        {"B_on_axis", field_on_axis},
                        {"runs", progress.runs},
                        {"open_flow_rate_m3_s", flow.flow_rate},
                        {"open_flow_rate_ml_min", flow.flow_rate * 6e7},
                        {"open_throat_speed_m_s", flow.throat_speed},
                        {"suspension_viscosity_Pa_s", flow.suspension_viscosity},
                        {"field_map", map.string()}};
            row.update(seed_probabilities(tally));
            if (!args->quiet)
                std::cerr << "[design] " << name << ": " << tally.jams << " jam(s) in " << tally.judged
                          << " seed(s) judged; open flow " << format_number(flow.flow_rate * 6e7, 3) << " ml/min\n";
            progress.rows.push_back(row);
            progress.field = nullptr;
            progress.runs = json::array();
            progress.first_report = nullptr;
            save_progress();
        }
        write_report("complete", nullptr);
        if (!args->quiet)
            std::cerr << "[design] widest constriction that jams reliably: "
                      << (progress.widest.empty() ? "none" : progress.widest) << "; report " << args->report << "\n";
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
