#include "shear/steady_state.hpp"

#include <algorithm>
#include <cmath>
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

namespace {

// Two-sided 95 % quantile of Student's t for `dof` degrees of freedom (tabulated to 10; 2.0
// beyond, between the table's 2.23 and the normal's 1.96).
double t_critical_95(std::size_t dof) {
    static const double table[] = {12.71, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228};
    return dof >= 1 && dof <= 10 ? table[dof - 1] : 2.0;
}

}  // namespace

Drift window_drift(const std::vector<double>& block_means) {
    const std::size_t b = block_means.size();
    if (b < 3) return {};
    const double n = static_cast<double>(b), x_mean = (n - 1) / 2;
    double y_mean = 0;
    for (double y : block_means) y_mean += y / n;
    double sxx = 0, sxy = 0;
    for (std::size_t k = 0; k < b; ++k) {
        sxx += (k - x_mean) * (k - x_mean);
        sxy += (k - x_mean) * (block_means[k] - y_mean);
    }
    const double slope = sxy / sxx;
    double ss_res = 0;
    for (std::size_t k = 0; k < b; ++k) {
        const double r = block_means[k] - y_mean - slope * (k - x_mean);
        ss_res += r * r;
    }
    const double slope_error = std::sqrt(ss_res / (n - 2) / sxx);
    Drift d{slope * n, slope_error * n, false};
    d.significant = std::abs(slope) > t_critical_95(b - 2) * slope_error;
    return d;
}

Settling settling_of(const std::vector<double>& series, double rate_strain, const BlockAverage& window) {
    const std::size_t n = series.size();
    if (n == 0) return {};
    const std::size_t settled = mser_truncation(series);
    Settling s;
    s.strain = rate_strain * static_cast<double>(settled) / static_cast<double>(n);
    s.before_window = settled + std::min(window.samples, n) <= n;
    s.drift = window_drift(window.means);
    s.drifting = s.drift.significant && std::abs(s.drift.change) > kMaterialDrift * std::abs(window.mean);
    return s;
}

std::string unsettled_advice(const std::string& key, const Settling& settling, double rate_strain,
                             double window_fraction) {
    char text[200];
    if (settling.drifting)
        std::snprintf(text, sizeof text, "raise %s beyond %.3g strain, until the window's stress stops drifting",
                      key.c_str(), rate_strain);
    else if (window_fraction >= 1)
        return "set /measure/window below 1 so the transient is left out";
    else
        std::snprintf(text, sizeof text, "raise %s to give at least %.3g strain", key.c_str(),
                      settling.strain / (1 - window_fraction));
    return text;
}

}  // namespace mrjam
