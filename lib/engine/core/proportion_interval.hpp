#pragma once
// How sure a jam probability from a few seeds is: the Wilson score interval of a binomial
// proportion (Wilson 1927). It stays inside [0, 1] and is not empty at 0 or n successes, where
// the normal ("Wald") interval collapses to a point: 3 jams in 3 seeds says the probability is
// at least 0.44 at 95 %, not that it is 1.
//
// The bounds are the two p with (k/n - p)^2 = z^2 p (1 - p) / n.
#include <cmath>

namespace mrjam {

struct ProportionInterval {
    double low = 0, high = 1;
};

// The standard normal quantile of a two-sided 95 % interval.
inline constexpr double kZ95 = 1.959963984540054;

// n = 0 says nothing: [0, 1].
inline ProportionInterval wilson_interval(int successes, int trials, double z = kZ95) {
    if (trials <= 0) return {};
    const double n = trials, p = static_cast<double>(successes) / n, z2 = z * z;
    const double scale = 1.0 / (1.0 + z2 / n);
    const double centre = (p + z2 / (2 * n)) * scale;
    const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n)) * scale;
    // At k = 0 or n one bound is exactly 0 or 1; the formula gets there only to round-off.
    return {successes <= 0 ? 0.0 : centre - half, successes >= trials ? 1.0 : centre + half};
}

}  // namespace mrjam
