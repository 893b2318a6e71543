#pragma once
// A contact stiffness that holds the magnetic pull on the finest grain (issue 45, the 33:67 fluid).
//
// Two of the largest grains along the field, with the finest grain caught between them, pull each
// other through it. At the source's softened modulus (1 GPa) a sub-micron grain's two Hertz
// contacts cannot bear that pull: it is crushed past the engine's overlap guard and the run blows
// up (docs/notes/shear_3367.md). Real iron (about 200 GPa) bears it at a few per cent of the
// radius. The rule, chosen once from that picture:
//   pull  F = 1.5^2 * 6 mu0 m^2 / (4 pi d^4): two linear dipoles m = 4 pi R^3 beta H0 (capped at
//         M_s V when the iron saturates) of the largest radius, d = 2 R_max + 2 R_min apart,
//         each moment enhanced 1.5 times by its chain;
//   hold  F = 4/3 E* sqrt(R*) (0.3 R_min)^(3/2): the finest grain's contact with the large one at
//         0.3 of its radius, half the overlap guard;
//   factor X = max(1, pull / hold): the modulus is multiplied by X, and every grain finer than
//         D = d_min sqrt(X) is given the Stokes and Rayleigh times of a grain of diameter D (its
//         mass times (D / d)^2, a grain batch's mass_scaling), so that no grain's Rayleigh time,
//         R sqrt(rho / G), falls below the finest class's at the scene's modulus: the step is
//         the one the scene has with a grain of that class in the cell.
// Mass scaling is valid while the heavier grains' inertia stays negligible: a D grain's Stokes
// number at the fastest rate, tau gamma_dot with tau = m / (6 pi mu R), is reported.
#include <nlohmann/json.hpp>

namespace mrjam {

struct PullHoldingInput {
    double min_diameter = 0, max_diameter = 0;  // m, of the size distribution
    double flux_density = 0;                    // T, applied
    double relative_permeability = 1;
    double saturation_magnetisation = 0;  // A/m; infinity when moments are not capped
    double youngs_modulus = 0;            // Pa, as the scene gives it
    double poisson_ratio = 0;
};

struct PullHolding {
    double pull = 0;           // N, the largest pair's pull through the finest grain
    double hold = 0;           // N, what the finest grain's contact bears at 0.3 of its radius
    double factor = 1;         // >= 1: the modulus is multiplied by it
    double heavier_below = 0;  // m: finer grains get this diameter's Stokes time (0: none)
};

inline constexpr double kPullHoldingOverlap = 0.3;  // of the finest radius
inline constexpr double kChainMomentEnhancement = 1.5;

PullHolding pull_holding(const PullHoldingInput& in);

// The Stokes number tau gamma_dot of a grain of this diameter and density in a carrier of this
// viscosity sheared at `rate`, tau = m / (6 pi mu R) = rho d^2 / (18 mu); 0 without a carrier.
double stokes_number(double diameter, double density, double viscosity, double rate);

nlohmann::json describe(const PullHolding& p);

}  // namespace mrjam
