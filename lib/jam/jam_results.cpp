#include "jam/jam_results.hpp"

#include <cmath>

#include "core/format.hpp"
#include "jam/closed_flow.hpp"
#include "jam/jam_protocol_steps.hpp"
#include "jam/jam_run.hpp"

namespace mrjam {

namespace {

// A figure that may not exist (NaN: no samples to form it) as a number or null.
nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace

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
            // Below 1 the closed period was fast-forwarded: duration_s / share is its overdamped length.
            {"viscosity_share", p.magnetise_viscosity_share},
            {"last_window_change", last_change},
            {"history", {{"columns", {"time_s", "mean_coordination", "magnetic_energy_J"}}, {"rows", rows}}}};
}

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

nlohmann::json jam_seed_record(const JamOutcome& outcome, long long seed) {
    const nlohmann::json& r = outcome.report.at("results");
    return {{"seed", seed},
            {"status", outcome.report["status"]},
            {"outcome", r["outcome"]},
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

}  // namespace mrjam
