#include "asteroid/force_scaling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "magnetic/magnetic_model.hpp"
#include "magnetic/sphere_pair_exact.hpp"

namespace mrjam {

double PowerLaw::at(double radius) const { return coefficient * std::pow(radius, exponent); }

PowerLaw surface_gravity_force(double density, double surface_gravity) {
    return {density * 4.0 / 3.0 * M_PI * surface_gravity, 3};
}

PowerLaw self_gravity_force(double density, SelfGravityFormula formula) {
    const double k = formula == SelfGravityFormula::two_spheres ? 4.0 / 9.0 : 1.0 / 9.0;
    return {kGravitationalConstant * density * density * k * M_PI * M_PI, 4};
}

const char* formula_name(SelfGravityFormula formula) {
    return formula == SelfGravityFormula::two_spheres ? "two_spheres" : "printed";
}

PowerLaw cohesion_force(double cleanliness) { return {3.6e-2 * cleanliness * cleanliness, 1}; }

const char* model_name(InducedPairModel model) {
    switch (model) {
        case InducedPairModel::fixed_dipoles:
            return "fixed_dipoles";
        case InducedPairModel::mutual_dipoles:
            return "mutual_dipoles";
        case InducedPairModel::exact_pair:
            return "exact_pair";
    }
    return "?";
}

double equivalent_magnetisation(const SoftMagneticGrain& grain, double flux_density) {
    return 3.0 * grain.beta() * flux_density / kMu0;
}

PairMagnetisation induced_pair_magnetisation(const SoftMagneticGrain& grain, double flux_density,
                                             InducedPairModel model) {
    double m = equivalent_magnetisation(grain, flux_density);
    // The partner's dipole field at the grain's centre, on the axis at 2R: m / (16 pi R^3), i.e.
    // M / 12, which the grain answers with 3 beta of it; iterated to convergence, 1 / (1 - beta/4).
    if (model == InducedPairModel::mutual_dipoles) m /= 1.0 - grain.beta() / 4.0;
    if (model != InducedPairModel::exact_pair && m > grain.saturation_magnetisation)
        return {grain.saturation_magnetisation, true};
    return {m, model == InducedPairModel::exact_pair && m > grain.saturation_magnetisation};
}

PowerLaw dipole_pair_force(double magnetisation) { return {kMu0 * M_PI * magnetisation * magnetisation / 6.0, 2}; }

PowerLaw induced_pair_force(const SoftMagneticGrain& grain, double flux_density, InducedPairModel model,
                            double exact_gap) {
    if (model != InducedPairModel::exact_pair)
        return dipole_pair_force(induced_pair_magnetisation(grain, flux_density, model).magnetisation);
    // F = -2 pi mu0 H0^2 R^2 d(alpha)/ds (sphere_pair_exact.hpp), attraction positive here.
    const SpherePairResponse r =
        converged_sphere_pair_response(grain.relative_permeability, 2.0 + exact_gap, PairOrientation::axial);
    const double h0 = flux_density / kMu0;
    return {-2.0 * M_PI * kMu0 * h0 * h0 * r.dpolarisability_ds, 2};
}

double crossover_radius(const PowerLaw& a, const PowerLaw& b) {
    if (a.exponent == b.exponent || !(a.coefficient > 0) || !(b.coefficient > 0))
        return std::numeric_limits<double>::quiet_NaN();
    return std::pow(a.coefficient / b.coefficient, 1.0 / (b.exponent - a.exponent));
}

}  // namespace mrjam
