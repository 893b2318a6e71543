#pragma once
// Velocity Verlet with rotation (spheres: the angular velocity is integrated directly).
#include <stdexcept>
#include <string>

#include "system.hpp"

namespace mrjam {

// A run that went unstable: names the grain, the step and the likely cause.
class BlowUp : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Builds the neighbour list and the first forces; call once before stepping.
void prepare(System& system);

// One step: half kick, drift, (re)neighbour, forces, half kick. Throws BlowUp on NaN, on an
// overlap above system.max_overlap_fraction of the smaller radius, or on a grain that left the
// box through a side with no periodic boundary.
void advance(System& system);

// `count` steps in a row, identical bit for bit to calling advance() `count` times but faster:
// the second half kick of each step shares its pass over the grains with the first half kick of
// the next.
void advance_steps(System& system, long count);

}  // namespace mrjam
