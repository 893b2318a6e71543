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

namespace mrjam {

// The first sample of the steady part (0 for a series steady from its start, or one too short to judge).
std::size_t mser_truncation(const std::vector<double>& x);

// One rate's settling against its averaged window: the strain into the rate at which its stress
// series settles (MSER), and whether that lies before the window's first sample.
struct Settling {
    double strain = 0.0;
    bool before_window = true;
};
Settling settling_of(const std::vector<double>& series, double rate_strain, std::size_t window_samples);

// What to change when a rate settles inside its window (rate_index 0 is the first, longer rate).
// The window is the last `window_fraction` of the rate's strain, so the strain that leaves the
// transient out is the settling strain over (1 - window_fraction); a window of the whole rate
// cannot leave it out at any strain.
std::string unsettled_advice(std::size_t rate_index, bool by_steps, double settle_strain, double window_fraction);

}  // namespace mrjam
