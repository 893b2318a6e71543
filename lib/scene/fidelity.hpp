#pragma once
// Fidelity tiers: named sets of defaults that trade speed for accuracy. A tier only changes
// defaults; any setting written in the scene file wins. The cost and error of each tier's
// settings are measured and published (docs/magnetic_forces.md, docs/accuracy.md).
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "magnetic/magnetic_model.hpp"

namespace mrjam {

struct FidelityTier {
    std::string name;
    double timestep_safety;        // automatic step as a fraction of the critical time
    MutualPolicy magnetic_policy;  // mutual-dipole policy
    double magnetic_cutoff_diameters;
};

// quick, standard (the default) and paper. Throws std::invalid_argument naming the valid tiers.
const FidelityTier& fidelity_tier(const std::string& name);
std::vector<std::string> fidelity_tier_names();
nlohmann::json describe(const FidelityTier& tier);

}  // namespace mrjam
