#pragma once
// The instant tier: a magnetic circuit (reluctance network) estimate of the EPM valve's field,
// no mesh and no solver. The two magnets are Norton sources (flux B_r A through their own
// permeance mu0 mu_rec A / L) between two ideal iron nodes, the brackets; the load is the set
// of parallel flux tubes between the brackets:
//   - straight tubes across the gap under the brackets, through air, valve body and fluid in
//     series (a strip of width dx and depth dz has permeance mu0 dx dz / (g - c (1 - 1/mu_f)),
//     with c the fluid chord; iron inserts remove the air part; a cutout lengthens the path),
//   - fringing tubes beyond the tips along quarter circles (path g + pi d at distance d),
//   - Roters' fringing permeances along the brackets' open sides and behind the magnets.
// It gives the magnetic potential between the brackets, hence |B| along every tube. It has
// no leakage through the OFF state and no field gradient; its error against the 3D model is
// published in docs/magnetics.md.
#include "magnetics/epm_field.hpp"

namespace mrjam::magnetics {

EpmField circuit_field(const EpmModel& model);

}  // namespace mrjam::magnetics
