#pragma once
// `mrjam asteroid scaling`: every force of the scene as a law of the radius, where each pair of
// them crosses, the band of radii where magnetism is the strongest, and section 4.5's claims
// evaluated with their numbers (docs/asteroid.md).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "asteroid/scaling_spec.hpp"

namespace mrjam {

// The band of radii where a magnetic law exceeds cohesion, the surface weight and self-gravity:
// above its crossing with cohesion (R^1 < R^2) and below its crossings with the gravities (R^3,
// R^4). Empty (nullopt) when the lower end is not below the upper.
struct DominanceBand {
    double from = 0, to = 0;
};
std::optional<DominanceBand> magnetic_dominance(const PowerLaw& magnetic, const PowerLaw& cohesion,
                                                const PowerLaw& surface_gravity, const PowerLaw& self_gravity);

// One claim of section 4.5: its words, the conditions it was evaluated at, the figures, the
// tolerance taken for its "about", and the verdict.
struct ScalingClaim {
    std::string claim, conditions, tolerance;
    nlohmann::json figures;
    bool holds = false;
};
std::vector<ScalingClaim> evaluate_section_4_5_claims(const ScalingSpec& spec);

// The report's "results": laws, crossovers, bands, the force table on the radius grid, claims.
nlohmann::json scaling_results(const ScalingSpec& spec);

// Fig. 4.15 for the scene: every force against the radius on log-log axes, as SVG.
void write_scaling_plot(const ScalingSpec& spec, const std::string& path);

}  // namespace mrjam
