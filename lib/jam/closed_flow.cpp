#include "jam/closed_flow.hpp"

#include <cmath>

namespace mrjam {

double mean_flow_scale(const std::vector<FlowSample>& history, double t0, double t1) {
    double sum = 0;
    long n = 0;
    for (const auto& s : history)
        if (s.time >= t0 && s.time <= t1) {
            sum += s.scale;
            ++n;
        }
    return n > 0 ? sum / n : std::nan("");
}

double closed_flow_share(const std::vector<FlowSample>& history, double flow_time, double window_start, double window) {
    const double open = mean_flow_scale(history, 0.5 * flow_time, flow_time);
    const double closed = mean_flow_scale(history, window_start, window_start + window);
    return closed / open;  // NaN propagates from either mean
}

}  // namespace mrjam
