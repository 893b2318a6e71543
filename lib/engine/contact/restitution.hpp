#pragma once
// Damping for the Hertz contact, eq. 2.1: F = k_n d - gamma_n v with
// gamma_n = 2 sqrt(5/6) beta sqrt(S_n m*), S_n = 2 Y* sqrt(R* d), beta = |ln e| / sqrt(ln^2 e + pi^2).
// For this law the restitution a pair shows is e exactly, whatever the speed: the beta of a linear
// spring carries over because the sqrt(5/6) factor absorbs the d^(1/4) growth of the damping. We
// checked this by integrating the dimensionless collision (tests/test_contact_physics.cpp: agreement
// to 1e-7 for e from 0.1 to 0.9), so no calibration table is needed.
namespace mrjam {

double damping_beta_for_restitution(double e);

// Duration of an undamped Hertz collision (Johnson, Contact Mechanics, eq. 11.24):
// 2.9433 (15 m* / (16 sqrt(R*) Y*))^(2/5) v^(-1/5).
double hertz_contact_duration(double reduced_mass, double reduced_radius, double effective_youngs, double impact_speed);

}  // namespace mrjam
