#pragma once
// The ranges a material's density and Young's modulus, and an applied field, must lie in, wherever
// a scene names them (run, jam and shear scenes alike). Real solids span about 1e5 Pa (soft rubber) to 1.2e12 Pa
// (diamond) and 10 to 22,600 kg/m3 (osmium); the ranges are wider so that stiffness and mass
// scaling still fit, and narrow enough that a slip of units (a modulus in GPa written as Pa, a
// density of 1e-300) is refused by name before the run instead of blowing up in it.
#include <string>

#include "core/format.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

inline Bounds youngs_modulus_range() { return Bounds::closed(1e3, 1e13); }  // Pa
inline Bounds density_range() { return Bounds::closed(1.0, 1e8); }          // kg/m3

// No magnet applies more than 10 T to a sample (the valve's EPM gives 0.2-0.8 T, a laboratory
// electromagnet 1-2 T, a superconducting one about 10): "230 T" is "230 mT" mistyped, and would
// run (saturated grains) or blow up (linear ones) instead of being refused.
inline constexpr double kLargestAppliedFluxDensity = 10.0;  // T
inline void check_applied_flux_density(const SceneNode& node, const std::string& key, double tesla) {
    if (tesla > kLargestAppliedFluxDensity)
        node.fail(key, format_number(tesla) + " T is more than any magnet applies (" +
                           format_number(kLargestAppliedFluxDensity) +
                           " T at most; the valve's EPM gives 0.2-0.8 T): did you mean mT?");
}
// The same bound on a field map's strongest node once its `scale_key` has scaled it.
inline void check_map_scale(const SceneNode& node, const std::string& scale_key, double scaled_peak_tesla) {
    if (scaled_peak_tesla > kLargestAppliedFluxDensity)
        node.fail(scale_key, "raises the map's strongest node to " + format_number(scaled_peak_tesla) +
                                 " T, more than any magnet applies (" + format_number(kLargestAppliedFluxDensity) +
                                 " T at most); give a smaller scale");
}

}  // namespace mrjam
