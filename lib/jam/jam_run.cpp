#include "jam/jam_run.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "fluid/valve_flow.hpp"
#include "integrator.hpp"
#include "jam/contact_clusters.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_picture.hpp"
#include "jam/jam_snapshots.hpp"
#include "jam/throat_span.hpp"
#include "jam/throat_flux.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"

namespace mrjam {

namespace {

// The bore's cross-section inside the slab |x| < h: the chord region of the circle.
double slab_section(double r, double h) {
    if (h >= r) return M_PI * r * r;
    return 2.0 * (h * std::sqrt(r * r - h * h) + r * r * std::asin(h / r));
}

}  // namespace

JamOutcome run_jam(const JamScene& js, long long seed, const JamRunOptions& options) {
    nlohmann::json engine = js.engine_scene;
    engine["seed"] = seed;
    BuildOptions build;
    build.threads = options.threads;
    build.fidelity = js.tier;
    const bool resuming = !options.resume_checkpoint.empty();
    JamCheckpoint checkpoint;
    if (resuming) {
        // As `mrjam run --resume`: the grains, lists and step come from the checkpoint.
        checkpoint = read_jam_checkpoint(options.resume_checkpoint);
        build.insert_grains = false;
        engine = checkpoint.header.resolved_scene;
    }
    Scene scene = build_scene(engine, build);
    if (resuming) restore_state(options.resume_checkpoint, scene.system);
    choose_timestep(scene);
    if (resuming) restore_state(options.resume_checkpoint, scene.system);  // the list and step from the checkpoint win
    System& s = scene.system;
    const JamProtocol& p = js.protocol;

    // The magnet is switched on after the no-field flow and off when the flow has arrested.
    auto field = std::make_shared<SwitchedField>(s.magnetic.field, p.flow_time);
    s.magnetic.field = field;

    ThroatFlux flux(0.0);
    double base_rate = 0, arrest_time = -1, release_start = -1;
    long passed_at_switch_on = 0, passed_at_arrest = 0;
    bool jammed = false, released = false, undetermined = false;
    RunOptions run;
    run.mode = "jam";
    run.progress = options.progress;
    run.observe_every = p.observe_every;
    const Wall* valve_wall = nullptr;
    for (const auto& w : s.walls)
        if (w.kind == Wall::Kind::passage || w.kind == Wall::Kind::slot_passage) valve_wall = &w;
    // Pressure-limited flow: the fluid pushes the grains with the drag sum_i 6 pi mu R_i (s u_i - v_i)
    // along the axis; it cannot exceed the supply pressure times the section it acts on, so
    // the profile's scale is s = min(1, (P A + D_v) / D_1) (D_1: the drag of the unscaled flow on
    // grains at rest, D_v: that of their own motion). Free-flowing grains (v = u) leave s = 1;
    // an arrested bed slows the fluid until it carries exactly P A.
    auto valve_flow = std::dynamic_pointer_cast<ValveFlow>(s.flow);
    const double section = js.slab_half_thickness > 0 ? slab_section(js.valve.bore_radius(), js.slab_half_thickness)
                                                      : M_PI * js.valve.bore_radius() * js.valve.bore_radius();
    double prescribed_drag = 0;  // D_1 at the last observation, N
    std::vector<std::pair<double, double>> scale_history;
    auto observer = [&](const System& sys, std::size_t, long) {
        flux.observe(sys);
        if (!valve_flow) return;
        const auto& g = sys.particles;
        double d1 = 0, dv = 0;
        for (std::size_t i = 0; i < g.size(); ++i) {
            const double c = 6.0 * M_PI * sys.physics.viscosity * g.radius[i];
            d1 += c * valve_flow->unscaled(g.position[i]).z;
            dv += c * g.velocity[i].z;
        }
        prescribed_drag = d1;
        if (js.flow.pressure_limited && d1 > 0) {
            const double scale = std::clamp((js.flow.supply_pressure * section + dv) / d1, 0.0, 1.0);
            valve_flow->set_scale(scale);
            scale_history.push_back({sys.time, scale});
        }
    };
    run.stage_finished = [&](const System& sys, std::size_t stage) {
        const double t = sys.time;
        if (stage == 0) return false;
        if (stage == 1) {
            if (base_rate == 0) {
                // The no-field flux over the second half of the flow period: the reference.
                base_rate = flux.rate_between(0.5 * p.flow_time, p.flow_time);
                passed_at_switch_on = flux.passed();
                if (!(base_rate > 0)) {  // nothing to compare an arrest with
                    undetermined = true;
                    return true;
                }
            }
            if (t - p.flow_time < p.arrest_window) return false;
            if (flux.rate(p.arrest_window) < p.arrest_fraction * base_rate) {
                jammed = true;
                arrest_time = t - p.arrest_window - p.flow_time;  // the low-flux window's start
                passed_at_arrest = flux.passed();
                field->switch_off_at(t);
                release_start = t;
                return true;
            }
            return false;
        }
        // Release: the field is off; has the flux come back?
        if (!jammed || undetermined) return true;
        if (t - release_start < p.arrest_window) return false;
        if (flux.rate(p.arrest_window) > p.release_fraction * base_rate) {
            released = true;
            return true;
        }
        return false;
    };
    // ---- Snapshots and checkpoint/resume (kept apart from the flow controller above) ----
    JamSnapshots snapshots;
    if (!options.snapshot_directory.empty()) snapshots = JamSnapshots(options.snapshot_directory, options.snapshot_every, seed);
    // Everything the protocol carries from one observation to the next that the engine's
    // checkpoint does not: restored below, it makes the resumed run take the same decisions.
    auto protocol_state = [&] {
        const double off = field->switch_off_time();
        nlohmann::json sh = nlohmann::json::array();
        for (const auto& [t, v] : scale_history) sh.push_back({t, v});
        return nlohmann::json{
            {"seed", seed}, {"flux", flux.save()}, {"base_rate", base_rate}, {"arrest_time", arrest_time},
            {"release_start", release_start}, {"passed_at_switch_on", passed_at_switch_on}, {"passed_at_arrest", passed_at_arrest},
            {"jammed", jammed}, {"released", released}, {"undetermined", undetermined},
            {"field_off_s", std::isfinite(off) ? nlohmann::json(off) : nlohmann::json(nullptr)},
            {"flow_scale", valve_flow ? valve_flow->scale() : 1.0}, {"prescribed_drag", prescribed_drag},
            {"scale_history", sh}, {"snapshots", snapshots.save()}};
    };
    ProtocolPosition start;
    if (resuming) {
        const nlohmann::json& st = checkpoint.state;
        flux.restore(st.at("flux"));
        base_rate = st.at("base_rate");
        arrest_time = st.at("arrest_time");
        release_start = st.at("release_start");
        passed_at_switch_on = st.at("passed_at_switch_on");
        passed_at_arrest = st.at("passed_at_arrest");
        jammed = st.at("jammed");
        released = st.at("released");
        undetermined = st.at("undetermined");
        if (!st.at("field_off_s").is_null()) field->switch_off_at(st["field_off_s"].get<double>());
        if (valve_flow) valve_flow->set_scale(st.at("flow_scale").get<double>());
        prescribed_drag = st.at("prescribed_drag");
        scale_history = st.at("scale_history").get<std::vector<std::pair<double, double>>>();
        snapshots.restore(st.at("snapshots"));
        start = checkpoint.header.position;
        run.resumed_stage_log = checkpoint.stage_log;
    }
    run.checkpoint_state = [&] { return nlohmann::json{{"protocol", protocol_state()}, {"campaign", options.campaign}}; };
    auto observe_all = [&](const System& sys, std::size_t stage, long step) {
        observer(sys, stage, step);
        snapshots.observe(sys);
    };
    auto protocol_finished = run.stage_finished;
    run.stage_finished = [&](const System& sys, std::size_t stage) {
        const bool was_jammed = jammed;
        const bool done = protocol_finished(sys, stage);
        if (jammed && !was_jammed) snapshots.write_tagged(sys, "arrest");
        return done;
    };
    const RunOutcome outcome = run_protocol(scene, run, start, observe_all);
    if (outcome.exit_status == 0) snapshots.write_tagged(s, "end");

    JamOutcome out;
    out.report = outcome.report;
    out.exit_status = outcome.exit_status;
    out.jammed = jammed;
    out.time_to_arrest = arrest_time;
    const ContactClusters clusters = contact_clusters(s);
    nlohmann::json history = nlohmann::json::array();
    const auto& h = flux.history();
    const std::size_t stride = std::max<std::size_t>(1, h.size() / 400);  // keep the report readable
    for (std::size_t i = 0; i < h.size(); i += stride) history.push_back({h[i].first, h[i].second});
    nlohmann::json& r = out.report["results"];
    r["jammed"] = jammed;
    r["time_to_arrest_s"] = jammed ? nlohmann::json(arrest_time) : nlohmann::json(nullptr);
    r["grains_passed_before_arrest"] = jammed ? nlohmann::json(passed_at_arrest - passed_at_switch_on) : nlohmann::json(nullptr);
    r["grains_passed_total"] = flux.passed();
    r["no_field_flux_grains_per_s"] = base_rate;
    r["released"] = jammed ? nlohmann::json(released) : nlohmann::json(nullptr);
    r["outcome"] = undetermined ? "undetermined" : !jammed ? "fail-no-jam" : (released ? "success" : "fail-irreversible");
    if (undetermined)
        out.report["warnings"].push_back("no grains crossed the throat during the no-field flow, so an arrest cannot be "
                                         "told from a blocked start: lengthen protocol/flow_time or check the flow");
    r["largest_cluster"] = clusters.size.empty() ? 0 : clusters.size[0];
    r["clusters"] = clusters.size.size();
    r["largest_cluster_spans_throat"] = valve_wall ? cluster_spans_throat(s, clusters, js.valve, *valve_wall) : false;
    r["flux_history"] = {{"columns", {"time_s", "net_grains_passed"}}, {"rows", history},
                         {"partial", outcome.exit_status != 0}};
    r["field_switched_on_s"] = p.flow_time;
    r["flow_model"] = js.flow.pressure_limited ? "pressure-limited (source's profile, slowed so the drag on the grains "
                                                 "does not exceed the supply pressure on the section)"
                                               : "prescribed (source's profile, fluid/valve_flow.hpp)";
    // What the prescribed flow would push an arrested bed with, as a pressure on the section
    // (the source tuned its flow so that this was about 100 kPa).
    r["arrested_bed_drag_pressure_Pa"] = valve_flow ? nlohmann::json(prescribed_drag / section) : nlohmann::json(nullptr);  // null: slot orifice
    if (js.flow.pressure_limited) {
        r["supply_pressure_Pa"] = js.flow.supply_pressure;
        r["final_flow_scale"] = valve_flow ? valve_flow->scale() : 1.0;
        nlohmann::json sh = nlohmann::json::array();
        const std::size_t step = std::max<std::size_t>(1, scale_history.size() / 200);
        for (std::size_t i = 0; i < scale_history.size(); i += step) sh.push_back({scale_history[i].first, scale_history[i].second});
        r["flow_scale_history"] = sh;
    }
    r["supply"] = "periodic along the tube axis (steady feed at the mix's volume fraction)";
    if (snapshots.enabled()) out.report["outputs"]["snapshots"] = snapshots.written();
    if (!options.picture_path.empty() && s.particles.size() > 0) {
        write_throat_picture(options.picture_path, s, clusters, js.valve);
        out.report["outputs"]["throat_picture"] = options.picture_path;
    }
    return out;
}

}  // namespace mrjam
