#include "asteroid/scaling_study.hpp"

#include <algorithm>
#include <cmath>

#include "core/format.hpp"

namespace mrjam {

namespace {

using json = nlohmann::json;

json law_json(const PowerLaw& law) { return {{"coefficient_N", law.coefficient}, {"exponent", law.exponent}}; }

json radius_or_null(double r) { return std::isfinite(r) ? json(r) : json(nullptr); }

// A magnetic source of the scene: an applied field on soft grains (one law per model) or a
// permanent magnetisation (point dipoles).
struct MagneticSource {
    json label;
    PowerLaw deciding;  // the law the dominance bands use
    json laws;
};

std::vector<MagneticSource> magnetic_sources(const ScalingSpec& spec) {
    std::vector<MagneticSource> out;
    for (double b : spec.flux_densities) {
        MagneticSource src;
        src.label = {{"flux_density_T", b}, {"equivalent_magnetisation_A_m", equivalent_magnetisation(spec.grain, b)}};
        for (InducedPairModel m :
             {InducedPairModel::fixed_dipoles, InducedPairModel::mutual_dipoles, InducedPairModel::exact_pair}) {
            const PowerLaw law = induced_pair_force(spec.grain, b, m, spec.exact_gap);
            const PairMagnetisation pm = induced_pair_magnetisation(spec.grain, b, m);
            json j = law_json(law);
            j["magnetisation_A_m"] = pm.magnetisation;
            j["saturated"] = pm.saturated;
            if (m == InducedPairModel::exact_pair) {
                j["surface_gap_radii"] = spec.exact_gap;
                if (pm.saturated) j["note"] = "the linear solution exceeds M_s: not valid at this field";
            }
            src.laws[model_name(m)] = j;
            if (m == spec.dominance_model) src.deciding = law;
        }
        out.push_back(src);
    }
    for (double m : spec.magnetisations) {
        MagneticSource src;
        src.label = {{"magnetisation_A_m", m}};
        src.deciding = dipole_pair_force(m);
        src.laws["permanent_dipoles"] = law_json(src.deciding);
        out.push_back(src);
    }
    return out;
}

json crossovers(const ScalingSpec& spec, const std::vector<MagneticSource>& sources) {
    const PowerLaw self = self_gravity_force(spec.density, spec.self_gravity);
    json rows = json::array();
    for (const MagneticSource& src : sources)
        for (double g : spec.surface_gravities)
            for (double S : spec.cleanliness) {
                const PowerLaw surface = surface_gravity_force(spec.density, g), coh = cohesion_force(S);
                json row = src.label;
                row["surface_gravity_m_s2"] = g;
                row["cleanliness"] = S;
                row["magnetic_equals_cohesion_m"] = radius_or_null(crossover_radius(src.deciding, coh));
                row["magnetic_equals_surface_gravity_m"] = radius_or_null(crossover_radius(src.deciding, surface));
                row["magnetic_equals_self_gravity_m"] = radius_or_null(crossover_radius(src.deciding, self));
                row["cohesion_equals_surface_gravity_m"] = radius_or_null(crossover_radius(coh, surface));
                row["cohesion_equals_self_gravity_m"] = radius_or_null(crossover_radius(coh, self));
                const auto band = magnetic_dominance(src.deciding, coh, surface, self);
                row["magnetism_dominates"] = band ? json{{"from_m", band->from}, {"to_m", band->to}} : json(nullptr);
                rows.push_back(row);
            }
    return rows;
}

json force_table(const ScalingSpec& spec, const std::vector<MagneticSource>& sources) {
    const std::vector<double> radii = spec.radii();
    auto column = [&](const PowerLaw& law) {
        std::vector<double> f;
        for (double r : radii) f.push_back(law.at(r));
        return f;
    };
    json t = {{"radius_m", radii}, {"forces_N", json::object()}};
    json& f = t["forces_N"];
    for (double g : spec.surface_gravities)
        f["surface_gravity " + format_number(g) + " m/s2"] = column(surface_gravity_force(spec.density, g));
    f["self_gravity"] = column(self_gravity_force(spec.density, spec.self_gravity));
    for (double S : spec.cleanliness) f["cohesion S=" + format_number(S)] = column(cohesion_force(S));
    for (const MagneticSource& src : sources)
        f[src.label.contains("flux_density_T")
              ? "magnetic " + format_number(src.label["flux_density_T"].get<double>()) + " T"
              : "magnetic " + format_number(src.label["magnetisation_A_m"].get<double>()) + " A/m"] =
            column(src.deciding);
    return t;
}

}  // namespace

std::optional<DominanceBand> magnetic_dominance(const PowerLaw& magnetic, const PowerLaw& cohesion,
                                                const PowerLaw& surface_gravity, const PowerLaw& self_gravity) {
    const double from = crossover_radius(magnetic, cohesion);
    const double to = std::min(crossover_radius(magnetic, surface_gravity), crossover_radius(magnetic, self_gravity));
    if (!(from < to)) return std::nullopt;
    return DominanceBand{from, to};
}

json scaling_results(const ScalingSpec& spec) {
    const std::vector<MagneticSource> sources = magnetic_sources(spec);
    json laws = {{"self_gravity", law_json(self_gravity_force(spec.density, spec.self_gravity))},
                 {"self_gravity_formula", formula_name(spec.self_gravity)},
                 {"surface_gravity", json::array()},
                 {"cohesion", json::array()},
                 {"magnetic", json::array()}};
    laws["self_gravity"]["other_formula"] = law_json(self_gravity_force(
        spec.density, spec.self_gravity == SelfGravityFormula::two_spheres ? SelfGravityFormula::printed
                                                                           : SelfGravityFormula::two_spheres));
    for (double g : spec.surface_gravities) {
        json j = law_json(surface_gravity_force(spec.density, g));
        j["surface_gravity_m_s2"] = g;
        laws["surface_gravity"].push_back(j);
    }
    for (double S : spec.cleanliness) {
        json j = law_json(cohesion_force(S));
        j["cleanliness"] = S;
        laws["cohesion"].push_back(j);
    }
    for (const MagneticSource& src : sources) {
        json j = src.label;
        j["models"] = src.laws;
        laws["magnetic"].push_back(j);
    }
    json claims = json::array();
    for (const ScalingClaim& c : evaluate_section_4_5_claims(spec))
        claims.push_back({{"claim", c.claim},
                          {"conditions", c.conditions},
                          {"tolerance", c.tolerance},
                          {"figures", c.figures},
                          {"holds", c.holds}});
    return {{"laws", laws},
            {"dominance_model", model_name(spec.dominance_model)},
            {"crossovers", crossovers(spec, sources)},
            {"table", force_table(spec, sources)},
            {"claims", claims}};
}

}  // namespace mrjam
