#include "shear/pull_holding.hpp"

#include <algorithm>
#include <cmath>

namespace mrjam {

PullHolding pull_holding(const PullHoldingInput& in) {
    constexpr double mu0 = 4e-7 * M_PI;
    const double r_small = 0.5 * in.min_diameter, r_large = 0.5 * in.max_diameter;
    const double volume = 4.0 / 3.0 * M_PI * r_large * r_large * r_large;
    const double beta = (in.relative_permeability - 1) / (in.relative_permeability + 2);
    // An isolated sphere's induced moment, 3 beta V H0 = 4 pi R^3 beta H0, at most M_s V.
    const double moment = std::min(3 * beta * volume * in.flux_density / mu0, in.saturation_magnetisation * volume);
    const double gap = 2 * r_large + 2 * r_small;
    PullHolding out;
    out.pull =
        kChainMomentEnhancement * kChainMomentEnhancement * 6 * mu0 * moment * moment / (4 * M_PI * std::pow(gap, 4));
    const double ystar = in.youngs_modulus / (2 * (1 - in.poisson_ratio * in.poisson_ratio));
    const double rstar = r_small * r_large / (r_small + r_large);
    out.hold = 4.0 / 3.0 * ystar * std::sqrt(rstar) * std::pow(kPullHoldingOverlap * r_small, 1.5);
    out.factor = std::max(1.0, out.pull / out.hold);
    if (out.factor > 1) out.heavier_below = in.min_diameter * std::sqrt(out.factor);
    return out;
}

double stokes_number(double diameter, double density, double viscosity, double rate) {
    return viscosity > 0 ? density * diameter * diameter / (18 * viscosity) * rate : 0.0;
}

nlohmann::json describe(const PullHolding& p) {
    return {{"rule",
             "modulus x factor: the finest grain's contact holds the largest pair's pull at 0.3 of its radius; "
             "finer grains than heavier_below get that diameter's Stokes time"},
            {"pull_N", p.pull},
            {"hold_at_scene_modulus_N", p.hold},
            {"factor", p.factor},
            {"heavier_below_diameter_m", p.heavier_below}};
}

}  // namespace mrjam
