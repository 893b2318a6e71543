#pragma once
// The forces between two touching equal grains of radius R at an asteroid's surface, as power laws
// of R (section 4.5 of the source, Fig. 4.15): a grain's weight in surface gravity (R^3), the two
// grains' mutual gravity (R^4), cohesion (R) and the magnetic attraction of two aligned dipoles
// (R^2). Every force here is C R^n, so where two of them cross is a closed form.
#include <string>

#include "magnetic/magnetic_model.hpp"

namespace mrjam {

inline constexpr double kGravitationalConstant = 6.67430e-11;  // m^3 / (kg s^2), CODATA 2018

// F(R) = coefficient R^exponent, in newtons with R in metres.
struct PowerLaw {
    double coefficient = 0;
    int exponent = 0;
    double at(double radius) const;
};

// Eq. 4.13: rho (4/3) pi R^3 g.
PowerLaw surface_gravity_force(double density, double surface_gravity);

// Two touching equal spheres: G m^2 / (2R)^2 = G rho^2 (4/9) pi^2 R^4. The source's Eq. 4.14,
// G (rho (1/3) pi R^2)^2, is four times smaller (it does not follow from m = rho (4/3) pi R^3 at a
// distance 2R); it is offered by name for comparison with Fig. 4.15.
enum class SelfGravityFormula { two_spheres, printed };
PowerLaw self_gravity_force(double density, SelfGravityFormula formula);
const char* formula_name(SelfGravityFormula formula);

// Eq. 4.15 (Scheeres et al. 2010): 3.6e-2 S^2 R, S the cleanliness (1 clean, 0.1 dirty).
PowerLaw cohesion_force(double cleanliness);

// Soft (induced) grains: linear with relative permeability mu_r up to the saturation
// magnetisation M_s, where the moment stops growing (as the engine's induced dipoles).
struct SoftMagneticGrain {
    double relative_permeability = 1000;
    double saturation_magnetisation = 1.7e6;  // A/m
    double beta() const { return clausius_mossotti(relative_permeability); }
};

// How the attraction of two touching soft grains aligned with the field is modelled.
enum class InducedPairModel {
    fixed_dipoles,   // each moment from the applied field alone, m = 4 pi R^3 beta H0
    mutual_dipoles,  // the moments converged in each other's field: m = 4 pi R^3 beta H0 / (1 - beta/4)
    exact_pair,      // the exact linear two-sphere force (multipoles), at a stated surface gap
};
const char* model_name(InducedPairModel model);

// The magnetisation each grain of the pair carries (A/m) in the applied flux density B0 (T), and
// whether it reached M_s (the exact pair is linear: it has no such cap, and says so).
struct PairMagnetisation {
    double magnetisation = 0;
    bool saturated = false;
};
PairMagnetisation induced_pair_magnetisation(const SoftMagneticGrain& grain, double flux_density,
                                             InducedPairModel model);

// The magnetisation of a lone grain in B0, 3 beta H0: the source's "equivalent magnetisation"
// (5e-4 T gives 1190 A/m for mu_r = 1000).
double equivalent_magnetisation(const SoftMagneticGrain& grain, double flux_density);

// The attraction of two aligned point dipoles of magnetisation M touching at 2R:
// 3 mu0 m^2 / (2 pi (2R)^4) with m = M (4/3) pi R^3, i.e. mu0 pi M^2 R^2 / 6.
PowerLaw dipole_pair_force(double magnetisation);

// The attraction of two touching soft grains in B0 by the named model. `exact_gap` is the surface
// gap (in radii) at which the exact pair is evaluated: the linear force grows without bound as
// the gap closes, so a gap (the grains' roughness) must be stated.
PowerLaw induced_pair_force(const SoftMagneticGrain& grain, double flux_density, InducedPairModel model,
                            double exact_gap);

// The radius where a(R) = b(R); NaN when the exponents are equal (they never cross, or always).
double crossover_radius(const PowerLaw& a, const PowerLaw& b);

}  // namespace mrjam
