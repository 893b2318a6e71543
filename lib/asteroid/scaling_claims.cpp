// Section 4.5's claims about which force dominates, each evaluated at the conditions it names
// (or, where it names none, the figure's: the five background fields of Fig. 4.15) with the
// scene's grain material and magnetic model. "About" is taken as within half a decade: the
// claims are read off log-log plots spanning a dozen decades.
#include <algorithm>
#include <cmath>

#include "asteroid/scaling_study.hpp"
#include "core/format.hpp"

namespace mrjam {

namespace {

using json = nlohmann::json;

const double kSeedFields[] = {5e-7, 5e-6, 5e-5, 5e-4, 5e-3};  // T, Fig. 4.15

bool within_half_decade(double value, double target) {
    return value > 0 && std::abs(std::log10(value / target)) <= 0.5;
}

PowerLaw magnetic_law(const ScalingSpec& spec, double flux_density) {
    return induced_pair_force(spec.grain, flux_density, spec.dominance_model, spec.exact_gap);
}

std::optional<DominanceBand> band_at(const ScalingSpec& spec, double b, double g, double S) {
    return magnetic_dominance(magnetic_law(spec, b), cohesion_force(S), surface_gravity_force(spec.density, g),
                              self_gravity_force(spec.density, spec.self_gravity));
}

json band_json(const std::optional<DominanceBand>& band) {
    return band ? json{{"from_m", band->from}, {"to_m", band->to}} : json(nullptr);
}

ScalingClaim middle_sizes(const ScalingSpec& spec) {
    ScalingClaim c{"dipole forces dominate over gravity and cohesion at middle sizes, about 1e-4 m to 1 m",
                   "the union over Fig. 4.15's fields (5e-7 to 5e-3 T) of the radii where magnetism beats "
                   "cohesion (S = 0.1), the weight in 1e-4 m/s2 and self-gravity",
                   "each end within half a decade of 1e-4 m and 1 m", json::object()};
    double from = INFINITY, to = 0;
    c.figures["bands"] = json::array();
    for (double b : kSeedFields) {
        const auto band = band_at(spec, b, 1e-4, 0.1);
        c.figures["bands"].push_back({{"flux_density_T", b}, {"band", band_json(band)}});
        if (band) {
            from = std::min(from, band->from);
            to = std::max(to, band->to);
        }
    }
    const bool any = to > 0;
    c.figures["union"] = any ? json{{"from_m", from}, {"to_m", to}} : json(nullptr);
    c.holds = any && within_half_decade(from, 1e-4) && within_half_decade(to, 1.0);
    return c;
}

ScalingClaim one_field(const ScalingSpec& spec) {
    ScalingClaim c{
        "in a 5e-4 T field, S = 0.1, surface gravity 1e-4 m/s2: magnetism dominates for sizes about "
        "1e-4 m to 1e-1 m",
        "5e-4 T, S = 0.1, 1e-4 m/s2", "each end within half a decade of 1e-4 m and 0.1 m", json::object()};
    const auto band = band_at(spec, 5e-4, 1e-4, 0.1);
    c.figures["band"] = band_json(band);
    c.holds = band && within_half_decade(band->from, 1e-4) && within_half_decade(band->to, 0.1);
    return c;
}

ScalingClaim self_gravity_sizes(const ScalingSpec& spec) {
    ScalingClaim c{"self gravity dominates only at tens to hundreds of metres",
                   std::string("the radius above which self-gravity (") + formula_name(spec.self_gravity) +
                       ") beats both cohesion and magnetism, for each of Fig. 4.15's fields and S = 1 and 0.1",
                   "every such radius between 10 m and 1000 m", json::array()};
    const PowerLaw self = self_gravity_force(spec.density, spec.self_gravity);
    c.holds = true;
    for (double b : kSeedFields)
        for (double S : {1.0, 0.1}) {
            const double r =
                std::max(crossover_radius(self, cohesion_force(S)), crossover_radius(self, magnetic_law(spec, b)));
            c.figures.push_back({{"flux_density_T", b}, {"cleanliness", S}, {"radius_m", r}});
            c.holds = c.holds && r >= 10 && r <= 1000;
        }
    return c;
}

ScalingClaim avalanche_grains(const ScalingSpec& spec) {
    ScalingClaim c{
        "0.144 m/s2 and 5 mT: magnetism beats gravity by about 10x for 5 mm iron grains, comparable at "
        "1 cm, gravity slightly stronger at 5 cm",
        "magnetic force over the grain's weight at 0.144 m/s2 and 5e-3 T, for diameters 5 mm, 1 cm "
        "and 5 cm",
        "5 mm: within half a decade of 10; 1 cm: between 0.5 and 2; 5 cm: between 0.5 and 1", json::array()};
    const PowerLaw mag = magnetic_law(spec, 5e-3), weight = surface_gravity_force(spec.density, 0.144);
    double ratio[3];
    const double diameters[3] = {5e-3, 1e-2, 5e-2};
    for (int k = 0; k < 3; ++k) {
        ratio[k] = mag.at(diameters[k] / 2) / weight.at(diameters[k] / 2);
        c.figures.push_back({{"diameter_m", diameters[k]}, {"magnetic_over_weight", ratio[k]}});
    }
    c.holds = within_half_decade(ratio[0], 10) && ratio[1] >= 0.5 && ratio[1] <= 2 && ratio[2] >= 0.5 && ratio[2] < 1;
    return c;
}

}  // namespace

std::vector<ScalingClaim> evaluate_section_4_5_claims(const ScalingSpec& spec) {
    return {middle_sizes(spec), one_field(spec), self_gravity_sizes(spec), avalanche_grains(spec)};
}

}  // namespace mrjam
