#pragma once
// The two-way coupled carrier flow through a circular valve (scene: fluid/flow "coupled"): the
// fluid's axial speed on a coarse grid of slices along the tube, each cut into equal rings, as
// lib/jam/coupled_flow.hpp solves it from the grains (radial Brinkman equation per slice,
// fluid/brinkman_slice.hpp). Where grains rest packed the fluid slows and goes round them,
// instead of every grain's lag being charged to the whole circuit as the one-profile
// pressure-driven option does (lib/jam/axial_resistance.hpp).
//
// Grid: the stretch [z_lo, z_hi] is cut at the valve's breakpoints (taper start, throat start,
// orifice exit), so the passage radius R(z) is smooth inside each slice, and each piece into
// slices of about `cell_length`. Slice k holds u_kj at the ring centres (j + 1/2) R_k / n, with
// R_k the radius that gives the slice's clear Poiseuille resistance. Between ring centres u is linear in r / R(z), zero
// at the wall; along z it is linear between slice centres of the same piece and scaled by (R_k / R(z))^2, so the
// taper's slices carry their flow rate into the narrowing cone. In the taper the radial velocity u_r = u_z r R'(z) /
// R(z) keeps the streamlines at fixed r / R (as the converging profile, fluid/valve_flow.hpp). Past the orifice exit
// the fluid leaves as a jet that re-opens to the bore over `jet_length` (the converging profile's mirrored taper): the
// slices there solve only the stream, r < R_f(z), and the fluid in the step's corner outside it is at rest. (The
// slices' lubrication balance has no inertia, so it cannot make the jet itself: without it the
// throat's plug would stop dead at the exit and pile the grains there.)
#include <cstdint>
#include <vector>

#include "fluid/flow_field.hpp"
#include "fluid/valve_flow.hpp"
#include "geometry/valve.hpp"

namespace mrjam {

struct FlowSlice {
    double z_lo, z_hi;
    double radius;  // R_k: the stream's radius with the slice's Poiseuille resistance (~ at its centre)
    bool walled;    // the stream's edge is the passage wall (not the jet's edge)
    int piece;      // slices of one piece (between breakpoints) are interpolated into each other
    double centre() const { return 0.5 * (z_lo + z_hi); }
};

class CoupledValveFlow final : public FlowField {
public:
    // `jet_length` > 0: how far past the exit the stream re-opens to the bore.
    CoupledValveFlow(const ValveGeometry& valve, double z_lo, double z_hi, double cell_length, int rings,
                     double jet_length);
    Vec3 velocity(const Vec3& x, double) const override;
    std::string name() const override { return "valve_coupled"; }
    // The hindered-drag factor of the ring holding x (1 outside the grid).
    double drag_factor(const Vec3& x) const override;
    // velocity() and drag_factor(), bit for bit, locating x once (a tenth of a step's time in the
    // 10 um valve went to locating every grain twice).
    Drag drag_at(const Vec3& x, double time) const override;

    const std::vector<FlowSlice>& slices() const { return slices_; }
    int rings() const { return rings_; }
    // Slice holding z (clamped to the grid) and ring holding x (r / R_f(z), clamped to the wall
    // ring; -1 outside the stream, in the jet's still corner).
    std::size_t slice_at(double z) const;
    int ring_at(const Vec3& x) const;
    // The moving stream's radius R_f(z) and slope: the passage's, except in the jet.
    double stream_radius(double z) const;
    double stream_slope(double z) const;
    const ValveGeometry& valve() const { return valve_; }

    // The field, slice-major (u[k * rings + j]); set between steps only (the force pass reads it).
    void set_field(const std::vector<double>& axial_speed, const std::vector<double>& drag_factors);
    const std::vector<double>& axial_speed() const { return speed_; }
    const std::vector<double>& drag_factors() const { return factor_; }

private:
    double slice_profile(std::size_t k, double xi) const;  // u of slice k at r / R = xi
    // The velocity at x given its stream radius R, distance r from the axis and slice k.
    Vec3 velocity_in(const Vec3& x, double R, double r, std::size_t k) const;
    // The ring at axial position z, distance r from the axis, stream radius rf (as ring_at), and
    // the drag factor there in slice k (1 off the grid).
    int ring_of(double z, double r, double rf) const;
    double factor_in(double z, std::size_t k, double r, double rf) const;
    double resistance_radius(double lo, double hi) const;
    void build_slice_table();
    ValveGeometry valve_;
    int rings_;
    double jet_length_;
    std::vector<FlowSlice> slices_;
    // slice_at's starting guess: equal bins over the grid, each naming the slice at its centre.
    // No bin is wider than the narrowest slice, so the exact answer is at most a step or two
    // away; against a binary search over the slices, 10 % less per drag_at call, about 1 % of
    // the 10 um valve's step (docs/notes/benchmark_log.md, "Carrier flows").
    double table_origin_ = 0, table_inverse_width_ = 0;
    std::vector<std::uint32_t> table_slice_;
    std::vector<double> speed_, factor_;
};

}  // namespace mrjam
