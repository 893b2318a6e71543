#include "jam/throat_flux.hpp"

#include <algorithm>
#include <cmath>

#include "grain_removal.hpp"

namespace mrjam {

void ThroatFlux::observe(const System& s) {
    const auto& x = s.particles.position;
    const double half_period = 0.5 * (s.domain.hi.z - s.domain.lo.z);
    if (previous_z_.size() != x.size()) {
        previous_z_.resize(x.size());
        for (std::size_t i = 0; i < x.size(); ++i) previous_z_[i] = x[i].z;
        history_.push_back({s.time, passed_});
        return;
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double before = previous_z_[i], now = x[i].z;
        if (std::abs(now - before) < half_period) {
            if (before < plane_ && now >= plane_)
                ++passed_;
            else if (before >= plane_ && now < plane_)
                --passed_;
        }
        previous_z_[i] = now;
    }
    history_.push_back({s.time, passed_});
}

void ThroatFlux::remove_grains(const std::vector<std::int64_t>& new_index, std::size_t kept) {
    compact_by_index(previous_z_, new_index, kept);
}

double ThroatFlux::passed_at(double t) const {
    auto it =
        std::lower_bound(history_.begin(), history_.end(), t, [](const auto& h, double v) { return h.first < v; });
    return static_cast<double>(it == history_.end() ? history_.back().second : it->second);
}

double ThroatFlux::rate_between(double t0, double t1) const {
    if (history_.size() < 2 || !(t1 > t0)) return 0.0;
    return (passed_at(t1) - passed_at(t0)) / (t1 - t0);
}

double ThroatFlux::first_time_above(double t0, double t1, double window, double limit) const {
    if (history_.empty()) return std::nan("");
    for (const auto& [t, passed] : history_) {
        if (t <= t0) continue;
        if (t > t1) break;
        if (passed - passed_at(std::max(t0, t - window)) > limit * window) return t;
    }
    return std::nan("");
}

std::vector<std::pair<double, double>> ThroatFlux::window_shares(double t0, double t1, double window,
                                                                 double base) const {
    std::vector<std::pair<double, double>> shares;
    if (!(base > 0) || !(window > 0)) return shares;
    // Whole windows only, with a margin for the rounding of t0 + k window.
    const long n = static_cast<long>(std::floor((t1 - t0) / window * (1 + 1e-12)));
    for (long k = 0; k < n; ++k) {
        const double a = t0 + k * window, b = a + window;
        shares.push_back({b, rate_between(a, b) / base});
    }
    return shares;
}

double ThroatFlux::rate(double window) const {
    if (history_.size() < 2) return 0.0;
    const double t1 = history_.back().first;
    if (t1 - history_.front().first < window) return 0.0;
    return rate_between(t1 - window, t1);
}

nlohmann::json ThroatFlux::save() const {
    return {{"plane", plane_}, {"previous_z", previous_z_}, {"passed", passed_}, {"history", history_}};
}

void ThroatFlux::restore(const nlohmann::json& state) {
    plane_ = state.at("plane").get<double>();
    previous_z_ = state.at("previous_z").get<std::vector<double>>();
    passed_ = state.at("passed").get<long>();
    history_ = state.at("history").get<std::vector<std::pair<double, long>>>();
}

}  // namespace mrjam
