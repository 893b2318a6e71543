#pragma once
// LAMMPS / LIGGGHTS data file for atom_style granular (LIGGGHTS) or sphere (LAMMPS), so a peer
// code can start from exactly the state mrjam holds.
//
// Layout (read_data):
//   header: N atoms, T atom types (T = density_per_material.size()), box bounds from domain
//   Atoms:      atom-ID atom-type diameter density x y z
//   Velocities: atom-ID vx vy vz wx wy wz
// with atom-ID = mrjam id + 1 (LAMMPS ids start at 1 and must fit a 32-bit int) and
// atom-type = material + 1; density = density_per_material[material]. Numbers use the shortest
// decimal form that parses back to the identical double. The data file carries no periodicity:
// the reading input script must set `boundary` to match domain.periodic before read_data.
#include <string>
#include <vector>

#include "core/domain.hpp"
#include "particles.hpp"

namespace mrjam {

// Throws std::invalid_argument if a particle's material has no density, a density is not
// positive, or an id does not fit a LAMMPS atom id; std::runtime_error naming the path if the
// file cannot be opened or written.
void write_lammps_data(const std::string& path, const Particles& particles, const Domain& domain,
                       const std::vector<double>& density_per_material);

}  // namespace mrjam
