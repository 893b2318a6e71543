#include "jam/steady_flow.hpp"

#include <algorithm>
#include <cmath>

namespace mrjam {

SteadyFlowVerdict steady_flow(const ThroatFlux& flux, const std::vector<FlowSample>& flow_history, double field_on,
                              const SteadyFlowCriterion& criterion) {
    SteadyFlowVerdict v;
    const double w = criterion.window;
    const auto& h = flux.history();
    if (!(w > 0) || h.empty()) return v;
    const double t = h.back().first;
    if (t - field_on < 2 * w) return v;
    v.previous_rate = flux.rate_between(t - 2 * w, t - w);
    v.last_rate = flux.rate_between(t - w, t);
    // A flux at or below zero is not a flow to call steady (an arrest, or grains backing up).
    if (!(v.previous_rate > 0 && v.last_rate > 0)) return v;
    const double tol = criterion.tolerance;
    if (std::abs(v.last_rate - v.previous_rate) > tol * std::max(v.previous_rate, v.last_rate)) return v;
    if (!flow_history.empty()) {
        // The flow scale a window ago (the first sample at or after t - w) against now.
        const auto then = std::lower_bound(flow_history.begin(), flow_history.end(), t - w,
                                           [](const FlowSample& s, double time) { return s.time < time; });
        if (then == flow_history.end()) return v;
        const double s_then = then->scale, s_now = flow_history.back().scale;
        if (std::abs(s_now - s_then) > tol * std::max(s_then, s_now)) return v;
    }
    v.steady = true;
    return v;
}

}  // namespace mrjam
