#include "asteroid/coalesce_run.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "asteroid/body_diagnostics.hpp"
#include "asteroid/cloud.hpp"
#include "asteroid/coalesce_scene.hpp"
#include "core/format.hpp"
#include "grain_removal.hpp"
#include "gravity/self_gravity.hpp"
#include "io/checkpoint.hpp"
#include "io/svg_plot.hpp"
#include "observers.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

constexpr const char* kMode = "asteroid coalesce";

// Momentum and angular momentum (about the origin, spins included) of the grains present.
struct Momenta {
    Vec3 linear, angular;
};

Momenta momenta(const Particles& p) {
    Momenta m;
    for (std::size_t i = 0; i < p.size(); ++i) {
        m.linear += p.velocity[i] * p.mass[i];
        m.angular += cross(p.position[i], p.velocity[i]) * p.mass[i] + p.angular_velocity[i] * p.inertia[i];
    }
    return m;
}

Vec3 vec3_of(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }
nlohmann::json json_of(const Vec3& v) { return {v.x, v.y, v.z}; }

// Tree against direct summation on the grains as they are: each grain's relative error.
nlohmann::json gravity_accuracy(const System& s, const CoalesceSpec& spec) {
    if (spec.direct_gravity)
        return {{"method", "direct"}, {"held_steps", spec.gravity_interval}, {"median_relative_error", 0.0}};
    const Particles& p = s.particles;
    GravityTree::Settings settings;
    settings.opening_angle = spec.opening_angle;
    GravityTree tree(settings);
    tree.build(p);
    std::vector<Vec3> a_tree, a_direct;
    tree.accelerations(p, kNewtonG, a_tree, s.threads);
    direct_gravity(p, kNewtonG, a_direct, s.threads);
    std::vector<double> err(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) err[i] = norm(a_tree[i] - a_direct[i]) / norm(a_direct[i]);
    std::sort(err.begin(), err.end());
    const auto at = [&](double q) { return err[static_cast<std::size_t>(q * static_cast<double>(err.size() - 1))]; };
    return {{"method", "tree"},
            {"opening_angle", spec.opening_angle},
            {"held_steps", spec.gravity_interval},
            {"grains_compared", err.size()},
            {"median_relative_error", at(0.5)},
            {"p99_relative_error", at(0.99)},
            {"max_relative_error", err.back()},
            {"against", "direct summation of every pair, on the initial cloud"}};
}

nlohmann::json energetics_json(const CloudEnergetics& e, const CoalesceSpec& s, std::size_t grains) {
    return {{"grains", grains},
            {"mass_kg", e.mass},
            {"radius_m", e.radius},
            {"thermal_speed_m_s", s.thermal_speed},
            {"thermal_speed_rule", s.thermal_from_temperature
                                       ? "the source's temperature 8e20 d^3 read as kelvin: sigma = sqrt(k_B T / m)"
                                       : "given (cloud/thermal_speed)"},
            {"spin_rad_s", s.spin},
            {"kinetic_J", e.kinetic},
            {"spin_kinetic_J", e.spin_kinetic},
            {"binding_J", e.binding},
            {"kinetic_over_binding", e.virial_ratio},
            {"orbital_rate_at_edge_rad_s", e.orbital_rate},
            {"spin_over_orbital_rate", e.spin_ratio},
            {"free_fall_time_s", e.free_fall_time}};
}

}  // namespace

namespace {

class Coalescence {
public:
    Coalescence(CoalesceSpec spec, CoalesceOptions options) : spec_(std::move(spec)), options_(std::move(options)) {}

    // A fresh run: the cloud built, set moving, checked to be bound, its tree error measured.
    void start_fresh() {
        const CloudLayout layout = lay_out_cloud(spec_);
        BuildOptions build;
        build.threads = options_.threads;
        build.fidelity = options_.fidelity;
        scene_ = std::make_unique<Scene>(build_scene(coalesce_engine_scene(spec_, layout), build));
        Particles& p = scene_->system.particles;
        std::vector<char> thermal(p.size());
        for (std::size_t i = 0; i < p.size(); ++i) thermal[i] = p.material[i] == 0;  // not the seed grain
        give_cloud_motion(p, thermal, spec_.thermal_speed, spec_.spin, spec_.seed);
        const CloudEnergetics e = cloud_energetics(p, spec_.spin, kNewtonG);
        check_bound(e);
        choose_timestep(*scene_);
        check_holds(e);
        cloud_ = energetics_json(e, spec_, p.size());
        cloud_["escape_radius_m"] = layout.escape_radius;
        cloud_["seed_grain_diameter_m"] = spec_.seed_diameter;
        accuracy_ = gravity_accuracy(scene_->system, spec_);
        initial_mass_ = e.mass;
        const Momenta m = momenta(p);
        initial_linear_ = m.linear;
        initial_angular_ = m.angular;
        momentum_scale_ = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            momentum_scale_ += p.mass[i] * (norm(p.velocity[i]) * (1.0 + norm(p.position[i]) / layout.cloud_radius));
        set_up_stage();
    }

    void resume(const std::string& path, const nlohmann::json& state, const CheckpointHeader& header) {
        BuildOptions build;
        build.threads = options_.threads;
        build.insert_grains = false;
        scene_ = std::make_unique<Scene>(build_scene(header.resolved_scene, build));
        restore_scene(path, *scene_);
        start_ = header.position;
        stage_log_ = header.history.at("stage_log");
        cloud_ = state.at("cloud");
        accuracy_ = state.at("gravity_accuracy");
        samples_ = state.at("samples");
        initial_mass_ = state.at("initial_mass_kg").get<double>();
        initial_linear_ = vec3_of(state.at("initial_momentum"));
        initial_angular_ = vec3_of(state.at("initial_angular_momentum"));
        momentum_scale_ = state.at("momentum_scale").get<double>();
        removed_linear_ = vec3_of(state.at("escaped_momentum"));
        removed_angular_ = vec3_of(state.at("escaped_angular_momentum"));
        escaped_ = state.at("escaped_grains").get<std::size_t>();
        escaped_mass_ = state.at("escaped_mass_kg").get<double>();
        next_sample_ = state.at("next_sample_s").get<double>();
        set_up_stage();
    }

    CoalesceOutcome run();

private:
    void check_bound(const CloudEnergetics& e) const;
    void check_holds(const CloudEnergetics& e) const;
    void set_up_stage();
    void escape(System& s);
    void observe(const System& s);
    nlohmann::json checkpoint_state() const;
    nlohmann::json conservation(const System& s) const;
    nlohmann::json summary() const;
    void write_plot(const std::string& path) const;

    CoalesceSpec spec_;
    CoalesceOptions options_;
    std::unique_ptr<Scene> scene_;
    ProtocolPosition start_;
    nlohmann::json stage_log_;
    nlohmann::json cloud_, accuracy_;
    nlohmann::json samples_ = nlohmann::json::array();
    double initial_mass_ = 0, momentum_scale_ = 0, escaped_mass_ = 0, next_sample_ = 0;
    Vec3 initial_linear_, initial_angular_, removed_linear_, removed_angular_;
    std::size_t escaped_ = 0;
};

void Coalescence::check_bound(const CloudEnergetics& e) const {
    if (e.virial_ratio < 1.0 || spec_.allow_unbound) return;
    const double thermal = e.kinetic - e.spin_kinetic;
    const double room = 0.5 * e.binding - e.spin_kinetic;  // thermal energy that would leave the ratio at 0.5
    std::string fix;
    if (room > 0 && thermal > 0)
        fix = "a thermal_speed of " + format_number(spec_.thermal_speed * std::sqrt(room / thermal), 3) +
              " m/s would make it 0.5";
    else
        fix = "the spin alone exceeds half the binding energy: lower /cloud/spin (the edge's orbital rate is " +
              format_number(e.orbital_rate, 3) + " rad/s)";
    throw SceneError(room > 0 ? "/cloud/thermal_speed" : "/cloud/spin",
                     "the cloud is unbound: kinetic / binding energy = " + format_number(e.virial_ratio, 3) + " (" +
                         format_number(e.kinetic, 3) + " J against " + format_number(e.binding, 3) +
                         " J), so it cannot collapse; " + fix + ", or set /cloud/allow_unbound to run it anyway");
}

// A held self-gravity must stay short against the dynamical time, where the field changes: the
// bound is 1 % of the free-fall time (the quick tier's 100 steps are about 0.03 % of it).
void Coalescence::check_holds(const CloudEnergetics& e) const {
    const double held = spec_.gravity_interval * scene_->system.dt;
    if (held > 0.01 * e.free_fall_time)
        throw SceneError("/self_gravity/update_interval",
                         "holds the self-gravity " + format_number(held, 3) + " s, more than 1 % of the cloud's " +
                             "free-fall time (" + format_number(e.free_fall_time, 3) + " s); lower it below " +
                             std::to_string(static_cast<long>(0.01 * e.free_fall_time / scene_->system.dt)));
}

// One stage of the run's duration; the escape test every twentieth of a sample interval (a grain
// past the escape sphere must not wander far out of the box first), the diagnostics at samples.
void Coalescence::set_up_stage() {
    Stage& st = scene_->stages.at(0);
    st.name = "coalescing";
    st.observe_every = std::max(1L, std::lround(spec_.sample_every / (20.0 * scene_->system.dt)));
}

void Coalescence::escape(System& s) {
    const double r2 = std::pow(cloud_.at("escape_radius_m").get<double>(), 2);
    Particles& p = s.particles;
    std::vector<char> out(p.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (norm2(p.position[i]) > r2) {
            out[i] = 1;
            any = true;
            removed_linear_ += p.velocity[i] * p.mass[i];
            removed_angular_ += cross(p.position[i], p.velocity[i]) * p.mass[i] + p.angular_velocity[i] * p.inertia[i];
            escaped_mass_ += p.mass[i];
        }
    if (any) escaped_ += remove_grains(s, out);
}

void Coalescence::observe(const System& s) {
    const bool last = s.time >= spec_.duration - 0.5 * s.dt;
    if (s.time < next_sample_ - 0.5 * s.dt && !last) return;
    nlohmann::json row = to_json(diagnose_body(s, initial_mass_));
    row["escaped_grains"] = escaped_;
    row["conservation"] = conservation(s);
    samples_.push_back(row);
    next_sample_ += spec_.sample_every;
}

nlohmann::json Coalescence::conservation(const System& s) const {
    const Momenta m = momenta(s.particles);
    const Vec3 dp = m.linear + removed_linear_ - initial_linear_;
    const Vec3 dl = m.angular + removed_angular_ - initial_angular_;
    const double l0 = norm(initial_angular_);
    const EnergyBreakdown e = energy(s);
    const double kinetic = e.translational + e.rotational;
    double bulk = 0;  // the momentum the motion carries now: what an unbalanced force is measured against
    for (std::size_t i = 0; i < s.particles.size(); ++i) bulk += s.particles.mass[i] * norm(s.particles.velocity[i]);
    return {{"momentum_drift", norm(dp) / std::max(bulk, momentum_scale_)},
            {"angular_momentum_drift", l0 > 0 ? norm(dl) / l0 : norm(dl)},
            {"kinetic_J", kinetic},
            {"gravitational_J", gravitational_energy(s.particles, kNewtonG)}};
}

nlohmann::json Coalescence::checkpoint_state() const {
    return {{"cloud", cloud_},
            {"gravity_accuracy", accuracy_},
            {"samples", samples_},
            {"coalesce_input", spec_.resolved},
            {"fidelity", options_.fidelity},
            {"initial_mass_kg", initial_mass_},
            {"initial_momentum", json_of(initial_linear_)},
            {"initial_angular_momentum", json_of(initial_angular_)},
            {"momentum_scale", momentum_scale_},
            {"escaped_momentum", json_of(removed_linear_)},
            {"escaped_angular_momentum", json_of(removed_angular_)},
            {"escaped_grains", escaped_},
            {"escaped_mass_kg", escaped_mass_},
            {"next_sample_s", next_sample_}};
}

}  // namespace

namespace {

// The figures the source compares across magnetisations (section 4.2): how fast the body
// gathers mass, how porous it is, how much of what is left outside sits in chains and clumps.
nlohmann::json Coalescence::summary() const {
    nlohmann::json out = {{"samples", samples_.size()},
                          {"escaped_grains", escaped_},
                          {"escaped_mass_fraction", escaped_mass_ / initial_mass_}};
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
    run.modifiers.push_back({"escape", [this](System& s, std::size_t) { escape(s); }});
    const RunOutcome outcome =
        run_protocol(*scene_, run, start_, [this](const System& s, std::size_t, long) { observe(s); });
    CoalesceOutcome out;
    out.exit_status = outcome.exit_status;
    nlohmann::json& r = out.report;
    r = outcome.report;
    r["mode"] = kMode;
    r["engine_inputs"] = r["inputs"];
    r["engine_inputs"]["grains"][0]["placement"]["positions"] = "(the cloud's lattice sites; cloud block)";
    r["inputs"] = spec_.resolved;
    r["fidelity"] = options_.fidelity;
    r["cloud"] = cloud_;
    r["gravity_accuracy"] = accuracy_;
    r["results"]["coalescence"] = summary();
    r["results"]["coalescence"]["series"] = samples_;
    if (!options_.report_path.empty()) {
        std::filesystem::path svg(options_.report_path);
        svg = svg.parent_path() / (svg.stem().string() + "_body.svg");
        write_plot(svg.string());
        r["plots"] = {{"body_fraction", svg.string()}};
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
    const CheckpointHeader header = read_checkpoint_header(checkpoint);
    if (!header.history.is_object() || header.history.value("mode", "") != kMode)
        throw SceneError("--resume", checkpoint + " was not written by `mrjam asteroid coalesce`");
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
