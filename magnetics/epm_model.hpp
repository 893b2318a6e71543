#pragma once
// The electropermanent magnet (EPM) valve as a parametric model: two magnets side by side
// between two soft-iron end caps whose brackets reach across a valve tube.
//
// Frame (shared with geometry/valve.hpp): the tube axis is z and the throat centre is the origin;
// the magnets sit at negative x, their 3.2 mm magnetisation axis along y, so the field crosses
// the tube along y, transverse to the flow. The alnico magnet is at z > 0, the NdFeB at z < 0.
// Every dimension is a named parameter; docs/magnetics.md gives the default of each and why.
#include <string>
#include <vector>

#include "geometry/valve.hpp"

namespace mrjam::magnetics {

enum class BracketVariant { unguided, rectangular, curved, unchamfered, insert };
std::string variant_name(BracketVariant);
std::vector<std::string> variant_names();
BracketVariant variant_from_name(const std::string&);  // throws std::invalid_argument

struct MagnetMaterial {
    double remanence = 1.35;            // T, magnitude of B_r
    double recoil_permeability = 1.05;  // relative
};

struct MagnetParameters {
    double width = 1.6e-3;             // along x (away from the tube)
    double depth = 1.6e-3;             // along z (flow direction); the two magnets sit side by side in z
    double length = 3.2e-3;            // along y, the magnetisation axis
    double spacing = 0.4e-3;           // z gap between the two magnets (room for the alnico's coil)
    MagnetMaterial ndfeb{1.35, 1.05};  // N42, remanence as in the source's FEM
    // The source's FEM fixed both remanences at 1.35 T and treated the alnico like the NdFeB;
    // real alnico 5 recoils with mu ~ 3.5 about its working point (its effect: docs/magnetics.md).
    MagnetMaterial alnico{1.35, 1.05};
    double alnico_polarity = 1.0;  // +1 ON (parallel), -1 OFF (antiparallel)
};

struct BracketParameters {
    BracketVariant variant = BracketVariant::rectangular;
    double thickness = 1.4e-3;       // along y: 3.2 mm magnets + 2 x 1.4 mm caps = the EPM's 6 mm
    double width = 4.0e-3;           // along z: the EPM's 4 mm
    double tube_clearance = 0.2e-3;  // x gap between the magnets' front face and the tube wall (coil room)
    double tip_reach = 0.0;          // tip x position measured from the tube axis (0: to the centre of the flow)
    double chamfer = 0.5e-3;         // 45-degree chamfer on the outer edge of each tip
    double cutout_radius = 0.6e-3;   // curved variant: circular cutout in the inner face at the base
    double insert_width = 1.0e-3;    // insert variant: x extent of the iron inserts bridging the wall
};

struct MaterialParameters {
    double iron_relative_permeability = 1000.0;  // soft (mild) steel, linear model
    bool iron_nonlinear = false;                 // Frohlich-Kennelly saturation curve instead
    double iron_saturation = 2.0;                // T, J_s of the saturation curve
    double fluid_relative_permeability = 10.0;   // MR fluid, linear (the source's value)
};

struct EpmModel {
    ValveGeometry valve;
    MagnetParameters magnets;
    BracketParameters bracket;
    MaterialParameters materials;

    // Derived positions (metres, model frame).
    double gap() const { return magnets.length; }  // between the brackets' inner faces
    double magnet_front_x() const { return -(0.5 * valve.outer_diameter() + bracket.tube_clearance); }
    double magnet_back_x() const { return magnet_front_x() - magnets.width; }
    double bracket_tip_x() const;  // unguided: the magnets' front face
    double magnets_z_span() const { return 2.0 * magnets.depth + magnets.spacing; }

    // Problems with the description, each "path: what is wrong and the fix"; empty if none.
    std::vector<std::string> problems() const;
};

}  // namespace mrjam::magnetics
