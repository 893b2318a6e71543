#pragma once
// Axial flow through one slice of a tube holding grains (the coupled carrier flow,
// lib/engine/fluid/coupled_valve_flow.hpp): the radial Brinkman equation
//     -mu (1/r) d/dr (r du/dr) + beta(r) (u - v(r)) = G,   du/dr = 0 at r = 0,  u = 0 at r = R,
// where G is the pressure gradient driving the fluid (-dp/dz), beta the grains' drag coefficient
// per unit volume (sum of 6 pi mu a f over the grains in a ring, over its volume) and v their
// drag-weighted axial velocity. Clear fluid (beta = 0) gives Poiseuille's parabola; a packed ring
// at rest (beta large, v = 0) lets fluid through only at its Darcy speed G / beta, so the flow goes
// round it, within a Brinkman layer sqrt(mu / beta) of its edge.
//
// Finite volumes on n equal rings (centres r_j = (j + 1/2) R / n), second order in R / n; the
// tridiagonal system is solved directly (Thomas; diagonally dominant, so no pivoting).
#include <vector>

namespace mrjam {

struct BrinkmanRings {
    double radius = 0;                // R, m
    double viscosity = 0;             // mu, Pa s
    std::vector<double> beta;         // per ring, Pa s / m^2 (0: clear fluid)
    std::vector<double> grain_speed;  // v per ring, m/s
};

// u per ring for pressure gradient G (Pa/m).
std::vector<double> brinkman_profile(const BrinkmanRings& rings, double pressure_gradient);
// Flow rate of a ring profile (the full circle: sum of 2 pi r_j dr u_j), m^3/s.
double ring_flow_rate(const std::vector<double>& u, double radius);

}  // namespace mrjam
