#include "asteroid/coalesce_run.hpp"

#include <algorithm>
#include <cmath>

#include "asteroid/asteroid_outcome.hpp"
#include "asteroid/body_diagnostics.hpp"
#include "asteroid/rubble_ledger.hpp"
#include "asteroid/rubble_start.hpp"
#include "core/format.hpp"
#include "io/checkpoint.hpp"
#include "io/svg_plot.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

constexpr const char* kMode = "asteroid coalesce";

class Coalescence {
public:
    Coalescence(CoalesceSpec spec, CoalesceOptions options) : spec_(std::move(spec)), options_(std::move(options)) {}

    // A fresh run: the cloud built, set moving, checked to be bound, its tree error measured.
    void start_fresh() {
        RubbleStart r = start_rubble(spec_, options_.threads, options_.fidelity, kMode);
        scene_ = std::move(r.scene);
        cloud_ = r.cloud;
        accuracy_ = r.gravity_accuracy;
        ledger_.open(scene_->system, r.escape_radius, r.energetics.radius);
        set_up_stage();
    }

    void resume(const std::string& path, const nlohmann::json& state, const CheckpointHeader& header) {
        scene_ = restore_rubble(path, header.resolved_scene, options_.threads);
        start_ = header.position;
        stage_log_ = header.history.at("stage_log");
        cloud_ = state.at("cloud");
        accuracy_ = state.at("gravity_accuracy");
        samples_ = state.at("samples");
        ledger_ = RubbleLedger::from_json(state.at("ledger"));
        next_sample_ = state.at("next_sample_s").get<double>();
        set_up_stage();
    }

    CoalesceOutcome run();

private:
    void set_up_stage();
    void observe(const System& s);
    nlohmann::json checkpoint_state() const;
    nlohmann::json summary() const;
    void write_plot(const std::string& path) const;

    CoalesceSpec spec_;
    CoalesceOptions options_;
    std::unique_ptr<Scene> scene_;
    ProtocolPosition start_;
    nlohmann::json stage_log_;
    nlohmann::json cloud_, accuracy_;
    nlohmann::json samples_ = nlohmann::json::array();
    RubbleLedger ledger_;
    double next_sample_ = 0;
};

// One stage of the run's duration; the escape test every twentieth of a sample interval (a grain
// past the escape sphere must not wander far out of the box first), the diagnostics at samples.
void Coalescence::set_up_stage() {
    Stage& st = scene_->stages.at(0);
    st.name = "coalescing";
    st.observe_every = std::max(1L, std::lround(spec_.sample_every / (20.0 * scene_->system.dt)));
}

void Coalescence::observe(const System& s) {
    const bool last = s.time >= spec_.duration - 0.5 * s.dt;
    if (s.time < next_sample_ - 0.5 * s.dt && !last) return;
    nlohmann::json row = to_json(diagnose_body(s, ledger_.initial_mass()));
    row["escaped_grains"] = ledger_.escaped();
    row["conservation"] = ledger_.conservation(s);
    samples_.push_back(row);
    next_sample_ += spec_.sample_every;
}

nlohmann::json Coalescence::checkpoint_state() const {
    return {{"cloud", cloud_},
            {"gravity_accuracy", accuracy_},
            {"samples", samples_},
            {"coalesce_input", spec_.resolved},
            {"fidelity", options_.fidelity},
            {"ledger", ledger_.to_json()},
            {"next_sample_s", next_sample_}};
}

// The figures the source compares across magnetisations (section 4.2): how fast the body
// gathers mass, how porous it is, how much of what is left outside sits in chains and clumps.
nlohmann::json Coalescence::summary() const {
    nlohmann::json out = {{"samples", samples_.size()},
                          {"escaped_grains", ledger_.escaped()},
                          {"escaped_mass_fraction", ledger_.escaped_mass() / ledger_.initial_mass()}};
    if (samples_.empty()) return out;
    const nlohmann::json& last = samples_.back();
    out["final"] = last;
    for (double share : {0.25, 0.5}) {
        nlohmann::json t = nullptr;
        for (const auto& row : samples_)
            if (row.at("body_mass_fraction").get<double>() >= share) {
                t = row.at("time_s");
                break;
            }
        out[share == 0.25 ? "time_to_quarter_mass_s" : "time_to_half_mass_s"] = t;
    }
    double worst_p = 0, worst_l = 0;
    for (const auto& row : samples_) {
        worst_p = std::max(worst_p, row.at("conservation").at("momentum_drift").get<double>());
        worst_l = std::max(worst_l, row.at("conservation").at("angular_momentum_drift").get<double>());
    }
    out["largest_momentum_drift"] = worst_p;
    out["largest_angular_momentum_drift"] = worst_l;
    return out;
}

void Coalescence::write_plot(const std::string& path) const {
    Plot plot;
    plot.title = "Coalescence: " + spec_.description.substr(0, 80);
    plot.x_label = "time (s)";
    plot.y_label = "share";
    PlotSeries body, grouped, clumped;
    body.label = "largest body's share of the cloud's mass";
    grouped.label = "grains outside it in chains or clumps (2+)";
    clumped.label = "... in clumps of more than 10";
    body.line = grouped.line = clumped.line = true;
    grouped.colour = "#ff7f0e";
    clumped.colour = "#2ca02c";
    clumped.dashed = true;
    for (const auto& row : samples_) {
        const double t = row.at("time_s").get<double>();
        body.x.push_back(t);
        body.y.push_back(row.at("body_mass_fraction").get<double>());
        grouped.x.push_back(t);
        grouped.y.push_back(row.at("outside_in_chains_or_clumps").get<double>());
        clumped.x.push_back(t);
        clumped.y.push_back(row.at("outside_in_clumps_over_10").get<double>());
    }
    plot.series = {body, grouped, clumped};
    write_svg(path, plot);
}

CoalesceOutcome Coalescence::run() {
    RunOptions run;
    run.mode = kMode;
    run.scene_path = options_.scene_path;
    run.progress = options_.progress;
    run.resumed_stage_log = stage_log_;
    run.checkpoint_state = [this] { return checkpoint_state(); };
    run.modifiers.push_back({"escape", [this](System& s, std::size_t) { ledger_.remove_escaped(s); }});
    const RunOutcome outcome =
        run_protocol(*scene_, run, start_, [this](const System& s, std::size_t, long) { observe(s); });
    CoalesceOutcome out;
    out.exit_status = outcome.exit_status;
    nlohmann::json& r = out.report;
    r = asteroid_report(outcome, kMode, spec_.resolved, options_.fidelity);
    r["engine_inputs"]["grains"][0]["placement"]["positions"] = "(the cloud's lattice sites; cloud block)";
    r["cloud"] = cloud_;
    r["gravity_accuracy"] = accuracy_;
    r["results"]["coalescence"] = summary();
    r["results"]["coalescence"]["series"] = samples_;
    if (!options_.report_path.empty()) {
        const std::string svg = plot_beside(options_.report_path, "body");
        write_plot(svg);
        r["plots"] = {{"body_fraction", svg}};
        const std::string views = body_views_beside(options_.report_path, "final_body", scene_->system,
                                                    "The body at t = " + format_number(scene_->system.time, 4) + " s");
        if (!views.empty()) r["plots"]["final_body"] = views;
        write_json_file(options_.report_path, r);
    }
    return out;
}

}  // namespace

CoalesceOutcome run_coalescence(const CoalesceSpec& spec, const CoalesceOptions& options) {
    install_interrupt_handler();
    prepare_output_directory(spec.output_directory, "/output/directory");
    Coalescence c(spec, options);
    c.start_fresh();
    return c.run();
}

CoalesceOutcome resume_coalescence(const std::string& checkpoint, const CoalesceOptions& options) {
    const CheckpointHeader header = read_mode_checkpoint(checkpoint, kMode);
    const nlohmann::json& state = header.history.at("state");
    CoalesceOptions o = options;
    o.fidelity = state.at("fidelity").get<std::string>();
    CoalesceSpec spec = read_coalesce_spec(state.at("coalesce_input"), o.fidelity);
    install_interrupt_handler();
    Coalescence c(spec, o);
    c.resume(checkpoint, state, header);
    return c.run();
}

}  // namespace mrjam
