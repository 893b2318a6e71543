#pragma once
// The dimensionless numbers a rheologist compares MR flow curves by (Klingenberg, van Swol and
// Zukoski, "The small shear rate response of electrorheological suspensions", J. Chem. Phys. 2007;
// Ruiz-Lopez et al., "Rheology of magnetorheological fluids", Soft Matter 2017):
// - the Clausius-Mossotti contrast beta of the grains (clausius_mossotti, magnetic/magnetic_model.hpp);
// - the magnetic stress scale 2 mu0 beta^2 H0^2, H0 = B / mu0 the applied field in the carrier;
// - the Mason number Mn = eta gamma_dot / (2 mu0 beta^2 H0^2), viscous over magnetic stress.
// A Bingham fluid's stress over the magnetic scale falls on one curve against Mn whatever the
// field, as long as the grains do not saturate.

namespace mrjam {

// Pa; 0 with no field.
double magnetic_stress_scale(double flux_density, double beta);

// Infinite with no field (viscous stress over a zero magnetic scale).
double mason_number(double viscosity, double shear_rate, double flux_density, double beta);

}  // namespace mrjam
