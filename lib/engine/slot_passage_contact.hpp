#pragma once
// Nearest-point geometry of a sphere centre against the walls of a valve bore with a slot
// orifice (geometry/slot_orifice.hpp).
//
// The solid around the fluid is the union of five simple pieces: the outside of the bore
// cylinder and four "plates" (x > X(z), x < -X(z), y > Y(z), y < -Y(z), each over the
// constriction's length). Each plate ignores the coordinate it does not bound, so its distance is
// a 2-D distance to a convex polygon in the (x, z) or (y, z) plane: its edges are the tapered
// flat face, the slot's straight face and the step face with the rectangular hole, its corners
// the taper-to-slot edge and the orifice lip. The distance to a union is the least distance to
// its pieces, so the result is exact: the face, edge or lip the centre is nearest to.
// Concave corners (the slot's four long edges, where an x plate meets a y plate; the step
// meeting the bore; the bore meeting a tapered face): a sphere can press on two or three pieces
// at once. Given its radius, the other pieces it reaches on a face (not at an edge or the lip,
// which the nearest piece's contact already is) are listed too, so that the wall pushes it out
// of each, as the circular passage does (lib/engine/walls.cpp).
#include <array>

#include "core/vec3.hpp"
#include "geometry/slot_orifice.hpp"

namespace mrjam {

struct SlotReach {
    double distance = 0;
    Vec3 normal;  // unit, from the wall towards the centre (into the fluid)
};

struct SlotContact {
    bool centre_in_fluid = true;
    // In the fluid: distance to the nearest wall point; in the solid (a blow-up's overlap
    // beyond the radius): the depth below the surface of the piece it is deepest in.
    double distance = 0;
    Vec3 normal;  // unit, from the wall towards the centre (into the fluid)
    // Centre in the fluid, nearest point on a face: the other pieces within `reach` on a face.
    std::array<SlotReach, 4> corner{};
    int corner_count = 0;
};

// `p` in the slot's frame (axis z, throat centre at the origin); `reach` the sphere's radius
// (0: the nearest piece only).
SlotContact slot_passage_contact(const SlotOrifice& slot, const Vec3& p, double reach = 0);

}  // namespace mrjam
