#include "asteroid/rubble_start.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "asteroid/asteroid_outcome.hpp"
#include "asteroid/coalesce_scene.hpp"
#include "core/format.hpp"
#include "gravity/self_gravity.hpp"
#include "io/checkpoint.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

void check_bound(const CloudEnergetics& e, const CoalesceSpec& spec) {
    if (e.virial_ratio < 1.0 || spec.allow_unbound) return;
    const double thermal = e.kinetic - e.spin_kinetic;
    const double room = 0.5 * e.binding - e.spin_kinetic;  // thermal energy that would leave the ratio at 0.5
    std::string fix;
    if (room > 0 && thermal > 0)
        fix = "a thermal_speed of " + format_number(spec.thermal_speed * std::sqrt(room / thermal), 3) +
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
void check_holds(const CloudEnergetics& e, const CoalesceSpec& spec, double dt) {
    const double held = spec.gravity_interval * dt;
    if (held > 0.01 * e.free_fall_time)
        throw SceneError("/self_gravity/update_interval",
                         "holds the self-gravity " + format_number(held, 3) + " s, more than 1 % of the cloud's " +
                             "free-fall time (" + format_number(e.free_fall_time, 3) + " s); lower it below " +
                             std::to_string(static_cast<long>(0.01 * e.free_fall_time / dt)));
}

// Tree against direct summation on the grains as they are: each grain's relative error.
nlohmann::json measure_gravity_accuracy(const System& s, const CoalesceSpec& spec) {
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

RubbleStart start_rubble(const CoalesceSpec& spec, int threads, const std::string& fidelity, const char* mode) {
    const CloudLayout layout = lay_out_cloud(spec);
    BuildOptions build;
    build.threads = threads;
    build.fidelity = fidelity;
    RubbleStart r;
    r.scene = std::make_unique<Scene>(build_scene(coalesce_engine_scene(spec, layout, mode), build));
    Particles& p = r.scene->system.particles;
    std::vector<char> thermal(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) thermal[i] = p.material[i] == 0;  // not the seed grain
    give_cloud_motion(p, thermal, spec.thermal_speed, spec.spin, spec.seed);
    r.energetics = cloud_energetics(p, spec.spin, kNewtonG);
    check_bound(r.energetics, spec);
    choose_timestep(*r.scene);
    check_holds(r.energetics, spec, r.scene->system.dt);
    r.escape_radius = layout.escape_radius;
    r.cloud = energetics_json(r.energetics, spec, p.size());
    r.cloud["escape_radius_m"] = layout.escape_radius;
    r.cloud["seed_grain_diameter_m"] = spec.seed_diameter;
    r.gravity_accuracy = measure_gravity_accuracy(r.scene->system, spec);
    return r;
}

std::unique_ptr<Scene> restore_rubble(const std::string& checkpoint, const nlohmann::json& resolved_scene,
                                      int threads) {
    BuildOptions build;
    build.threads = threads;
    build.insert_grains = false;
    auto scene = std::make_unique<Scene>(build_scene(resolved_scene, build));
    restore_scene(checkpoint, *scene);
    return scene;
}

void RubbleRun::begin(const CoalesceSpec& spec, int threads, const std::string& fidelity, const char* mode) {
    RubbleStart r = start_rubble(spec, threads, fidelity, mode);
    scene = std::move(r.scene);
    cloud = r.cloud;
    gravity_accuracy = r.gravity_accuracy;
    ledger.open(scene->system, r.escape_radius, r.energetics.radius);
}

void RubbleRun::restore(const std::string& checkpoint, const nlohmann::json& state, const CheckpointHeader& header,
                        int threads) {
    scene = restore_rubble(checkpoint, header.resolved_scene, threads);
    start = header.position;
    stage_log = header.history.at("stage_log");
    cloud = state.at("cloud");
    gravity_accuracy = state.at("gravity_accuracy");
    samples = state.at("samples");
    ledger = RubbleLedger::from_json(state.at("ledger"));
    next_sample = state.at("next_sample_s").get<double>();
}

nlohmann::json RubbleRun::save() const {
    return {{"cloud", cloud},
            {"gravity_accuracy", gravity_accuracy},
            {"samples", samples},
            {"ledger", ledger.to_json()},
            {"next_sample_s", next_sample}};
}

RunOptions RubbleRun::run_options(const char* mode, const std::string& scene_path, bool progress) {
    RunOptions run;
    run.mode = mode;
    run.scene_path = scene_path;
    run.progress = progress;
    run.resumed_stage_log = stage_log;
    run.modifiers.push_back({"escape", [this](System& s, std::size_t) { ledger.remove_escaped(s); }});
    return run;
}

nlohmann::json RubbleRun::report(const RunOutcome& outcome, const char* mode, const nlohmann::json& inputs,
                                 const std::string& fidelity) const {
    nlohmann::json r = asteroid_report(outcome, mode, inputs, fidelity);
    r["engine_inputs"]["grains"][0]["placement"]["positions"] = "(the cloud's lattice sites; cloud block)";
    r["cloud"] = cloud;
    r["gravity_accuracy"] = gravity_accuracy;
    return r;
}

void RubbleRun::draw_final_body(nlohmann::json& report, const std::string& report_path) const {
    const std::string views = body_views_beside(report_path, "final_body", scene->system,
                                                "The body at t = " + format_number(scene->system.time, 5) + " s");
    if (!views.empty()) report["plots"]["final_body"] = views;
}

}  // namespace mrjam
