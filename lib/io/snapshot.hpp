#pragma once
// Particle snapshots for visualisation and post-processing.
//
//   vtk_legacy   ".vtk"  legacy VTK 3.0, BINARY (big-endian, as the legacy format requires),
//                        POLYDATA with one vertex cell per particle.
//   vtk_xml      ".vtp"  VTK XML PolyData, little-endian binary arrays inline as base64 with
//                        UInt64 byte-count headers (as VTK's own writer lays them out).
//   lammps_dump  ".dump" LAMMPS text dump, readable by OVITO and LAMMPS read_dump.
//
// Both VTK formats carry the point arrays radius, id, material, velocity, angular_velocity,
// force and dipole_moment (all doubles except id: UInt64 and material: UInt16), radius and
// velocity being the active scalars and vectors, and the field data TIME (double) and CYCLE
// (the step, Int64). (The legacy file stores the arrays after radius and velocity as a point
// FIELD, since legacy readers skip any SCALARS/VECTORS section after the first.)
// To draw spheres in ParaView apply Glyph with Glyph Type Sphere, Scale Array "radius",
// Scale Factor 2 and Glyph Mode "All Points" (the default sphere source has radius 0.5, so the
// factor 2 makes the glyph radius equal the particle radius).
//
// The dump's columns are
//   id type radius x y z vx vy vz omegax omegay omegaz fx fy fz mux muy muz
// followed by one column per extra integer array (below).
//
// A mode may add integer point arrays of its own (the jam predictor's contact-cluster id, so
// ParaView can colour grains by cluster): VTK legacy "int" field arrays, VTK XML Int32 arrays.
// with type = material + 1 (LAMMPS types start at 1). The dump carries the step, not the
// time. Numbers are written in the shortest form that reads back to the identical double.
#include <cstdint>
#include <string>
#include <vector>

#include "core/domain.hpp"
#include "particles.hpp"

namespace mrjam {

enum class SnapshotFormat { vtk_legacy, vtk_xml, lammps_dump };

// "vtk" -> vtk_legacy, "vtp" -> vtk_xml, "lammps" -> lammps_dump. Anything else throws
// std::invalid_argument whose message lists the valid names.
SnapshotFormat snapshot_format_from_name(const std::string& name);

// The file extension including the dot: ".vtk", ".vtp", ".dump".
std::string snapshot_extension(SnapshotFormat format);

// An extra per-particle integer array; `values` has one entry per particle.
struct IntPointArray {
    std::string name;  // no spaces (a legacy VTK array name is one token)
    std::vector<std::int32_t> values;
};

// Writes one snapshot of every particle to path (created or truncated). Throws
// std::runtime_error naming the path when the file cannot be opened or written, and
// std::invalid_argument when an extra array's length or name is wrong.
void write_snapshot(const std::string& path, SnapshotFormat format, const Particles& particles, const Domain& domain,
                    long step, double time, const std::vector<IntPointArray>& extra = {});

}  // namespace mrjam
