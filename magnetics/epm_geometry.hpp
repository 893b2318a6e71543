#pragma once
// The EPM valve as gmsh solids (3D) or as its x-y cross-section through the throat (2D), each
// piece tagged with its region, and the mesh grading that resolves the fluid.
#include <vector>

#include "magnetics/epm_model.hpp"
#include "magnetics/gmsh_assembly.hpp"

namespace mrjam::magnetics {

// Physical group numbers shared by the mesh and the GetDP problem.
namespace region {
inline constexpr int alnico = 1;
inline constexpr int ndfeb = 2;
inline constexpr int iron = 3;           // end caps / brackets and inserts
inline constexpr int fluid_active = 4;   // MR fluid between the brackets (|z| <= bracket width / 2)
inline constexpr int fluid_passive = 5;  // MR fluid up- and downstream of the brackets
inline constexpr int inactive_air = 6;   // air between the brackets, from the magnets to the tube axis plane
inline constexpr int air = 7;            // everything else (valve body plastic is non-magnetic: air)
inline constexpr int magnet_pair = 8;    // 2D only: the two magnets averaged over the bracket width
inline constexpr int valve_body = 9;     // the valve body's wall (plastic: non-magnetic)
inline constexpr int boundary = 10;      // the air box: phi = 0
}  // namespace region

// Element sizes (the standard tier's defaults; see tier_mesh in magnetics_scene.hpp).
struct MeshSettings {
    double fluid_size = 0.2e-3;   // in and around the active fluid
    double device_size = 0.5e-3;  // magnets, brackets, the tube near them
    double far_size = 3e-3;       // at the air box
    double air_box = 30e-3;       // side of the cubic (square in 2D) air box, centred on the device
};

std::vector<RegionPieces> add_epm_pieces(const EpmModel& model, int dimension);
MeshRequest epm_mesh_request(const EpmModel& model, int dimension, const MeshSettings& mesh);

// Where the active fluid and the inactive air are, for documentation and the circuit model.
struct EpmLayout {
    Vec3 device_lo, device_hi;  // bounding box of magnets, brackets and the modelled tube
};
EpmLayout epm_layout(const EpmModel& model);

}  // namespace mrjam::magnetics
