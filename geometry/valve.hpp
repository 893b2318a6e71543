#pragma once
// The valve body: a tube that holds the MR fluid, with a tapered circular constriction (the
// throat) where the grains jam. One description shared by the magnetostatic model (magnetics/)
// and the jam predictor, so both see the same valve.
//
// Frame: the tube axis is z, the flow runs towards +z, the throat centre is the origin. The
// fluid converges from the tube bore to the throat over `taper_length`, runs `throat_length` at
// the throat diameter, then re-opens abruptly to the bore (a printed orifice plate with a
// tapered entry, as in section 3.2 of the source).
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct ValveGeometry {
    double tube_inner_diameter = 2.6e-3;    // bore of the valve body
    double wall_thickness = 0.3e-3;         // printed wall: the body's 3.2 mm outside fills the magnet gap
    double constriction_diameter = 1.32e-3; // throat (the source's 30x preset: 30 x 44 um)
    double taper_length = 0.8e-3;           // converging cone, bore -> throat
    double throat_length = 0.2e-3;          // straight part at the throat diameter
    double upstream_length = 4.0e-3;        // fluid modelled upstream of the throat centre
    double downstream_length = 4.0e-3;      // and downstream of it

    double outer_diameter() const { return tube_inner_diameter + 2.0 * wall_thickness; }
    double bore_radius() const { return 0.5 * tube_inner_diameter; }
    double throat_radius() const { return 0.5 * constriction_diameter; }
    // z where the taper starts (bore diameter) and where the throat ends (the orifice exit).
    double taper_start_z() const { return -0.5 * throat_length - taper_length; }
    double throat_end_z() const { return 0.5 * throat_length; }

    // Radius of the fluid passage at axial position z (bore radius outside the constriction).
    double passage_radius(double z) const;
    // Whether a point is inside the fluid passage (and within the modelled length).
    bool in_fluid(const Vec3& point) const;
    // Fluid volume of the modelled length, exact for the cone.
    double fluid_volume() const;

    // Problems with the description, each as "field: what is wrong and the fix"; empty if none.
    std::vector<std::string> problems() const;
};

// The source's three constrictions are named by their ratio to the largest grain (44 um):
// "20x" 0.88 mm, "30x" 1.32 mm, "40x" 1.76 mm. Returns the diameter in metres, or 0 if the name
// is not a preset.
double constriction_preset(const std::string& name);
std::vector<std::string> constriction_preset_names();

}  // namespace mrjam
