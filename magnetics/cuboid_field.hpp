#pragma once
// Flux density of a uniformly magnetised, axis-aligned rectangular block (cuboid) in free space,
// in closed form, at any point outside or inside the magnet.
//
// Model (Coulombian / surface-charge, as in Akoun & Yonnet, IEEE Trans. Magn. 20 (1984) 1962;
// Furlani, "Permanent Magnet and Electromechanical Devices", Academic Press 2001, sec. 4.3;
// Engel-Herbert & Hesjedal, J. Appl. Phys. 97 (2005) 074504): a uniform magnetisation M has no
// volume charge (div M = 0) and a surface charge sigma = M . n on the faces. The faces normal to
// M carry +-|M_k|; H is the Coulomb field of those charged rectangles, and B = mu0 (H + M), so
// inside the block the remanence Br = mu0 M is added. A general direction of Br is the
// superposition of its three axis components, each with its own pair of charged faces.
//
// Where it is finite: everywhere except on the 12 edges of the block (including its corners),
// where the tangential field diverges logarithmically (an edge between two charged faces, or a
// charged face's rim, is a line of discontinuous charge). Points on those edges give +-inf or NaN
// components. Points on the faces but off the edges are finite: a face belongs to the (closed)
// magnet, so the value there is the limit from inside, which has the same normal B as outside.
// Points on the straight-line extensions of edges, outside the block, are finite and handled.
//
// Accuracy: close to machine precision near the magnet (1e-14 measured against quadrature). Far
// away, the corner terms (O(1) off-axis) cancel to the face fields and the two faces' fields
// cancel to a dipole, so about 3 log10(r / size) digits are lost: measured relative rounding
// ~1e-7 at r = 1000 sizes, where the point dipole m = M V (relative error ~0.2 (size/r)^2, also
// ~1e-7 there) is as good and much cheaper. Use the dipole beyond a few hundred sizes.
#include "core/vec3.hpp"

namespace mrjam::magnetics {

struct Cuboid {
    Vec3 centre;       // metres
    Vec3 size;         // full side lengths along x, y, z, metres (all > 0)
    Vec3 remanence_T;  // Br = mu0 M, tesla, any direction
};

// B in tesla at `point` (metres). Inside the closed block B includes the mu0 M = Br term.
Vec3 cuboid_flux_density(const Cuboid& magnet, const Vec3& point);

// True when `point` is inside the block or on its surface (where Br is added to mu0 H).
bool cuboid_contains(const Cuboid& magnet, const Vec3& point);

}  // namespace mrjam::magnetics
