#pragma once
// The stable time step. Three clocks limit an explicit soft-sphere step:
//  - the Rayleigh time of the smallest grain, pi R sqrt(rho/G) / (0.1631 nu + 0.8766), the period
//    of surface waves that carry contact forces;
//  - the Hertz contact duration of the smallest pair at the characteristic impact speed
//    (Johnson eq. 11.24), which a step must resolve;
//  - the Stokes relaxation time m / (6 pi mu R) of the smallest grain: explicit drag is unstable
//    above twice it and inaccurate well before.
// The critical time is the smallest of them. The automatic step is `safety` times it (0.1 by
// default, the source's "below 10% of the Hertz time"); a requested step above 0.2 of it is refused.
#include <string>

#include "system.hpp"

namespace mrjam {

struct TimestepLimits {
    double rayleigh = 0;
    double hertz = 0;
    double drag = 0;          // infinity without drag: the smaller of the two below
    double stokes = 0;        // the smallest grain's m / (6 pi mu R), infinity without a fluid
    double pair_damping = 0;  // m* / c of two smallest grains, infinity without pair damping
    double gravity = 0;       // a tenth of a grazing orbit's period about the densest grain (self-gravity)
    double critical = 0;      // the smallest
    std::string limiting;     // which of them
    double stable_limit = 0;  // largest step accepted: max_fraction * critical
};

inline constexpr double kMaxStepFraction = 0.2;

// More steps than any run could take: a duration, strain or unit gone wrong, or a step some
// damping has shrunk. Refused where a mode turns its times into steps (a count past a long's
// range would also wrap round to a one-step run).
inline constexpr double kMostSteps = 1e15;

TimestepLimits timestep_limits(const System& system, double characteristic_speed);

// The scene's warning when the drag sets a step more than 10 times shorter than the contacts
// need (a viscous carrier, or fine grains); empty otherwise.
std::string drag_limited_step_warning(const TimestepLimits& limits);

}  // namespace mrjam
