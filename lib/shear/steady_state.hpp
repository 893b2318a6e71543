#pragma once
// Where a stress series becomes steady: the marginal standard error rule (MSER; White, "An
// effective truncation heuristic for bias reduction in simulation output", Simulation 69, 1997).
// The truncation d minimises the squared standard error of the mean of x[d..n), the sum of
// squared deviations over (n - d)^2: dropping a transient lowers the spread faster than it
// shortens the series, dropping steady samples does not. Searched over the first half only: near
// the end a few samples have a small spread by chance.
#include <cstddef>
#include <vector>

namespace mrjam {

// The first sample of the steady part (0 for a series steady from its start, or one too short to judge).
std::size_t mser_truncation(const std::vector<double>& x);

}  // namespace mrjam
