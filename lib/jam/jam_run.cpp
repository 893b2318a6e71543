#include "jam/jam_run.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "fluid/valve_flow.hpp"
#include "integrator.hpp"
#include "jam/axial_resistance.hpp"
#include "jam/contact_clusters.hpp"
#include "jam/jam_picture.hpp"
#include "jam/throat_flux.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"

namespace mrjam {

namespace {

// Whether the largest cluster touches the constriction's wall on both sides of the gap (y > 0
// and y < 0, the field's direction): an arch spanning the throat.
bool spans_throat(const System& s, const ContactClusters& c, const ValveGeometry& v, const Wall& wall) {
    if (c.size.empty() || c.size[0] < 2) return false;
    bool upper = false, lower = false;
    const auto& p = s.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (c.label[i] != 0) continue;
        const Vec3& x = p.position[i];
        if (x.z < v.taper_start_z() - p.radius[i] || x.z > v.throat_end_z() + p.radius[i]) continue;
        double overlap;
        Vec3 n;
        if (!wall.touch(x, p.radius[i] * 1.05, overlap, n)) continue;  // touching, with 5 % slack
        if (x.y > 0) upper = true;
        if (x.y < 0) lower = true;
    }
    return upper && lower;
}

}  // namespace

JamOutcome run_jam(const JamScene& js, long long seed, const JamRunOptions& options) {
    nlohmann::json engine = js.engine_scene;
    engine["seed"] = seed;
    BuildOptions build;
    build.threads = options.threads;
    build.fidelity = js.tier;
    Scene scene = build_scene(engine, build);
    choose_timestep(scene);
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
        if (w.kind == Wall::Kind::passage) valve_wall = &w;
    // The carrier flow's resistance cells (lib/jam/axial_resistance.hpp): with the pressure
    // option they set the flow; with the prescribed flow they only measure what it would push
    // an arrested bed with.
    auto valve_flow = std::dynamic_pointer_cast<ValveFlow>(s.flow);
    const AxialResistance resistance(js.valve, js.slab_half_thickness, -js.valve.upstream_length,
                                     js.valve.downstream_length, js.flow.cell_length, js.feed_fraction,
                                     js.flow.supply_pressure);
    AxialResistanceState flow_state;
    struct FlowSample { double time, scale, stretch_pressure, max_fraction; };
    std::vector<FlowSample> flow_history;
    double next_report = 0.1e-3;
    auto observer = [&](const System& sys, std::size_t, long) {
        flux.observe(sys);
        if (!valve_flow) return;
        flow_state = resistance.update(sys, *valve_flow, js.flow.pressure_driven);
        if (js.flow.pressure_driven)
            flow_history.push_back({sys.time, flow_state.scale, flow_state.stretch_pressure, flow_state.max_fraction});
        // A line per 0.1 ms of simulated time: what a user watches for is the flux.
        if (options.progress && sys.time >= next_report) {
            next_report = sys.time + 0.1e-3;
            const double rate = flux.rate(std::min(0.1e-3, sys.time));
            std::cerr << "[jam] t = " << sys.time * 1e3 << " ms: grain flux " << rate << " /s";
            if (base_rate > 0) std::cerr << " (" << std::lround(100 * rate / base_rate) << " % of the no-field flux)";
            if (js.flow.pressure_driven)
                std::cerr << ", flow scale " << flow_state.scale << ", densest cell " << flow_state.max_fraction;
            std::cerr << "\n";
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
    const RunOutcome outcome = run_protocol(scene, run, {}, observer);

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
    r["largest_cluster_spans_throat"] = valve_wall ? spans_throat(s, clusters, js.valve, *valve_wall) : false;
    r["flux_history"] = {{"columns", {"time_s", "net_grains_passed"}}, {"rows", history},
                         {"partial", outcome.exit_status != 0}};
    r["field_switched_on_s"] = p.flow_time;
    r["flow_model"] = js.flow.pressure_driven
                          ? "pressure-driven (lib/jam/axial_resistance.hpp): the supply pressure drives the source's "
                            "profile through a circuit resistance sized for the prescribed flow plus the grains' "
                            "Kozeny-Carman resistance in axial cells"
                          : "prescribed (the source's profile, fluid/valve_flow.hpp; Stokes drag)";
    r["flow_profile"] = valve_flow && valve_flow->profile() == ValveFlow::Profile::conserving ? "conserving" : "source";
    // What the prescribed flow would push an arrested bed with: the cells' pressure drops summed
    // (the source tuned its flow so that this was about 100 kPa).
    r["arrested_bed_drag_pressure_Pa"] = flow_state.arrested_pressure;
    if (js.flow.pressure_driven) {
        r["supply_pressure_Pa"] = js.flow.supply_pressure;
        r["resistance_cells"] = resistance.cells();
        r["final_flow_scale"] = flow_state.scale;
        r["final_densest_cell_fraction"] = flow_state.max_fraction;
        nlohmann::json sh = nlohmann::json::array();
        const std::size_t step = std::max<std::size_t>(1, flow_history.size() / 200);
        for (std::size_t i = 0; i < flow_history.size(); i += step)
            sh.push_back({flow_history[i].time, flow_history[i].scale, flow_history[i].stretch_pressure,
                          flow_history[i].max_fraction});
        r["flow_history"] = {{"columns", {"time_s", "flow_scale", "stretch_pressure_Pa", "densest_cell_fraction"}},
                             {"rows", sh}};
    }
    r["supply"] = "periodic along the tube axis (steady feed at the mix's volume fraction)";
    if (!options.picture_path.empty() && s.particles.size() > 0) {
        write_throat_picture(options.picture_path, s, clusters, js.valve);
        out.report["outputs"]["throat_picture"] = options.picture_path;
    }
    return out;
}

}  // namespace mrjam
