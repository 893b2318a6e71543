#pragma once
// Two equal, linearly magnetisable spheres in a uniform applied field, solved exactly (to a
// truncation order) by multipole expansion: the yardstick for how much the point-dipole
// (mutual dipole) model the engine uses underestimates the force between close grains.
//
// Units: radius a = 1, applied field H0 = 1. Each sphere's outside potential is
// sum_n A_n r^-(n+1) P_n^m(cos theta) e^{i m phi} about its own centre, with m = 0 for a field
// along the line of centres (axial) and m = 1 across it (transverse); P_n^m is Ferrers' function
// without the Condon-Shortley phase (std::assoc_legendre). The other sphere's outgoing harmonics
// are re-expanded about each centre (translation coefficients from Hobson's theorem, below) and
// each sphere's boundary conditions (psi and mu dpsi/dr continuous) close a linear system.
//
// The pair's polarisability alpha (its total moment over 4 pi a^3 H0; an isolated pair is 2 beta
// with beta = (mu - 1)/(mu + 2)) gives the force through the co-energy W' = mu0/2 H0 . M at fixed
// applied field: the force separating the spheres is F = 2 pi mu0 H0^2 a^2 d(alpha)/d(s), s the
// centre distance over a. Negative: attraction.
namespace mrjam {

enum class PairOrientation { axial, transverse };

struct SpherePairResponse {
    double polarisability = 0;      // total moment / (4 pi a^3 H0)
    double dpolarisability_ds = 0;  // its derivative with the centre distance over the radius
    int order = 0;                  // highest multipole order kept
};

// The exact response at truncation `order` (harmonics n = 1..order about each sphere).
// `separation` is the centre distance over the radius (> 2: the spheres must not overlap).
SpherePairResponse sphere_pair_response(double relative_permeability, double separation, PairOrientation orientation,
                                        int order);

// The same, doubling the order from 16 until alpha and its derivative change by less than
// `relative_tolerance`; throws std::runtime_error naming the gap if `max_order` is not enough.
SpherePairResponse converged_sphere_pair_response(double relative_permeability, double separation,
                                                  PairOrientation orientation, double relative_tolerance = 1e-7,
                                                  int max_order = 2048);

// The point-dipole (mutual dipole, converged) response of the same pair: each sphere a dipole
// of polarisability 4 pi beta a^3 in the applied field plus the other's dipole field.
SpherePairResponse mutual_dipole_pair_response(double relative_permeability, double separation,
                                               PairOrientation orientation);

// Coefficient of the regular harmonic r^l P_l^m e^{i m phi} about centre i in the expansion of
// the outgoing harmonic r^-(n+1) P_n^m e^{i m phi} about centre j, where centre j sits at
// `offset` along z from centre i (|offset| > the radius of the expansion); m is 0 or 1.
double translation_coefficient(int m, int l, int n, double offset);

}  // namespace mrjam
