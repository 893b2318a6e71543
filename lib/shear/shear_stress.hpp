#pragma once
// Shear-cell observers. They read the state after a step and never change it.
//
// Raft stress (eq. 2.8): tau = -(x-force the suspension exerts on the upper boundary) / (X Y).
// The upper boundary is the upper raft together with the top wall behind it, so grains that slip
// through the raft to the wall still count; the raft-wall forces are internal to that boundary and
// cancel in the sum. Computed from the grains' total forces, it includes contact and magnetic
// forces (the engine's own raft sum holds the contact part only).
//
// Bulk (virial) stress over the gap between the rafts, volume V = X Y h (h the gap):
//   tau_bulk = -(1/V) [ sum_pairs (z_i - z_j) f_ij,x + sum_free (z_i - z_mid) D_i,x ]
//              -(1/V) sum_free m_i (v_i,x - u_x(z_i)) v_i,z
// over every contact and magnetic pair with at least one free grain (f_ij the force on i from j)
// and the Stokes drag D_i. In steady state the moment balance of the free grains makes this equal
// to the mean of the upper and lower raft stresses, up to where inside its raft layer each raft
// force acts: a relative difference of order (grain diameter) / h (docs/shear.md).
#include "system.hpp"

namespace mrjam {

struct ShearStress {
    double upper = 0;  // Pa, raft stress on the upper boundary (moving +x)
    double lower = 0;  // Pa, on the lower boundary (moving -x), sign chosen so both are positive when resisting
    double bulk = 0;   // Pa, virial stress of the gap
};

// `upper_raft`/`lower_raft`: raft indices; `top_wall`/`bottom_wall`: wall indices (-1 if none).
// z_lower, z_upper: the inner faces of the rafts (the gap).
ShearStress shear_stress(const System& system, int upper_raft, int lower_raft, int top_wall, int bottom_wall,
                         double z_lower, double z_upper);

// Virial stress of a Lees-Edwards cell, volume V = X Y Z (the whole periodic box):
//   tau = -(1/V) [ sum_pairs (z_i - z_j) f_ij,x + sum m_i (v_i,x - u_x(z_i)) v_i,z ]
// with the pair vectors through the sliding images. No drag moment: the box has no boundary for
// the drag's moment to be taken about (z is periodic), and in homogeneous shear the drag has no
// mean in any layer, so the momentum flux across every z plane is the pair and kinetic sum alone.
double lees_edwards_stress(const System& system);

// The x force per area that the grains above the sliding boundary exert, through it, on the
// grains below (pairs listed with a z image; method of planes): the momentum flux across that one
// plane. In steady homogeneous shear its time average equals the virial's, a check that the
// sliding images carry the stress (tests/test_lees_edwards_stress.cpp). The kinetic flux of grains
// crossing the plane is left out: small wherever the Stokes number is.
double lees_edwards_boundary_stress(const System& system);

// Chain-formation measures for the magnetisation criterion.
struct ChainState {
    double contacts_per_grain = 0;  // 2 x grain-grain contacts / grains
    double mean_abs_cos = 0;        // mean |cos| between contact normals and the field direction (0.5 when isotropic)
};
ChainState chain_state(const System& system, const Vec3& field_direction);

}  // namespace mrjam
