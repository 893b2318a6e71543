#include "shear/steady_state.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

namespace mrjam {

std::size_t mser_truncation(const std::vector<double>& x) {
    const std::size_t n = x.size();
    if (n < 4) return 0;
    // Suffix sums give each candidate's mean and spread in one pass from the end.
    std::vector<double> sum(n + 1, 0.0), sum_sq(n + 1, 0.0);
    for (std::size_t i = n; i-- > 0;) {
        sum[i] = sum[i + 1] + x[i];
        sum_sq[i] = sum_sq[i + 1] + x[i] * x[i];
    }
    std::size_t best = 0;
    double best_score = std::numeric_limits<double>::infinity();
    for (std::size_t d = 0; d <= n / 2; ++d) {
        const double m = static_cast<double>(n - d);
        const double spread = sum_sq[d] - sum[d] * sum[d] / m;  // sum of squared deviations
        const double score = spread / (m * m);
        if (score < best_score) {
            best_score = score;
            best = d;
        }
    }
    return best;
}

Settling settling_of(const std::vector<double>& series, double rate_strain, std::size_t window_samples) {
    const std::size_t n = series.size();
    if (n == 0) return {};
    const std::size_t settled = mser_truncation(series);
    return {rate_strain * static_cast<double>(settled) / static_cast<double>(n),
            settled + std::min(window_samples, n) <= n};
}

std::string unsettled_advice(std::size_t rate_index, bool by_steps, double settle_strain, double window_fraction) {
    if (window_fraction >= 1) return "set /measure/window below 1 so the transient is left out";
    const char* key = rate_index == 0 ? (by_steps ? "/ladder/steps_first" : "/ladder/strain_first")
                                      : (by_steps ? "/ladder/steps_per_rate" : "/ladder/strain_per_rate");
    char text[160];
    std::snprintf(text, sizeof text, "raise %s to give at least %.3g strain", key,
                  settle_strain / (1 - window_fraction));
    return text;
}

}  // namespace mrjam
