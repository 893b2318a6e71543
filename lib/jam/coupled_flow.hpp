#pragma once
// The two-way coupled carrier flow of `mrjam jam` (fluid/flow "coupled"): the supply pressure
// drives the fluid through the rest of the circuit and through the grains, and the fluid finds
// its own way through them (lib/engine/fluid/coupled_valve_flow.hpp holds the field the grains feel).
//
// Model (stated in the report):
//  * Grid: slices along the tube (about `cell_length` each) cut into rings of equal width. In
//    ring (k, j) the grains' volume fraction phi_kj is their volume over the ring's fluid volume
//    (cut by the slab walls); their drag coefficient per unit volume is
//        beta_kj = sum_i 6 pi mu a_i f_kj / V_kj,   f_kj = Kozeny-Carman factor of phi_kj
//    (relative to the feed fraction, as the one-profile option; the wall ring's volume counted
//    to R - wall_gap, where centres can be), and v_kj their drag-weighted
//    axial speed. The fluid feels exactly the drag the grains feel, reversed.
//  * Each slice: lubrication (the pressure uniform across the slice, gradient G_k) and the radial
//    Brinkman equation (fluid/brinkman_slice.hpp), linear in G_k: u_k = G_k a_k + b_k, so its flow
//    rate is Q = G_k Qa_k + Qb_k.
//  * Continuity: the same flow rate Q through every slice (the grains' volume change is ignored).
//  * Circuit: P = R_c Q + sum_k G_k dz_k, with R_c sized so that the supply pressure P drives the
//    source's bore flow rate Q0 (the bore profile at the bore speed, fluid/valve_flow.hpp) through
//    clear fluid; Q is clamped to [0, Q0] as in the one-profile option.
//  * Past the orifice exit the slices solve the jet only (lib/engine/fluid/coupled_valve_flow.hpp);
//    grains in the still corner outside it feel no flow and give the fluid no drag.
// With the grains moving as the fluid they add nothing, and the flow is Poiseuille's in every
// slice at Q0; a packed bed at rest across a slice throttles Q; a pile resting in the corner
// outside the jet costs nothing.
#include <memory>
#include <vector>

#include "fluid/coupled_valve_flow.hpp"
#include "jam/axial_resistance.hpp"
#include "system.hpp"

namespace mrjam {

struct CoupledFlowSettings {
    double slab_half_thickness = 0;  // 0: the full bore
    double z_lo = 0, z_hi = 0;       // the modelled stretch
    double cell_length = 0;          // slice length, m
    int rings = 0;                   // rings per slice
    double feed_fraction = 0;
    double supply_pressure = 0;  // Pa
    double viscosity = 0;        // Pa s
    double bore_speed = 0;       // m/s (sets Q0)
    // Grain centres stay a radius from the wall, so the wall ring's fraction is counted over the
    // part of it they can reach, up to R - wall_gap (the mix's volume-weighted mean radius):
    // otherwise a ring narrower than a diameter looks half empty at the wall and the fluid
    // slips past a packed bed there.
    double wall_gap = 0;
    double jet_length = 0;  // past the exit, the stream re-opens to the bore over this, m
};

class CoupledFlow {
public:
    CoupledFlow(const ValveGeometry& valve, const CoupledFlowSettings& settings);
    std::shared_ptr<CoupledValveFlow> field() const { return field_; }
    // Bins the grains, solves the slices and the circuit, and sets the field the grains feel.
    // `supply` is the supply pressure now (protocol/hold_pressure; the circuit stays sized for the
    // settings' supply_pressure); negative for that one; 0 stops the fluid.
    AxialResistanceState update(const System& s, double supply = -1) const;
    double reference_flow_rate() const { return q0_; }
    // What the clear stretch costs at Q0 (Poiseuille on the grid), Pa.
    double clear_stretch_pressure() const { return clear_pressure_; }
    // Each slice's pressure drop G_k dz_k at the last update (where the stretch spends the
    // pressure), Pa, and the grains' volume fraction in it.
    const std::vector<double>& slice_pressure() const { return slice_pressure_; }
    const std::vector<double>& slice_fraction() const { return slice_fraction_; }
    std::size_t cells() const { return field_->slices().size() * static_cast<std::size_t>(field_->rings()); }
    double ring_volume(std::size_t k, int j) const {
        return volume_[k * static_cast<std::size_t>(field_->rings()) + static_cast<std::size_t>(j)];
    }

private:
    CoupledFlowSettings set_;
    std::shared_ptr<CoupledValveFlow> field_;
    std::vector<double> volume_;  // fluid volume of each ring, slice-major
    double q0_ = 0, clear_pressure_ = 0, circuit_resistance_ = 0;
    mutable std::vector<double> slice_pressure_, slice_fraction_;
};

// The clear fluid's pressure drop along the stretch [z_lo, z_hi] at flow rate q (Poiseuille,
// 8 mu q / (pi R_f^4) integrated over the stream, jet included), for checking a supply pressure
// before a run.
double clear_stretch_pressure(const ValveGeometry& valve, double z_lo, double z_hi, double jet_length, double viscosity,
                              double q);

}  // namespace mrjam
