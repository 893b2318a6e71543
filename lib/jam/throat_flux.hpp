#pragma once
// Grain flux through the throat: net crossings of the plane z = plane in +z (the flow
// direction), counted from the grains' axial positions at successive observations. In a domain
// periodic along z a wrap is not a crossing (a displacement of half the period or more).
#include <cstdint>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "system.hpp"

namespace mrjam {

class ThroatFlux {
public:
    explicit ThroatFlux(double plane = 0.0) : plane_(plane) {}
    void observe(const System& s);
    long passed() const { return passed_; }
    // (time, net grains passed so far) at every observation.
    const std::vector<std::pair<double, long>>& history() const { return history_; }
    // Grains per second over the last `window` seconds of history (0 if shorter).
    double rate(double window) const;
    // Grains per second between two times (linear in the recorded history).
    double rate_between(double t0, double t1) const;
    // The first observation t in (t0, t1] at which the grains passed over the `window` before it,
    // counted from t0 on, exceed `limit` grains/s times the window: when an arrest called at t0
    // gave way. Counting from t0 keeps the grains of the arrest's own window out. NaN if none.
    double first_time_above(double t0, double t1, double window, double limit) const;
    // The flux over consecutive whole windows from t0, the last ending at or before t1, as a share
    // of `base` grains/s: (window end, share) pairs. Empty when base is not positive.
    std::vector<std::pair<double, double>> window_shares(double t0, double t1, double window, double base) const;

    // Follows a removal of grains (lib/engine/grain_removal.hpp's surviving index), so the next
    // observation compares each remaining grain with its own previous position.
    void remove_grains(const std::vector<std::int64_t>& new_index, std::size_t kept);

    // The whole counting state (previous positions, net count, history) for a checkpoint; JSON
    // numbers round-trip doubles exactly, so a resumed run counts as the uninterrupted one.
    nlohmann::json save() const;
    void restore(const nlohmann::json& state);

private:
    // The net count at the first observation at or after t (the last one past the history's end).
    double passed_at(double t) const;

    double plane_;
    std::vector<double> previous_z_;
    long passed_ = 0;
    std::vector<std::pair<double, long>> history_;
};

}  // namespace mrjam
