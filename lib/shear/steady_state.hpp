#pragma once
// Where a stress series becomes steady: the marginal standard error rule (MSER; White, "An
// effective truncation heuristic for bias reduction in simulation output", Simulation 69, 1997).
// The truncation d minimises the squared standard error of the mean of x[d..n), the sum of
// squared deviations over (n - d)^2: dropping a transient lowers the spread faster than it
// shortens the series, dropping steady samples does not. Searched over the first half only: near
// the end a few samples have a small spread by chance.
#include <cstddef>
#include <string>
#include <vector>

#include "shear/block_average.hpp"

namespace mrjam {

// The first sample of the steady part (0 for a series steady from its start, or one too short to judge).
std::size_t mser_truncation(const std::vector<double>& x);

// A trend left in the averaged window: the least-squares line through its block means (blocks
// longer than the correlation time are nearly independent, so the line's residuals give its
// error). `change` is the line's rise over the window's length, `error` its standard error;
// `significant` when |change| exceeds the two-sided 95 % Student-t bound (blocks - 2 degrees of
// freedom). Fewer than 3 blocks cannot be judged: no change, not significant. MSER misses a
// series that still rises steadily through its whole length, since it only searches the first
// half; the line does not.
struct Drift {
    double change = 0.0;
    double error = 0.0;
    bool significant = false;
};
Drift window_drift(const std::vector<double>& block_means);

// One rate's settling against its averaged window: the strain into the rate at which its stress
// series settles (MSER), whether that lies before the window's first sample, and the window's drift.
// `drifting` asks for a drift both significant and material: more than a tenth of the window's mean
// stress, which moves the mean by more than 5 %, near the seed-to-seed scatter (7-11 %) that the
// quoted errors are held to. A window shorter than the stress's correlation strain makes its block
// means correlated and the t test too eager; the materiality keeps its small swings unflagged.
struct Settling {
    double strain = 0.0;
    bool before_window = true;
    Drift drift;
    bool drifting = false;
    bool steady() const { return before_window && !drifting; }
};
inline constexpr double kMaterialDrift = 0.1;  // of the window's mean stress
// `window` is the block average of the series' last samples, the rate's averaged window.
Settling settling_of(const std::vector<double>& series, double rate_strain, const BlockAverage& window);

// What to change when a rate is not steady in its window; `key` is the ladder key that sets the
// rate's length (ladder_length_key, shear/shear_spec.hpp). Settling inside the window: the window is the last
// `window_fraction` of the rate's strain, so the strain that leaves the transient out is the settling strain over (1 -
// window_fraction), and a window of the whole rate cannot leave it out at any strain. Still drifting: no strain can be
// read off, only that the rate's `rate_strain` was not enough.
std::string unsettled_advice(const std::string& key, const Settling& settling, double rate_strain,
                             double window_fraction);

}  // namespace mrjam
