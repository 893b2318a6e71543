#include "asteroid/spinup_run.hpp"

#include <algorithm>
#include <cmath>

#include "asteroid/asteroid_outcome.hpp"
#include "asteroid/body_diagnostics.hpp"
#include "asteroid/body_spin.hpp"
#include "asteroid/rubble_ledger.hpp"
#include "asteroid/rubble_start.hpp"
#include "asteroid/spin_limits.hpp"
#include "core/format.hpp"
#include "gravity/self_gravity.hpp"
#include "io/checkpoint.hpp"
#include "io/svg_plot.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

// A sample taken during a spin step (stage 1 on). Samples from a checkpoint written before the
// stage was recorded: by time, past the settling's end by more than half a sample interval.
bool spinning_sample(const nlohmann::json& row, double settle_time, double sample_every) {
    if (row.contains("stage")) return row.at("stage").get<std::size_t>() > 0;
    return row.at("time_s").get<double>() > settle_time + 0.5 * sample_every;
}

constexpr const char* kMode = "asteroid spinup";

class SpinUp {
public:
    SpinUp(SpinupSpec spec, CoalesceOptions options) : spec_(std::move(spec)), options_(std::move(options)) {}

    void start_fresh() {
        run_.begin(spec_.body, options_.threads, options_.fidelity, kMode);
        set_up_stages();
    }

    void resume(const std::string& path, const nlohmann::json& state, const CheckpointHeader& header) {
        run_.restore(path, state, header, options_.threads);
        step_rows_ = state.at("steps");
        events_ = state.at("events");
        set_up_stages();
    }

    CoalesceOutcome run();

private:
    void set_up_stages();
    void observe(const System& s, std::size_t stage, long step);
    nlohmann::json step_row(const System& s, std::size_t stage) const;
    void detect_events(const System& s, const nlohmann::json& before, const nlohmann::json& now);
    nlohmann::json checkpoint_state() const;
    nlohmann::json summary() const;
    nlohmann::json drucker_prager_summary(const nlohmann::json& settled) const;
    void write_plot(const std::string& path) const;

    SpinupSpec spec_;
    CoalesceOptions options_;
    RubbleRun run_;
    nlohmann::json step_rows_ = nlohmann::json::array(), events_ = nlohmann::json::array();
};

// Stage 0 settles the gathered body; stage k adds the k-th increment to the body as it starts
// (once: a run resumed inside the stage has the spin in its checkpoint already).
void SpinUp::set_up_stages() {
    const double dt = run_.scene->system.dt;
    const long every = std::max(1L, std::lround(spec_.body.sample_every / (20.0 * dt)));
    auto stage = [&](std::string name, double duration) {
        Stage st;
        st.name = std::move(name);
        st.steps = std::max(1L, std::lround(duration / dt));
        st.duration = duration;
        st.path = "/spin_up";
        st.observe_every = every;
        st.keep_forces = true;
        return st;
    };
    run_.scene->stages.clear();
    Stage settle = stage("settling", spec_.settle_time);
    settle.keep_forces = false;
    run_.scene->stages.push_back(settle);
    for (int k = 1; k <= spec_.steps(); ++k) {
        char name[64];
        std::snprintf(name, sizeof name, "spin step %d: %.0f urad/s", k, spec_.target(k) * 1e6);
        Stage st = stage(name, spec_.interval(k));
        const double delta = spec_.increment;
        st.on_start = [this, delta](System& s, bool fresh) {
            if (fresh)
                run_.ledger.inject_angular_momentum(spin_up_body(s.particles, heaviest_cluster(s).grains, delta));
        };
        run_.scene->stages.push_back(st);
    }
}

nlohmann::json SpinUp::step_row(const System& s, std::size_t stage) const {
    const BodyDiagnostics d = diagnose_body(s, run_.ledger.initial_mass());
    const BodyMembers members = heaviest_cluster(s);
    const BodySpin spin = body_spin(s.particles, members.grains);
    std::size_t fragments = 0;  // bodies of at least 10 grains besides the main one
    for (std::size_t size : members.other_cluster_sizes) fragments += size >= 10;
    const double second = members.cluster_masses.size() > 1 ? members.cluster_masses[1] : 0.0;
    return {{"step", stage},
            {"time_s", s.time},
            {"target_spin_rad_s", spec_.target(static_cast<int>(stage))},
            {"body_spin_rad_s", spin.rate},
            {"i_zz_kg_m2", spin.i_zz},
            {"body_mass_fraction", d.body_mass_fraction},
            {"semi_axes_m", {d.semi_axes[0], d.semi_axes[1], d.semi_axes[2]}},
            {"axis_ratio_b_a", d.semi_axes[1] / d.semi_axes[0]},
            {"axis_ratio_c_a", d.semi_axes[2] / d.semi_axes[0]},
            {"bulk_density_kg_m3", d.bulk_density},
            {"porosity", d.porosity},
            {"second_body_mass_fraction", second / run_.ledger.initial_mass()},
            {"fragments", fragments},
            {"escaped_grains", run_.ledger.escaped()}};
}

// Against the previous step's end: fission (a second body above the threshold), shedding (the
// body lost more than the threshold), deformation (I_zz or c/a changed beyond the threshold with
// no shedding).
void SpinUp::detect_events(const System& s, const nlohmann::json& before, const nlohmann::json& now) {
    auto val = [](const nlohmann::json& row, const char* key) { return row.at(key).get<double>(); };
    const double lost = val(before, "body_mass_fraction") - val(now, "body_mass_fraction");
    const double d_inertia = std::fabs(val(now, "i_zz_kg_m2") / val(before, "i_zz_kg_m2") - 1.0);
    const double d_shape = std::fabs(val(now, "axis_ratio_c_a") / val(before, "axis_ratio_c_a") - 1.0);
    auto record = [&](const char* type) {
        events_.push_back({{"event", type},
                           {"step", now.at("step")},
                           {"target_spin_rad_s", now.at("target_spin_rad_s")},
                           {"body_spin_rad_s", now.at("body_spin_rad_s")},
                           {"time_s", now.at("time_s")},
                           {"mass_lost_fraction", lost},
                           {"i_zz_change", d_inertia},
                           {"axis_ratio_change", d_shape},
                           {"fragments", now.at("fragments")},
                           {"bulk_density_kg_m3", now.at("bulk_density_kg_m3")}});
        // The body as the event left it, along and across the spin axis.
        if (options_.report_path.empty()) return;
        const std::string suffix = "event" + std::to_string(events_.size()) + "_" + type;
        const std::string views = body_views_beside(
            options_.report_path, suffix, s,
            std::string(type) + " at " + format_number(now.at("target_spin_rad_s").get<double>() * 1e6, 4) +
                " urad/s (t = " + format_number(now.at("time_s").get<double>(), 5) + " s)");
        if (!views.empty()) events_.back()["picture"] = views;
    };
    if (val(now, "second_body_mass_fraction") > spec_.fission_threshold) record("fission");
    if (lost > spec_.shedding_threshold) record("shedding");
    if (lost <= spec_.shedding_threshold &&
        (d_inertia > spec_.deformation_threshold || d_shape > spec_.deformation_threshold))
        record("deformation");
}

void SpinUp::observe(const System& s, std::size_t stage, long step) {
    if (s.time >= run_.next_sample - 0.5 * s.dt) {
        nlohmann::json row = to_json(diagnose_body(s, run_.ledger.initial_mass()));
        row["conservation"] = run_.ledger.conservation(s);
        row["stage"] = stage;  // 0 settling, k the k-th spin step
        run_.samples.push_back(row);
        run_.next_sample += spec_.body.sample_every;
    }
    if (step != run_.scene->stages[stage].steps) return;  // a step's end
    nlohmann::json row = step_row(s, stage);
    if (!step_rows_.empty()) detect_events(s, step_rows_.back(), row);
    step_rows_.push_back(row);
}

nlohmann::json SpinUp::checkpoint_state() const {
    nlohmann::json state = run_.save();
    state["steps"] = step_rows_;
    state["events"] = events_;
    state["spinup_input"] = spec_.body.resolved;
    state["fidelity"] = options_.fidelity;
    return state;
}

// Holsapple's cohesionless Drucker-Prager limit of the settled body (its bulk density, its
// equivalent ellipsoid spinning about its shortest axis) for a range of friction angles and for
// the grains' own friction angle, atan(mu) (a packing's bulk angle is larger than that).
nlohmann::json SpinUp::drucker_prager_summary(const nlohmann::json& settled) const {
    const double rho = settled.at("bulk_density_kg_m3").get<double>();
    const std::array<double, 3> axes = settled.at("semi_axes_m");
    nlohmann::json limits = nlohmann::json::object();
    for (int deg : {20, 25, 30, 35, 40, 45})
        limits[std::to_string(deg)] = drucker_prager_spin_limit(rho, axes, deg * M_PI / 180);
    const double grain_angle = std::atan(spec_.body.material.friction);
    return {{"model",
             "Holsapple (2007): volume-averaged stresses of a uniform ellipsoid at the Drucker-Prager "
             "surface, cohesionless"},
            {"limits_rad_s_by_friction_angle_deg", limits},
            {"grain_friction_angle_deg", grain_angle * 180 / M_PI},
            {"limit_at_grain_friction_angle_rad_s", drucker_prager_spin_limit(rho, axes, grain_angle)}};
}

// The settled body, the analytic rigid-sphere limit at its bulk density, and the first spin at
// which it deformed and at which it lost mass or split (the source's deformation and disruption).
nlohmann::json SpinUp::summary() const {
    nlohmann::json out = {{"steps", step_rows_}, {"events", events_}, {"escaped_grains", run_.ledger.escaped()}};
    if (step_rows_.empty()) return out;
    const nlohmann::json& settled = step_rows_.front();
    out["settled_body"] = settled;
    const double rho = settled.at("bulk_density_kg_m3").get<double>();
    out["rigid_sphere_limit_rad_s"] = rigid_sphere_spin_limit(rho);
    out["drucker_prager"] = drucker_prager_summary(settled);
    out["first_deformation_rad_s"] = nullptr;
    out["first_disruption_rad_s"] = nullptr;
    for (const auto& e : events_) {
        const std::string type = e.at("event").get<std::string>();
        const char* key = type == "deformation" ? "first_deformation_rad_s" : "first_disruption_rad_s";
        if (out[key].is_null()) out[key] = e.at("target_spin_rad_s");
    }
    // The bulk friction angle each event implies: the angle whose limit is the spin it came at.
    for (const auto& [key, implied] :
         {std::pair{"first_deformation_rad_s", "friction_angle_implied_by_deformation_deg"},
          std::pair{"first_disruption_rad_s", "friction_angle_implied_by_disruption_deg"}}) {
        const double phi =
            out[key].is_null() ? std::nan("") : friction_angle_for_spin(rho, settled.at("semi_axes_m"), out[key]);
        out["drucker_prager"][implied] =
            std::isfinite(phi) ? nlohmann::json(phi * 180 / M_PI) : nlohmann::json(nullptr);
    }
    // The angular momentum over the spin steps only: a cold cloud settling has next to none, so
    // a drift relative to it says nothing there. Told by the stage a sample was taken in, not by
    // its time: the settling's last sample falls a few steps past settle_time (and its 9 % drift
    // of a near-zero angular momentum was once reported as the spinning body's).
    double worst_p = 0, worst_l = 0;
    for (const auto& row : run_.samples) {
        worst_p = std::max(worst_p, row.at("conservation").at("momentum_drift").get<double>());
        if (spinning_sample(row, spec_.settle_time, spec_.body.sample_every))
            worst_l = std::max(worst_l, row.at("conservation").at("angular_momentum_drift").get<double>());
    }
    out["largest_momentum_drift"] = worst_p;
    out["largest_angular_momentum_drift_spinning"] = worst_l;
    return out;
}

void SpinUp::write_plot(const std::string& path) const {
    Plot plot;
    plot.title = "Spin-up: the body at the end of each step";
    plot.x_label = "spin given (urad/s)";
    plot.y_label = "ratio";
    PlotSeries mass, shape, inertia;
    mass.label = "body's share of the mass";
    shape.label = "axis ratio c/a";
    inertia.label = "I_zz over the settled body's";
    mass.line = shape.line = inertia.line = true;
    shape.colour = "#ff7f0e";
    inertia.colour = "#2ca02c";
    inertia.dashed = true;
    const double i0 = step_rows_.empty() ? 1.0 : step_rows_.front().at("i_zz_kg_m2").get<double>();
    for (const auto& row : step_rows_) {
        const double w = row.at("target_spin_rad_s").get<double>() * 1e6;
        mass.x.push_back(w);
        mass.y.push_back(row.at("body_mass_fraction").get<double>());
        shape.x.push_back(w);
        shape.y.push_back(row.at("axis_ratio_c_a").get<double>());
        inertia.x.push_back(w);
        inertia.y.push_back(row.at("i_zz_kg_m2").get<double>() / i0);
    }
    plot.series = {mass, shape, inertia};
    write_svg(path, plot);
}

CoalesceOutcome SpinUp::run() {
    RunOptions run = run_.run_options(kMode, options_.scene_path, options_.progress);
    run.checkpoint_state = [this] { return checkpoint_state(); };
    run.checkpoint_each_stage = true;  // a finished step is never redone
    const RunOutcome outcome = run_protocol(*run_.scene, run, run_.start,
                                            [this](const System& s, std::size_t k, long i) { observe(s, k, i); });
    CoalesceOutcome out;
    out.exit_status = outcome.exit_status;
    nlohmann::json& r = out.report;
    r = run_.report(outcome, kMode, spec_.body.resolved, options_.fidelity);
    r["results"]["spin_up"] = summary();
    r["results"]["spin_up"]["series"] = run_.samples;
    if (!options_.report_path.empty()) {
        const std::string svg = plot_beside(options_.report_path, "spin");
        write_plot(svg);
        r["plots"] = {{"spin_steps", svg}};
        run_.draw_final_body(r, options_.report_path);
        write_json_file(options_.report_path, r);
    }
    return out;
}

}  // namespace

CoalesceOutcome run_spinup(const SpinupSpec& spec, const CoalesceOptions& options) {
    return run_fresh<SpinUp>(spec, spec.body.output.directory, options);
}

CoalesceOutcome resume_spinup(const std::string& checkpoint, const CoalesceOptions& options) {
    return run_resumed<SpinUp>(checkpoint, options, kMode, "spinup_input", read_spinup_spec);
}

}  // namespace mrjam
