#include "shear/steady_state.hpp"

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

}  // namespace mrjam
