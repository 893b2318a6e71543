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
        run_.begin(spec_, options_.threads, options_.fidelity, kMode);
        set_up_stage();
    }

    void resume(const std::string& path, const nlohmann::json& state, const CheckpointHeader& header) {
        run_.restore(path, state, header, options_.threads);
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
    RubbleRun run_;
};

// One stage of the run's duration; the escape test every twentieth of a sample interval (a grain
// past the escape sphere must not wander far out of the box first), the diagnostics at samples.
void Coalescence::set_up_stage() {
    Stage& st = run_.scene->stages.at(0);
    st.name = "coalescing";
    st.observe_every = std::max(1L, std::lround(spec_.sample_every / (20.0 * run_.scene->system.dt)));
}

void Coalescence::observe(const System& s) {
    const bool last = s.time >= spec_.duration - 0.5 * s.dt;
    if (s.time < run_.next_sample - 0.5 * s.dt && !last) return;
    nlohmann::json row = to_json(diagnose_body(s, run_.ledger.initial_mass()));
    row["escaped_grains"] = run_.ledger.escaped();
    row["conservation"] = run_.ledger.conservation(s);
    run_.samples.push_back(row);
    run_.next_sample += spec_.sample_every;
}

nlohmann::json Coalescence::checkpoint_state() const {
    nlohmann::json state = run_.save();
    state["coalesce_input"] = spec_.resolved;
    state["fidelity"] = options_.fidelity;
    return state;
}

// The figures the source compares across magnetisations (section 4.2): how fast the body
// gathers mass, how porous it is, how much of what is left outside sits in chains and clumps.
nlohmann::json Coalescence::summary() const {
    nlohmann::json out = {{"samples", run_.samples.size()},
                          {"escaped_grains", run_.ledger.escaped()},
                          {"escaped_mass_fraction", run_.ledger.escaped_mass() / run_.ledger.initial_mass()}};
    if (run_.samples.empty()) return out;
    const nlohmann::json& last = run_.samples.back();
    out["final"] = last;
    for (double share : {0.25, 0.5}) {
        nlohmann::json t = nullptr;
        for (const auto& row : run_.samples)
            if (row.at("body_mass_fraction").get<double>() >= share) {
                t = row.at("time_s");
                break;
            }
        out[share == 0.25 ? "time_to_quarter_mass_s" : "time_to_half_mass_s"] = t;
    }
    double worst_p = 0, worst_l = 0;
    for (const auto& row : run_.samples) {
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
    for (const auto& row : run_.samples) {
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
    RunOptions run = run_.run_options(kMode, options_.scene_path, options_.progress);
    run.checkpoint_state = [this] { return checkpoint_state(); };
    const RunOutcome outcome =
        run_protocol(*run_.scene, run, run_.start, [this](const System& s, std::size_t, long) { observe(s); });
    CoalesceOutcome out;
    out.exit_status = outcome.exit_status;
    nlohmann::json& r = out.report;
    r = run_.report(outcome, kMode, spec_.resolved, options_.fidelity);
    r["results"]["coalescence"] = summary();
    r["results"]["coalescence"]["series"] = run_.samples;
    if (!options_.report_path.empty()) {
        const std::string svg = plot_beside(options_.report_path, "body");
        write_plot(svg);
        r["plots"] = {{"body_fraction", svg}};
        run_.draw_final_body(r, options_.report_path);
        write_json_file(options_.report_path, r);
    }
    return out;
}

}  // namespace

CoalesceOutcome run_coalescence(const CoalesceSpec& spec, const CoalesceOptions& options) {
    return run_fresh<Coalescence>(spec, spec.output.directory, options);
}

CoalesceOutcome resume_coalescence(const std::string& checkpoint, const CoalesceOptions& options) {
    return run_resumed<Coalescence>(checkpoint, options, kMode, "coalesce_input", read_coalesce_spec);
}

}  // namespace mrjam
