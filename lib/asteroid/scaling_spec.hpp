#pragma once
// The scene of `mrjam asteroid scaling` (docs/asteroid.md): the grains' material, a range of
// radii, and lists of applied fields or magnetisations, surface gravities and cleanliness
// factors, read and checked before anything is computed.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "asteroid/force_scaling.hpp"

namespace mrjam {

struct ScalingSpec {
    nlohmann::json resolved;  // the scene with every default filled in (echoed into the report)
    std::string description;
    double density = 0;  // kg/m3
    SoftMagneticGrain grain;
    double radius_min = 0, radius_max = 0;  // m
    int points_per_decade = 10;
    std::vector<double> flux_densities;                                   // T, applied to soft (induced) grains
    std::vector<double> magnetisations;                                   // A/m, of permanently magnetised grains
    double exact_gap = 0.01;                                              // surface gap of the exact pair, in radii
    InducedPairModel dominance_model = InducedPairModel::mutual_dipoles;  // decides the crossovers' bands
    std::vector<double> surface_gravities;                                // m/s2
    std::vector<double> cleanliness;                                      // S of Eq. 4.15
    SelfGravityFormula self_gravity = SelfGravityFormula::two_spheres;

    std::vector<double> radii() const;  // the grid, points_per_decade to the decade, ends included
};

// Reads and checks the scene; throws SceneError naming the key.
ScalingSpec read_scaling_spec(const nlohmann::json& scene);

}  // namespace mrjam
