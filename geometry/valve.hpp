#pragma once
// The valve body: a tube that holds the MR fluid, with a tapered circular constriction (the
// throat) where the grains jam. One description shared by the magnetostatic model (magnetics/)
// and the jam predictor, so both see the same valve.
//
// Frame: the tube axis is z, the flow runs towards +z, the throat centre is the origin. The
// fluid converges from the tube bore to the throat over `taper_length`, runs `throat_length` at
// the throat diameter, then re-opens abruptly to the bore (a printed orifice plate with a
// tapered entry, as in section 3.2 of the source).
//
// The orifice is circular (the source's) or, as an option, a rectangular slot
// (geometry/slot_orifice.hpp): `slot_width` across the field (x) by `constriction_diameter`
// along it (y), so the gap the field's chains must bridge is the same number as for the circle.
#include <string>
#include <vector>

#include "core/vec3.hpp"
#include "geometry/slot_orifice.hpp"

namespace mrjam {

enum class Orifice { circular, slot };

struct ValveGeometry {
    Orifice orifice = Orifice::circular;
    double tube_inner_diameter = 2.6e-3;     // bore of the valve body
    double wall_thickness = 0.3e-3;          // printed wall: the body's 3.2 mm outside fills the magnet gap
    double constriction_diameter = 1.32e-3;  // throat (the source's 30x preset: 30 x 44 um)
    double taper_length = 0.8e-3;            // converging cone, bore -> throat
    double throat_length = 0.2e-3;           // straight part at the throat diameter
    double upstream_length = 4.0e-3;         // fluid modelled upstream of the throat centre
    double downstream_length = 4.0e-3;       // and downstream of it
    double slot_width = 0;  // slot only: its size along x (its height along y is constriction_diameter)

    double outer_diameter() const { return tube_inner_diameter + 2.0 * wall_thickness; }
    double bore_radius() const { return 0.5 * tube_inner_diameter; }
    double throat_radius() const { return 0.5 * constriction_diameter; }
    // z where the taper starts (bore diameter) and where the throat ends (the orifice exit).
    double taper_start_z() const { return -0.5 * throat_length - taper_length; }
    double throat_end_z() const { return 0.5 * throat_length; }

    bool is_slot() const { return orifice == Orifice::slot; }
    // The slot's description in its own frame (meaningful for a slot orifice only).
    SlotOrifice slot() const;

    // Radius of the fluid passage at axial position z (bore radius outside the constriction);
    // circular orifice only (a slot has no radius: use passage_half_height or slot()).
    double passage_radius(double z) const;
    // Half extent of the passage along y (the field) in the mid-plane x = 0: the radius for a
    // circular orifice, min(Y(z), bore radius) for a slot. What a cut-plane picture draws.
    double passage_half_height(double z) const;
    // Cross-section area of the passage at z.
    double section_area(double z) const;
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
