#pragma once
// The ranges a material's density and Young's modulus must lie in, wherever a scene names them
// (run, jam and shear scenes alike). Real solids span about 1e5 Pa (soft rubber) to 1.2e12 Pa
// (diamond) and 10 to 22,600 kg/m3 (osmium); the ranges are wider so that stiffness and mass
// scaling still fit, and narrow enough that a slip of units (a modulus in GPa written as Pa, a
// density of 1e-300) is refused by name before the run instead of blowing up in it.
#include "scene/scene_node.hpp"

namespace mrjam {

inline Bounds youngs_modulus_range() { return Bounds::closed(1e3, 1e13); }  // Pa
inline Bounds density_range() { return Bounds::closed(1.0, 1e8); }          // kg/m3

}  // namespace mrjam
