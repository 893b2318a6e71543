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
// A centre in a concave corner (two faces at equal reach) gets the nearer face's contact only,
// as on the circular passage.
#include "core/vec3.hpp"
#include "geometry/slot_orifice.hpp"

namespace mrjam {

struct SlotContact {
    bool centre_in_fluid = true;
    // In the fluid: distance to the nearest wall point; in the solid (a blow-up's overlap
    // beyond the radius): the depth below the surface of the piece it is deepest in.
    double distance = 0;
    Vec3 normal;  // unit, from the wall towards the centre (into the fluid)
};

// `p` in the slot's frame (axis z, throat centre at the origin).
SlotContact slot_passage_contact(const SlotOrifice& slot, const Vec3& p);

}  // namespace mrjam
