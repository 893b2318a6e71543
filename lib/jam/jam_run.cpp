#include "jam/jam_run.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

#include "core/format.hpp"
#include "fluid/valve_flow.hpp"
#include "integrator.hpp"
#include "jam/axial_resistance.hpp"
#include "jam/batch_outlet.hpp"
#include "jam/closed_flow.hpp"
#include "jam/contact_clusters.hpp"
#include "jam/coupled_flow.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_engine_scene.hpp"
#include "jam/jam_outcome.hpp"
#include "jam/jam_picture.hpp"
#include "jam/jam_protocol_state.hpp"
#include "jam/jam_snapshots.hpp"
#include "jam/steady_flow.hpp"
#include "jam/throat_flux.hpp"
#include "jam/throat_span.hpp"
#include "observers.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

// A figure that may not exist (NaN: no samples to form it) as a number or null.
nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

// When the arrest was called (the end of its low-flux window): the hold runs from here to the
// release. Only meaningful once st.jammed.
double arrest_called_at(const JamProtocolState& st, const JamProtocol& p) { return st.release_start - p.hold_time; }

// The hold (protocol/hold_time): with the field kept on after the arrest, did the grains stay put,
// and how much fluid does the valve pass at its end? Null until a run has held that long.
nlohmann::json hold_results(const JamProtocolState& st, const JamProtocol& p, double supply_pressure) {
    const auto& h = st.flux.history();
    if (!st.jammed || h.empty() || h.back().first < st.release_start) return nullptr;
    const double called = arrest_called_at(st, p), limit = p.arrest_fraction * st.base_rate;
    const double rate = st.flux.rate_between(called, st.release_start);
    // When the bed first gave way, and the supply then: what a ramped hold
    // (protocol/hold_pressure_ramp) measures. Given way means flowing again by the release test's
    // measure (release_fraction of the no-field flux over an arrest window), not the arrest's
    // 5 %: a held bed settles by a few grains after the arrest, more than 5 % of a window's flux.
    const double gave_way =
        st.flux.first_time_above(called, st.release_start, p.arrest_window, p.release_fraction * st.base_rate) - called;
    // As a share of the open flow at the pressure held (the circuit is linear: P_hold / P times
    // the open flow at the supply pressure).
    const double leak =
        closed_flow_share(st.flow_history, p.flow_time, st.release_start - p.arrest_window, p.arrest_window) /
        (p.hold_pressure / supply_pressure);
    // Held: the grains stayed put on average and the bed never gave way (one that gives way and
    // re-forms let a burst through, which the experiment would have seen as fluid getting past).
    return {{"held", rate < limit && !std::isfinite(gave_way)},
            {"flux_share", rate / st.base_rate},
            {"gave_way_after_s", number_or_null(gave_way)},
            {"gave_way_at_pressure_Pa",
             number_or_null(std::isfinite(gave_way) ? p.supply_after_arrest(gave_way, supply_pressure) : gave_way)},
            {"pressure_Pa", p.hold_pressure},
            {"pressure_ramp_s", p.hold_pressure_ramp},
            {"closed_flow_share_at_end", number_or_null(leak)}};
}

// An arrest is a window whose grain count falls below arrest_fraction of the no-field count.
// With few grains per window a flowing bed's count is zero by chance (Poisson: e^-20 ~ 2e-9 at 20
// grains, e^-5 ~ 7e-3 at 5, tested at every observation), so the arrest may be noise; likewise a
// reference period that would carry fewer than this many grains across says nothing by passing none.
constexpr double kFewestGrainsPerWindow = 20;

// What the run says about the valve, for the outcome's words and the jam probability; `hold` is
// hold_results() (null without a hold, or before the run has held that long).
JamVerdict jam_verdict(const JamProtocolState& st, const JamScene& js, const nlohmann::json& hold, bool incomplete,
                       bool blew_up) {
    const JamProtocol& p = js.protocol;
    JamVerdict v;
    v.field_free = !(js.peak_flux_density > 0);
    v.clogged = st.undetermined && st.reference_expected >= kFewestGrainsPerWindow;
    v.undetermined = st.undetermined && !v.clogged;
    v.incomplete = incomplete;
    v.blew_up = blew_up;
    v.jammed = st.jammed;
    v.hold_asked = p.hold_time > 0;
    v.held = hold.is_object() && hold["held"].get<bool>();
    v.released = st.released;
    return v;
}

// A window of the no-field flux holding fewer than kFewestGrainsPerWindow grains.
std::string sparse_window_warning(double base_rate, const JamProtocol& p) {
    const double per_window = base_rate * p.arrest_window;
    if (!(base_rate > 0) || per_window >= kFewestGrainsPerWindow) return {};
    return "the no-field flux passes only " + format_number(per_window) +
           " grains per protocol/arrest_window, so an arrest can be counting noise: lengthen the window to at least " +
           format_number(kFewestGrainsPerWindow / base_rate * 1e3) + " ms";
}

// A jet (the coupled flow's, or the prescribed converging profile's) cut short by a tube length
// the scene fixed (lib/jam/jam_scene.cpp keeps it): the grains pile up where the stream slows,
// which blew up the 10 um mix, and a 44 um 20x case with a 24 um jet (docs/notes/jam_measurements.md).
std::string short_jet_warning(const JamScene& js) {
    if (js.valve.is_slot() || !(js.flow.jet_length > 0) || js.flow.jet_length >= js.valve.taper_length) return {};
    return std::string(js.flow.coupled ? "the coupled flow's" : "the converging profile's") + " jet re-opens over " +
           format_number(js.flow.jet_length * 1e3) + " mm, shorter than the taper (" +
           format_number(js.valve.taper_length * 1e3) +
           " mm), because the scene fixes the tube's length: grains can pile up past the orifice; give "
           "model/downstream_length at least " +
           format_number((js.valve.throat_end_z() + js.valve.taper_length + 2.0 * js.flow.cell_length) * 1e3) +
           " mm, or drop it";
}

// An error in the generated engine scene, named by the jam scene's key the user wrote: a packing
// it cannot make is the feed's volume fraction, a stage with too many steps its protocol time
// (the stages of jam_stages(): flow, then magnetise and pressure or field_on, then release).
SceneError as_jam_key(const SceneError& e, const JamProtocol& p) {
    const std::string& path = e.path();
    if (path.starts_with("/grains/") && path.ends_with("/placement/volume_fraction"))
        return e.at("/grains/volume_fraction");
    const nlohmann::json stages = jam_stages(p);
    for (std::size_t k = 0; k < stages.size(); ++k) {
        if (path != "/stages/" + std::to_string(k) + "/duration") continue;
        const std::string name = stages[k]["name"];
        return e.at(name == "flow"        ? "/protocol/flow_time"
                    : name == "magnetise" ? "/protocol/magnetise_time"
                    : name == "release"   ? "/protocol/release_time"
                                          : "/protocol/max_time");
    }
    return e;
}

// What each engine stage is to the protocol (jam_stages): the no-field reference flow, the
// magnetisation at rest (closed first), the judged period (pressure on, or field on open first),
// and the release.
enum class JamPhase { reference, magnetise, judged, release };
JamPhase jam_phase(const JamProtocol& p, std::size_t stage) {
    if (stage == 0) return JamPhase::reference;
    if (p.order == JamOrder::closed_first)
        return stage == 1 ? JamPhase::magnetise : stage == 2 ? JamPhase::judged : JamPhase::release;
    return stage == 1 ? JamPhase::judged : JamPhase::release;
}

// Relative change from a to b; 0 when both are 0 (no contacts, or no field, stays settled).
double relative_change(double a, double b) {
    const double scale = std::max(std::abs(a), std::abs(b));
    return scale > 0 ? std::abs(b - a) / scale : 0.0;
}

// The relative change of the mean contact number and of the magnetic energy over the last settle
// window; none before two checks.
std::optional<std::pair<double, double>> last_settle_change(const JamProtocolState& st) {
    const std::size_t n = st.settle_history.size();
    if (n < 2) return std::nullopt;
    const SettleSample &a = st.settle_history[n - 2], &b = st.settle_history[n - 1];
    return std::pair{relative_change(a.coordination, b.coordination),
                     relative_change(a.magnetic_energy, b.magnetic_energy)};
}

// Closed first: a settle check every protocol/settle_window from the start of the magnetisation.
// Settled once both the mean contact number and the magnetic energy changed by less than
// settle_tolerance over the last window, after at least two windows.
bool magnetised_structure_settled(JamProtocolState& st, const System& sys, const JamProtocol& p) {
    if (!st.settle_history.empty() && sys.time < st.settle_history.back().time + p.settle_window) return false;
    st.settle_history.push_back({sys.time, mean_coordination(sys), induced_magnetic_energy(sys)});
    if (st.settle_history.size() < 3) return false;
    const auto change = last_settle_change(st);
    return change->first < p.settle_tolerance && change->second < p.settle_tolerance;
}

// The no-field reference, taken once at the first observation after the flow period: its flux
// over the period's second half, and whether none crossed (a clog, or too slow a flow to tell).
void take_reference(JamProtocolState& st, const JamScene& js, const System& sys, bool progress) {
    const JamProtocol& p = js.protocol;
    st.base_rate = st.flux.rate_between(0.5 * p.flow_time, p.flow_time);
    if (progress)
        if (const std::string w = sparse_window_warning(st.base_rate, p); !w.empty())
            std::cerr << "[jam] warning: " << w << "\n";
    st.undetermined = !(st.base_rate > 0);
    st.reference_expected = static_cast<double>(sys.particles.size()) /
                            (js.valve.upstream_length + js.valve.downstream_length) * js.flow.bore_speed * 0.5 *
                            p.flow_time;
}

// The judged period (pressure on, or field on): an arrest switches the field off after the hold;
// a steady flow ends the period as no jam. True ends the stage.
bool judge_arrest(JamProtocolState& st, const JamProtocol& p, SwitchedField& field, double t) {
    if (st.judged_from < 0) {
        if (p.order == JamOrder::closed_first && st.magnetise_end < 0)
            st.magnetise_end = p.flow_time + p.magnetise_time;
        st.judged_from = p.order == JamOrder::closed_first ? st.magnetise_end : p.flow_time;
        st.passed_at_switch_on = st.flux.passed();
    }
    if (t - st.judged_from < p.arrest_window) return false;
    if (st.flux.rate(p.arrest_window) < p.arrest_fraction * st.base_rate) {
        st.jammed = true;
        st.arrest_time = t - p.arrest_window - st.judged_from;  // the low-flux window's start
        st.passed_at_arrest = st.flux.passed();
        st.upstream_at_arrest = st.upstream_now;
        // The field stays on for the hold (protocol/hold_time; 0 by default), then goes off.
        field.switch_off_at(t + p.hold_time);
        st.release_start = t + p.hold_time;
        return true;
    }
    // Or a steady flow that has not arrested: no jam, without waiting for max_time.
    st.steady = steady_flow(st.flux, st.flow_history, st.judged_from, {p.steady_window, p.steady_tolerance}).steady;
    return st.steady;
}

// The protocol's decision at an observation in `phase`: true ends the engine's current stage.
bool protocol_stage_finished(JamProtocolState& st, const JamScene& js, SwitchedField& field, const System& sys,
                             JamPhase phase, bool progress) {
    const JamProtocol& p = js.protocol;
    const double t = sys.time;
    if (phase == JamPhase::reference) return false;
    if (st.base_rate == 0 && !st.undetermined) take_reference(st, js, sys, progress);
    if (st.undetermined) return true;
    if (phase == JamPhase::magnetise) {
        st.settled = magnetised_structure_settled(st, sys, p);
        if (st.settled) {
            st.magnetise_end = t;
            if (progress)
                std::cerr << "[jam] magnetised structure settled after " << format_number((t - p.flow_time) * 1e3, 3)
                          << " ms at rest; pressure on\n";
        }
        return st.settled;
    }
    if (phase == JamPhase::judged) return judge_arrest(st, p, field, t);
    // Release: the field is off; has the flux come back?
    if (!st.jammed) return true;
    if (t - st.release_start < p.arrest_window) return false;
    st.released = st.flux.rate(p.arrest_window) > p.release_fraction * st.base_rate;
    return st.released;
}

// The report's account of the magnetisation at rest (closed first), with the criterion's values.
nlohmann::json magnetisation_results(const JamProtocolState& st, const JamProtocol& p) {
    nlohmann::json rows = nlohmann::json::array();
    for (const SettleSample& x : st.settle_history) rows.push_back({x.time, x.coordination, x.magnetic_energy});
    nlohmann::json last_change = nullptr;
    if (const auto change = last_settle_change(st))
        last_change = {{"coordination", change->first}, {"magnetic_energy", change->second}};
    return {{"criterion",
             "mean contact number and magnetic energy (-1/2 sum m.B0) each change by less than "
             "protocol/settle_tolerance over one protocol/settle_window, after at least two windows"},
            {"settled", st.settled},
            {"duration_s", st.magnetise_end >= 0 ? nlohmann::json(st.magnetise_end - p.flow_time) : nullptr},
            {"last_window_change", last_change},
            {"history", {{"columns", {"time_s", "mean_coordination", "magnetic_energy_J"}}, {"rows", rows}}}};
}

// Closed first, a structure still changing when protocol/magnetise_time ran out met the pressure
// unsettled: said with the criterion's values. Empty otherwise (settled, open first, or not yet there).
std::string unsettled_warning(const JamProtocolState& st, const JamProtocol& p) {
    const auto change = last_settle_change(st);
    if (p.order != JamOrder::closed_first || st.settled || st.magnetise_end < 0 || !change) return {};
    return "the magnetised structure had not settled by protocol/magnetise_time (" +
           format_number(p.magnetise_time * 1e3) +
           " ms): over its last settle window the mean contact number changed by " +
           format_number(100 * change->first, 2) + " % and the magnetic energy by " +
           format_number(100 * change->second, 2) + " %, against " + format_number(100 * p.settle_tolerance) +
           " % (protocol/settle_tolerance); lengthen magnetise_time";
}

// The flux is counted at observations: a window (or the no-field reference, the flow period's
// second half) that holds only a few of them reads the same count at both ends, a zero rate, and
// so a false arrest. Refused before the run, now that the step is known.
void check_observation_interval(const JamProtocol& p, double dt) {
    constexpr double kObservationsPerWindow = 4;
    const double interval = p.observe_every * dt;
    const double shortest = std::min(p.arrest_window, 0.5 * p.flow_time);
    if (interval * kObservationsPerWindow <= shortest) return;
    const long most = static_cast<long>(std::floor(shortest / (kObservationsPerWindow * dt)));
    if (most >= 1)
        throw SceneError("/protocol/observe_every_steps",
                         "observes the flux every " + format_number(interval * 1e6) + " us (step " +
                             format_number(dt * 1e9) +
                             " ns), fewer than 4 times per arrest window or half flow time (" +
                             format_number(shortest * 1e6) + " us): give at most " + format_number(most));
    const bool flow_is_shorter = 0.5 * p.flow_time < p.arrest_window;
    throw SceneError(
        flow_is_shorter ? "/protocol/flow_time" : "/protocol/arrest_window",
        std::string(flow_is_shorter ? "is shorter than 8 steps of " : "is shorter than 4 steps of ") +
            format_number(dt * 1e9) + " ns" +
            (flow_is_shorter ? " (its second half is the no-field reference, observed at least 4 times)" : "") +
            ": lengthen it");
}

// The report's results: outcome, flux history, arch, and the carrier flow's model and state.
void write_jam_results(nlohmann::json& report, const JamProtocolState& st, const ClusterView& view, const JamScene& js,
                       std::size_t resistance_cells, const ValveFlow* valve_flow, bool incomplete, bool blew_up) {
    nlohmann::json history = nlohmann::json::array();
    const auto& h = st.flux.history();
    const std::size_t stride = std::max<std::size_t>(1, h.size() / 400);  // keep the report readable
    for (std::size_t i = 0; i < h.size(); i += stride) history.push_back({h[i].first, h[i].second});
    nlohmann::json& r = report["results"];
    r["jammed"] = st.jammed;
    r["time_to_arrest_s"] = st.jammed ? nlohmann::json(st.arrest_time) : nlohmann::json(nullptr);
    r["grains_passed_before_arrest"] =
        st.jammed ? nlohmann::json(st.passed_at_arrest - st.passed_at_switch_on) : nlohmann::json(nullptr);
    r["grains_passed_total"] = st.flux.passed();
    r["no_field_flux_grains_per_s"] = st.base_rate;
    r["no_field_flux_measured_over"] = "the second half of the no-field flow that opens the run (protocol/flow_time)";
    r["released"] = st.jammed ? nlohmann::json(st.released) : nlohmann::json(nullptr);
    // Why the field period ended: an arrest, a steady flow (protocol/steady_window) or max_time.
    r["field_period_ended_by"] = st.jammed         ? "arrest"
                                 : st.steady       ? "steady flow"
                                 : st.undetermined ? "no no-field flux to compare with"
                                 : blew_up         ? "blow-up"
                                 : incomplete      ? "interruption"
                                                   : "max_time";
    const nlohmann::json hold =
        js.protocol.hold_time > 0 ? hold_results(st, js.protocol, js.flow.supply_pressure) : nlohmann::json(nullptr);
    const JamVerdict verdict = jam_verdict(st, js, hold, incomplete, blew_up);
    r["outcome"] = jam_outcome_word(verdict);
    r["stops_flow"] = jam_stops_flow(verdict);
    if (st.steady)
        report["warnings"].push_back(
            "the field period ended on a steady flow (protocol/steady_window), which was "
            "taken as no jam: arrests can come late after a long steady flow (on the bundled "
            "cases every window up to 1 ms missed one; docs/notes/jam_measurements.md), so confirm a no-jam "
            "outcome with steady_window 0");
    for (const std::string& w :
         {sparse_window_warning(st.base_rate, js.protocol), short_jet_warning(js), saturated_field_warning(js)})
        if (!w.empty()) report["warnings"].push_back(w);
    r["reference_grains_expected"] = st.reference_expected;
    if (st.undetermined && verdict.clogged)
        report["warnings"].push_back(
            "no grain crossed the throat over the second half of the no-field flow, where the carrier would "
            "have brought about " +
            format_number(st.reference_expected, 3) +
            ": the constriction clogs without the field (outcome clog; it would not open)");
    else if (st.undetermined)
        report["warnings"].push_back(
            "no grains crossed the throat during the no-field flow, and the carrier would have brought only about " +
            format_number(st.reference_expected, 3) +
            ", so an arrest cannot be told from a blocked start: lengthen protocol/flow_time or check the flow");
    r["largest_cluster"] = view.largest;
    r["clusters"] = view.count;
    r["largest_cluster_spans_throat"] = view.spans;
    r["clusters_seen_at"] = st.arrest_view.valid ? "arrest" : "end of run";
    r["flux_history"] = {{"columns", {"time_s", "net_grains_passed"}}, {"rows", history}, {"partial", incomplete}};
    r["field_switched_on_s"] = js.protocol.flow_time;
    const bool closed_first = js.protocol.order == JamOrder::closed_first;
    r["order"] = closed_first ? "closed_first" : "open_first";
    // Time to arrest and grains passed count from here: the pressure applied (closed first) or
    // the field switched on (open first).
    r["judged_from_s"] = number_or_null(st.judged_from >= 0 ? st.judged_from : std::nan(""));
    if (closed_first) r["magnetisation"] = magnetisation_results(st, js.protocol);
    if (const std::string w = unsettled_warning(st, js.protocol); !w.empty()) report["warnings"].push_back(w);
    // How much still got through with the field on, window by window (the arrest test's window
    // and measure), up to the arrest or the end of the field period: for a valve that does not
    // jam, the figure a designer weighs (a creep of 5 % against a flow at 90 %).
    const double field_end = st.jammed ? arrest_called_at(st, js.protocol) : (h.empty() ? 0.0 : h.back().first);
    const double judged_from = st.judged_from >= 0 ? st.judged_from : js.protocol.flow_time;
    const auto shares = st.flux.window_shares(judged_from, field_end, js.protocol.arrest_window, st.base_rate);
    r["flux_share_with_field"] = {{"window_s", js.protocol.arrest_window},
                                  {"columns", {"window_end_s", "share_of_no_field_flux"}},
                                  {"rows", shares}};
    r["flux_share_last_window"] = shares.empty() ? nlohmann::json(nullptr) : nlohmann::json(shares.back().second);
    r["flow_model"] = js.flow.coupled
                          ? "coupled (lib/jam/coupled_flow.hpp): the supply pressure drives the fluid through a "
                            "circuit resistance sized for the bore flow in clear fluid plus the stretch, where each "
                            "slice's radial Brinkman equation with the grains' Kozeny-Carman drag sets the profile "
                            "and the fluid feels the grains' drag reversed"
                      : js.flow.pressure_driven
                          ? "pressure-driven (lib/jam/axial_resistance.hpp): the supply pressure drives the "
                            "flow_profile through a circuit resistance sized for the prescribed flow plus the grains' "
                            "Kozeny-Carman resistance in axial cells"
                          : "prescribed (the flow_profile at the bore speed, fluid/valve_flow.hpp; Stokes drag)";
    r["flow_profile"] = js.flow.coupled ? "brinkman (solved)"
                        : valve_flow    ? valve_flow_profile_name(valve_flow->profile())
                                        : "conserving";
    if ((valve_flow && valve_flow->profile() == ValveFlow::Profile::converging) || js.flow.coupled)
        r["jet_length_m"] = js.flow.jet_length;
    // What the prescribed flow would push an arrested bed with: the cells' pressure drops summed
    // (the source tuned its flow so that this was about 100 kPa).
    r["arrested_bed_drag_pressure_Pa"] =
        valve_flow || js.flow.coupled ? nlohmann::json(st.flow_state.arrested_pressure) : nlohmann::json(nullptr);
    if (js.flow.pressure_driven) {
        r["supply_pressure_Pa"] = js.flow.supply_pressure;
        r["resistance_cells"] = resistance_cells;
        if (js.flow.coupled) r["rings_per_slice"] = js.flow.rings;
        r["final_flow_scale"] = st.flow_state.scale;
        // The leak of the closed valve: does the jam stop the fluid as well as the grains?
        const double leak = st.jammed
                                ? closed_flow_share(st.flow_history, js.protocol.flow_time,
                                                    js.protocol.flow_time + st.arrest_time, js.protocol.arrest_window)
                                : std::nan("");
        r["closed_flow_share"] = number_or_null(leak);
        r["final_densest_cell_fraction"] = st.flow_state.max_fraction;
        nlohmann::json sh = nlohmann::json::array();
        const std::size_t step = std::max<std::size_t>(1, st.flow_history.size() / 200);
        for (std::size_t i = 0; i < st.flow_history.size(); i += step)
            sh.push_back({st.flow_history[i].time, st.flow_history[i].scale, st.flow_history[i].stretch_pressure,
                          st.flow_history[i].max_fraction});
        r["flow_history"] = {{"columns", {"time_s", "flow_scale", "stretch_pressure_Pa", "densest_cell_fraction"}},
                             {"rows", sh}};
    }
    r["supply"] = js.batch_supply ? "a finite batch (model/supply): the grains filled at the start, those reaching "
                                    "the outlet past the throat taken out, none fed in"
                                  : "periodic along the tube axis (steady feed at the mix's volume fraction)";
    if (js.protocol.hold_time > 0) {
        r["hold"] = hold;
        if (hold.is_object() && !hold["held"].get<bool>()) {
            // It gave way (and may have re-formed), or it crept through the hold without ever
            // flowing by the release test's measure.
            const double share = hold["flux_share"].get<double>();
            std::ostringstream why;
            why << "the arrest did not hold: with the field still on, ";
            if (hold["gave_way_after_s"].is_number())
                why << "the bed gave way " << hold["gave_way_after_s"].get<double>() * 1e3
                    << " ms after the arrest, at a supply of " << hold["gave_way_at_pressure_Pa"].get<double>() / 1e3
                    << " kPa (grain flux over protocol/hold_time " << std::lround(100 * share)
                    << " % of the no-field flux)";
            else
                why << "the grain flux over protocol/hold_time came back to " << std::lround(100 * share)
                    << " % of the no-field flux, above arrest_fraction, without the bed giving way (it crept)";
            report["warnings"].push_back(
                why.str() +
                "; the valve does not hold at this pressure (outcome fail-no-hold; it does not count towards the "
                "jam probability)");
        }
    }
}

std::unique_ptr<CoupledFlow> make_coupled_flow(const JamScene& js, double viscosity) {
    CoupledFlowSettings c;
    c.slab_half_thickness = js.slab_half_thickness;
    c.z_lo = -js.valve.upstream_length;
    c.z_hi = js.valve.downstream_length;
    c.cell_length = js.flow.cell_length;
    c.rings = js.flow.rings;
    c.feed_fraction = js.feed_fraction;
    c.supply_pressure = js.flow.supply_pressure;
    c.viscosity = viscosity;
    c.bore_speed = js.flow.bore_speed;
    c.wall_gap = js.flow.wall_gap;
    c.jet_length = js.flow.jet_length;
    return std::make_unique<CoupledFlow>(js.valve, c);
}

// Where the coupled flow spent the pressure, slice by slice, at its last update.
void write_coupled_slices(nlohmann::json& results, const CoupledFlow& coupled) {
    nlohmann::json rows = nlohmann::json::array();
    const auto& slices = coupled.field()->slices();
    if (coupled.slice_pressure().size() == slices.size())  // not before the first update
        for (std::size_t k = 0; k < slices.size(); ++k)
            rows.push_back(
                {slices[k].centre(), slices[k].radius, coupled.slice_fraction()[k], coupled.slice_pressure()[k]});
    results["coupled_slices"] = {{"columns", {"z_m", "stream_radius_m", "volume_fraction", "pressure_drop_Pa"}},
                                 {"rows", rows}};
    results["clear_stretch_pressure_Pa"] = coupled.clear_stretch_pressure();
}

// A finite batch's counts (model/supply "batch"), taken at the observations as the flux is. An
// arrest with most of the batch gone upstream may be the feed running out rather than an arch:
// the warning says so.
void write_batch_results(nlohmann::json& report, const JamProtocolState& st, const BatchOutlet& outlet,
                         std::size_t grains_left) {
    report["results"]["batch"] = {{"outlet_z_m", outlet.z()},
                                  {"grains_at_start", st.drained + static_cast<long>(grains_left)},
                                  {"grains_drained", st.drained},
                                  {"grains_left", grains_left},
                                  {"upstream_of_throat_centre_at_start", st.upstream_at_start},
                                  {"upstream_of_throat_centre_at_arrest",
                                   st.jammed ? nlohmann::json(st.upstream_at_arrest) : nlohmann::json(nullptr)},
                                  {"upstream_of_throat_centre_at_end", st.upstream_now}};
    if (st.jammed && 2 * st.upstream_at_arrest < st.upstream_at_start)
        report["warnings"].push_back(
            "the batch had lost " +
            std::to_string(std::lround(100.0 * (st.upstream_at_start - st.upstream_at_arrest) /
                                       std::max(1L, st.upstream_at_start))) +
            " % of its grains upstream of the throat by the arrest: the flux may have stopped because the feed "
            "ran out, not because an arch held; lengthen model/upstream_length");
}

}  // namespace

nlohmann::json jam_seed_record(const JamOutcome& outcome) {
    const nlohmann::json& r = outcome.report.at("results");
    return {{"outcome", r["outcome"]},
            {"time_to_arrest_s", r["time_to_arrest_s"]},
            {"flux_share_last_window", r.value("flux_share_last_window", nlohmann::json(nullptr))},
            {"grains_passed_before_arrest", r["grains_passed_before_arrest"]},
            {"flux_share_with_field", r.value("flux_share_with_field", nlohmann::json(nullptr))},
            {"stops_flow", outcome.stops_flow},
            {"hold", r.value("hold", nlohmann::json(nullptr))},
            {"closed_flow_share", r.value("closed_flow_share", nlohmann::json(nullptr))},
            {"warnings", outcome.report.value("warnings", nlohmann::json::array())}};
}

// Above the lone-grain saturation field every grain is saturated as soon as the magnet is on: a
// stronger field then adds nothing to the magnetic forces, which a designer raising the field to
// make a valve jam should be told.
std::string saturated_field_warning(const JamScene& js) {
    if (!(js.peak_flux_density > js.lone_grain_saturation_flux_density)) return {};
    return "the field reaches " + format_number(js.peak_flux_density, 3) + " T at its strongest, above the " +
           format_number(js.lone_grain_saturation_flux_density, 3) +
           " T at which even a lone grain saturates (mu0 M_s / (3 beta), material/saturation_magnetisation): "
           "where it does, a stronger field adds nothing to the grains' moments or the magnetic forces";
}

std::string seed_summary(const nlohmann::json& record) {
    const nlohmann::json none(nullptr);
    auto word = [&](const char* key) {
        const nlohmann::json& w = record.value(key, none);
        return w.is_string() ? w.get<std::string>() : std::string();
    };
    std::string line = word("outcome");
    if (line.empty()) line = word("status");
    if (line.empty()) line = "?";
    const nlohmann::json& arrest = record.value("time_to_arrest_s", none);
    if (arrest.is_number()) {
        line += ", arrest at " + format_number(arrest.get<double>() * 1e3, 3) + " ms of field";
        const nlohmann::json& hold = record.value("hold", none);
        if (hold.is_object() && hold.value("gave_way_after_s", none).is_number())
            line +=
                ", gave way " + format_number(hold["gave_way_after_s"].get<double>() * 1e3, 3) + " ms into the hold";
        else if (hold.is_object() && hold.value("held", none) == true)
            line += ", held";
        return line;
    }
    const nlohmann::json& share = record.value("flux_share_last_window", none);
    if (share.is_number())
        line += ", grain flux at " + std::to_string(std::lround(100 * share.get<double>())) +
                " % of the no-field flux over the last window";
    return line;
}

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
    // The engine scene is generated: a packing it cannot make is the jam scene's volume fraction
    // (or size table), named as the user wrote it rather than by the generated scene's path.
    Scene scene = [&] {
        try {
            return build_scene(engine, build);
        } catch (const SceneError& e) {
            throw as_jam_key(e, js.protocol);
        }
    }();
    // The coupled flow replaces the engine scene's prescribed one before anything reads it.
    std::unique_ptr<CoupledFlow> coupled;
    if (js.flow.coupled) {
        coupled = make_coupled_flow(js, scene.system.physics.viscosity);
        scene.system.flow = coupled->field();
    }
    if (resuming) restore_state(options.resume_checkpoint, scene.system);
    try {
        choose_timestep(scene);
    } catch (const SceneError& e) {
        throw as_jam_key(e, js.protocol);
    }
    if (resuming) restore_state(options.resume_checkpoint, scene.system);  // the list and step from the checkpoint win
    System& s = scene.system;
    const JamProtocol& p = js.protocol;
    check_observation_interval(p, s.dt);
    for (const std::string& w : {short_jet_warning(js), saturated_field_warning(js)})
        if (options.progress && !w.empty()) std::cerr << "[jam] warning: " << w << "\n";
    if (options.progress) std::cerr << "[jam] " << s.particles.size() << " grains, time step " << s.dt * 1e9 << " ns\n";

    // The magnet is switched on after the no-field flow and off when the flow has arrested.
    auto field = std::make_shared<SwitchedField>(s.magnetic.field, p.flow_time);
    s.magnetic.field = field;

    JamProtocolState st;
    RunOptions run;
    run.mode = "jam";
    run.progress = options.progress;
    run.observe_every = p.observe_every;
    const Wall* valve_wall = nullptr;
    for (const auto& w : s.walls)
        if (w.kind == Wall::Kind::passage || w.kind == Wall::Kind::slot_passage) valve_wall = &w;
    // The carrier flow's resistance cells (lib/jam/axial_resistance.hpp): with the pressure
    // option they set the flow; with the prescribed flow they only measure what it would push
    // an arrested bed with. (A slot's flow has no cells: null valve_flow.)
    auto valve_flow = std::dynamic_pointer_cast<ValveFlow>(s.flow);
    const AxialResistance resistance(js.valve, js.slab_half_thickness, -js.valve.upstream_length,
                                     js.valve.downstream_length, js.flow.cell_length, js.feed_fraction,
                                     js.flow.supply_pressure);
    // A finite batch's outlet (model/supply "batch"); none for the periodic feed.
    std::optional<BatchOutlet> outlet;
    if (js.batch_supply) outlet.emplace(s, js.valve.downstream_length, js.valve.throat_end_z(), js.largest_diameter);
    double next_report = 0.2e-3;  // the first line once a full 0.1 ms window of flux exists
    auto observer = [&](const System& sys, std::size_t stage, long) {
        st.flux.observe(sys);
        // Counted first, then taken out: the outlet is past the throat, so no crossing is lost.
        // (`s` is `sys`, writable: the runner calls the observer between steps.)
        if (outlet) {
            st.drained += static_cast<long>(outlet->drain(s, st.flux));
            st.upstream_now = 0;
            for (const Vec3& x : sys.particles.position) st.upstream_now += x.z < 0;
            if (st.upstream_at_start < 0) st.upstream_at_start = st.upstream_now;
        }
        // From the arrest on the supply rises to the hold pressure (protocol/hold_pressure and its
        // ramp; the same pressure by default). Closed first the supply is cut while the grains are
        // magnetised: the fluid is at rest.
        const double supply = jam_phase(p, stage) == JamPhase::magnetise ? 0.0
                              : st.jammed
                                  ? p.supply_after_arrest(sys.time - arrest_called_at(st, p), js.flow.supply_pressure)
                                  : js.flow.supply_pressure;
        if (coupled)
            st.flow_state = coupled->update(sys, supply);
        else if (valve_flow)
            st.flow_state = resistance.update(sys, *valve_flow, js.flow.pressure_driven, supply);
        else
            return;
        if (js.flow.pressure_driven)
            st.flow_history.push_back(
                {sys.time, st.flow_state.scale, st.flow_state.stretch_pressure, st.flow_state.max_fraction});
        // A line per 0.1 ms of simulated time: what a user watches for is the flux.
        if (options.progress && sys.time >= next_report) {
            next_report = sys.time + 0.1e-3;
            const double rate = st.flux.rate(0.1e-3);
            std::cerr << "[jam] t = " << sys.time * 1e3 << " ms: grain flux " << rate << " /s";
            if (st.base_rate > 0)
                std::cerr << " (" << std::lround(100 * rate / st.base_rate) << " % of the no-field flux)";
            if (js.flow.pressure_driven)
                std::cerr << ", flow scale " << st.flow_state.scale << ", densest cell " << st.flow_state.max_fraction;
            std::cerr << "\n";
        }
    };
    run.stage_finished = [&](const System& sys, std::size_t stage) {
        return protocol_stage_finished(st, js, *field, sys, jam_phase(p, stage), options.progress);
    };
    std::string picture_error;
    auto look_at_clusters = [&](const System& sys) {
        const ContactClusters clusters = contact_clusters(sys);
        ClusterView v;
        v.valid = true;
        v.largest = clusters.size.empty() ? 0 : static_cast<long>(clusters.size[0]);
        v.count = static_cast<long>(clusters.size.size());
        v.spans = valve_wall ? cluster_spans_throat(sys, clusters, js.valve, *valve_wall) : false;
        // A picture that cannot be written costs a warning, never the run.
        if (!options.picture_path.empty() && sys.particles.size() > 0) try {
                write_throat_picture(options.picture_path, sys, clusters, js.valve);
            } catch (const std::exception& e) {
                picture_error = e.what();
            }
        return v;
    };
    // ---- Snapshots and checkpoint/resume (kept apart from the flow controller above) ----
    JamSnapshots snapshots;
    if (!options.snapshot_directory.empty())
        snapshots = JamSnapshots(options.snapshot_directory, options.snapshot_every, seed);
    // Everything the protocol carries from one observation to the next that the engine's
    // checkpoint does not: restored below, it makes the resumed run take the same decisions.
    // The protocol's state plus what lives in the field, the flow and the snapshot writer.
    auto protocol_state = [&] {
        const double off = field->switch_off_time();
        nlohmann::json state = st.save();
        state["seed"] = seed;
        state["field_off_s"] = std::isfinite(off) ? nlohmann::json(off) : nlohmann::json(nullptr);
        state["drag_factors"] = valve_flow ? valve_flow->drag_factors() : std::vector<double>{};
        if (coupled)
            state["coupled_flow"] = {{"axial_speed", coupled->field()->axial_speed()},
                                     {"drag_factors", coupled->field()->drag_factors()}};
        state["snapshots"] = snapshots.save();
        return state;
    };
    ProtocolPosition start;
    if (resuming) {
        const nlohmann::json& saved = checkpoint.state;
        st.restore(saved);
        if (!saved.at("field_off_s").is_null()) field->switch_off_at(saved["field_off_s"].get<double>());
        if (valve_flow) {
            // The cells' factors and scale as the last observation left them: the steps up to the
            // next observation use them.
            valve_flow->set_scale(st.flow_state.scale);
            const auto factors = saved.at("drag_factors").get<std::vector<double>>();
            if (!factors.empty()) resistance.apply(*valve_flow, factors);
        }
        if (coupled) {
            const nlohmann::json& cf = saved.at("coupled_flow");
            coupled->field()->set_field(cf.at("axial_speed").get<std::vector<double>>(),
                                        cf.at("drag_factors").get<std::vector<double>>());
        }
        snapshots.restore(saved.at("snapshots"));
        start = checkpoint.header.position;
        run.resumed_stage_log = checkpoint.stage_log;
    }
    run.checkpoint_state = [&] {
        return nlohmann::json{{"protocol", protocol_state()}, {"campaign", options.campaign}};
    };
    auto observe_all = [&](const System& sys, std::size_t stage, long step) {
        observer(sys, stage, step);
        snapshots.observe(sys);
    };
    // The arch is looked at when the flow arrests (after the release it has let go): the
    // clusters, whether the largest spans the throat, and the picture are taken then.
    auto protocol_finished = run.stage_finished;
    run.stage_finished = [&](const System& sys, std::size_t stage) {
        const bool was_jammed = st.jammed;
        const bool done = protocol_finished(sys, stage);
        if (st.jammed && !was_jammed) {
            snapshots.write_tagged(sys, "arrest");
            st.arrest_view = look_at_clusters(sys);
        }
        return done;
    };
    const RunOutcome outcome = run_protocol(scene, run, start, observe_all);
    if (outcome.exit_status == 0) snapshots.write_tagged(s, "end");

    const bool incomplete = outcome.exit_status != 0;
    JamOutcome out;
    out.report = outcome.report;
    out.exit_status = outcome.exit_status;
    out.jammed = st.jammed;
    out.time_to_arrest = st.arrest_time;
    // Clusters at the arrest if there was one, otherwise as the run ended (the picture too).
    const ClusterView view = st.arrest_view.valid ? st.arrest_view : look_at_clusters(s);
    const bool blew_up = out.report.value("status", "") == "failed";  // the runner's BlowUp (exit status 3)
    write_jam_results(out.report, st, view, js, coupled ? coupled->cells() : resistance.cells(), valve_flow.get(),
                      incomplete, blew_up);
    out.stops_flow = out.report["results"]["stops_flow"].get<bool>();
    if (coupled) write_coupled_slices(out.report["results"], *coupled);
    if (outlet) write_batch_results(out.report, st, *outlet, s.particles.size());
    if (snapshots.enabled()) out.report["outputs"]["snapshots"] = snapshots.written();
    if (!picture_error.empty())
        out.report["warnings"].push_back("the throat picture was not written: " + picture_error);
    else if (!options.picture_path.empty() && s.particles.size() > 0)
        out.report["outputs"]["throat_picture"] = options.picture_path;
    return out;
}

}  // namespace mrjam
