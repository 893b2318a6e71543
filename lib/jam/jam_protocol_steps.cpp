#include "jam/jam_protocol_steps.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include "core/format.hpp"
#include "jam/jam_engine_scene.hpp"
#include "jam/steady_flow.hpp"
#include "observers.hpp"

namespace mrjam {

namespace {

// Relative change from a to b; 0 when both are 0 (no contacts, or no field, stays settled).
double relative_change(double a, double b) {
    const double scale = std::max(std::abs(a), std::abs(b));
    return scale > 0 ? std::abs(b - a) / scale : 0.0;
}

}  // namespace

double arrest_called_at(const JamProtocolState& st, const JamProtocol& p) { return st.release_start - p.hold_time; }

JamPhase jam_phase(const JamProtocol& p, std::size_t stage) {
    if (stage == 0) return JamPhase::reference;
    if (p.order == JamOrder::closed_first)
        return stage == 1 ? JamPhase::magnetise : stage == 2 ? JamPhase::judged : JamPhase::release;
    return stage == 1 ? JamPhase::judged : JamPhase::release;
}

double carrier_viscosity_share(const JamProtocol& p, std::size_t stage) {
    return jam_phase(p, stage) == JamPhase::magnetise ? p.magnetise_viscosity_share : 1.0;
}

std::optional<std::pair<double, double>> last_settle_change(const JamProtocolState& st) {
    const std::size_t n = st.settle_history.size();
    if (n < 2) return std::nullopt;
    const SettleSample &a = st.settle_history[n - 2], &b = st.settle_history[n - 1];
    return std::pair{relative_change(a.coordination, b.coordination),
                     relative_change(a.magnetic_energy, b.magnetic_energy)};
}

bool magnetised_structure_settled(JamProtocolState& st, const System& sys, const JamProtocol& p) {
    if (!st.settle_history.empty() && sys.time < st.settle_history.back().time + p.settle_window) return false;
    st.settle_history.push_back({sys.time, mean_coordination(sys), induced_magnetic_energy(sys)});
    if (st.settle_history.size() < 3) return false;
    const auto change = last_settle_change(st);
    return change->first < p.settle_tolerance && change->second < p.settle_tolerance;
}

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

std::string sparse_window_warning(double base_rate, const JamProtocol& p) {
    const double per_window = base_rate * p.arrest_window;
    if (!(base_rate > 0) || per_window >= kFewestGrainsPerWindow) return {};
    return "the no-field flux passes only " + format_number(per_window) +
           " grains per protocol/arrest_window, so an arrest can be counting noise: lengthen the window to at least " +
           format_number(kFewestGrainsPerWindow / base_rate * 1e3) + " ms";
}

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

}  // namespace mrjam
