#pragma once
#include "system.hpp"

namespace mrjam {

// Zeroes and accumulates forces and torques on every grain from the physics terms the system
// has switched on; fills contact statistics, raft and wall forces. Deterministic for a given
// thread count: each thread accumulates into its own buffer and the buffers are summed in order.
void compute_forces(System& system);

// The same, adding to forces and torques the caller has already zeroed (the integrator clears
// them in its drift pass, saving a pass over the arrays).
void accumulate_forces(System& system);

// Elastic energy stored in the Hertz contacts, sum of 2/5 k_n d^2 (= 8/15 Y* sqrt(R*) d^5/2).
double contact_elastic_energy(const System& system);

}  // namespace mrjam
