#pragma once
// The open valve's flow rate at a supply pressure: the suspension's viscosity from
// Krieger-Dougherty, mu_s = mu (1 - phi/phi_m)^(-[eta] phi_m) with [eta] = 2.5, phi_m = 0.64;
// Poiseuille losses in the modelled bore and in the throat (taper included as throat length),
// and the orifice's contraction loss rho Q^2 / (2 C_d^2 A_t^2) with C_d = 0.61 (sharp-edged
// orifice). Solving P = a Q + b Q^2 for Q. A designer's estimate, not a simulation.
#include "geometry/valve.hpp"

namespace mrjam {

struct OpenFlowEstimate {
    double suspension_viscosity = 0;  // Pa s
    double flow_rate = 0;             // m^3/s
    double throat_speed = 0;          // m/s, mean in the throat
    double reynolds_throat = 0;
};

OpenFlowEstimate open_flow_estimate(const ValveGeometry& valve, double carrier_viscosity, double volume_fraction,
                                    double suspension_density, double supply_pressure);

}  // namespace mrjam
