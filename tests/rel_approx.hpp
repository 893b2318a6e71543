#pragma once
#include <doctest/doctest.h>

namespace mrjam_test {

// A relative comparison. doctest's Approx adds its `scale` (1 by default) to the magnitudes it
// compares, so for SI-small values (a flow rate of 1e-6 m^3/s, a force of 1e-4 N) its epsilon
// acts as an absolute tolerance and almost anything passes. rel(x) compares relative to |x|
// (the default epsilon is ~1.2e-5); a comparison with zero needs an explicit .scale(S), S the
// size of the quantity being compared.
inline doctest::Approx rel(double x) { return doctest::Approx(x).scale(0.0); }

}  // namespace mrjam_test
