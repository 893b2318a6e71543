#pragma once
// The pressure-driven carrier flow of `mrjam jam` (fluid/flow "pressure"): the supply pressure
// drives the fluid through the rest of the circuit and through the grains in the modelled
// stretch of valve; where the grains pack, their Kozeny-Carman resistance slows the whole flow,
// so a jam really stops the fluid.
//
// Model (stated in the report):
//  * The stretch is cut into axial cells (coarse: a few grain diameters). In cell k the grains'
//    volume fraction phi_k is the grain volume whose centres lie in it over the cell's fluid
//    volume (the passage, cut by the slab walls).
//  * Drag per grain: the source's Stokes drag 6 pi mu R (u - v), kept as it is at the mix's
//    feed fraction phi_0 (the source tuned its flow with it), raised in denser cells by
//    Kozeny-Carman's per-grain dependence phi / (1 - phi)^2:
//        f_k = max(1, [phi_k (1 - phi_0)^2] / [phi_0 (1 - phi_k)^2]),  phi_k capped at 0.62.
//  * Pressure: the drag the fluid exerts on the grains of a cell is the pressure drop across
//    it times its mean section, dP_k = (s D1_k - Dv_k) / A_k, with D1_k the drag of the unscaled
//    profile on the cell's grains at rest and Dv_k that of their own axial motion.
//  * Circuit: the rest of the circuit is a linear resistance sized so that the supply pressure P
//    drives the prescribed profile (scale 1) while the grains move with the fluid:
//        P = s P + sum_k dP_k(s)   =>   s = (P + sum_k Dv_k/A_k) / (P + sum_k D1_k/A_k).
//    Free-flowing grains (v = u) give s = 1; an arrested, packed bed whose drag at the
//    prescribed flow would far exceed P stops the fluid (s -> 0), and a bed the supply can
//    push through keeps a share of the flow. A supply P' other than the P the circuit was
//    sized for (protocol/hold_pressure) drives s = (P' + sum Dv/A) / (P + sum D1/A), up to P'/P.
#include <vector>

#include "fluid/valve_flow.hpp"
#include "system.hpp"

namespace mrjam {

struct AxialResistanceState {
    double scale = 1.0;            // flow scale s
    double stretch_pressure = 0;   // sum_k dP_k at the new scale, Pa
    double arrested_pressure = 0;  // sum_k D1_k / A_k: what the prescribed flow pushes a bed at rest with, Pa
    double max_fraction = 0;       // densest cell's phi
    double max_drag_factor = 1;
};

// One observation of the resistance cells, as the report's flow history keeps it.
struct FlowSample {
    double time, scale, stretch_pressure, max_fraction;
};

class AxialResistance {
public:
    // Cells of about `cell_length` between z_lo and z_hi; `slab_half_thickness` 0 for the full bore.
    AxialResistance(const ValveGeometry& valve, double slab_half_thickness, double z_lo, double z_hi,
                    double cell_length, double feed_fraction, double supply_pressure);
    // Recomputes the cells from the grains; when `drive` sets the flow's drag factors and scale,
    // otherwise (the prescribed flow) only measures, with Stokes drag (factors 1, scale 1).
    // `supply` is the supply pressure now (the circuit stays sized for the scene's); negative for that
    // one; 0 stops the fluid (closed first, the grains are magnetised at rest).
    AxialResistanceState update(const System& s, ValveFlow& flow, bool drive, double supply = -1) const;
    // Sets the flow's cell factors (as update() does; for a resumed run).
    void apply(ValveFlow& flow, std::vector<double> factors) const {
        flow.set_drag_factors(z_lo_, dz_, std::move(factors));
    }
    // Kozeny-Carman's per-grain drag relative to the feed fraction (>= 1).
    double drag_factor(double fraction) const;
    std::size_t cells() const { return volume_.size(); }
    double cell_volume(std::size_t k) const { return volume_[k]; }
    double cell_section(std::size_t k) const { return volume_[k] / dz_; }

private:
    double z_lo_, dz_, feed_, pressure_;
    std::vector<double> volume_;  // fluid volume of each cell
};

// Kozeny-Carman's per-grain drag at volume fraction phi relative to the feed fraction (>= 1;
// phi capped at 0.62, below random close packing, so that the explicit step's drag stays bounded).
double kozeny_carman_factor(double phi, double feed_fraction);

// Area of the disc of radius r inside the slab |x| < h (the whole disc if h = 0 or h >= r).
double slab_section(double r, double h);

}  // namespace mrjam
