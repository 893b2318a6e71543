#include "scene/fidelity.hpp"

namespace mrjam {
namespace {

// Chosen from measured tables: magnetic policy and cutoff from docs/magnetic_forces.md (error of
// the mean magnetic force and stress against converged dipoles at 8 diameters), the time-step
// safety from docs/accuracy.md (restitution error against steps per contact).
const std::vector<FidelityTier>& tiers() {
    static const std::vector<FidelityTier> all = {
        {"quick", 0.2, MutualPolicy::lagged, 2.0},
        {"standard", 0.1, MutualPolicy::lagged, 3.0},
        {"paper", 0.05, MutualPolicy::converged, 5.0},
    };
    return all;
}

}  // namespace

const FidelityTier& fidelity_tier(const std::string& name) {
    for (const auto& t : tiers())
        if (t.name == name) return t;
    std::string list;
    for (const auto& t : tiers()) list += (list.empty() ? "" : ", ") + t.name;
    throw std::invalid_argument("unknown fidelity tier '" + name + "'; expected one of " + list);
}

std::vector<std::string> fidelity_tier_names() {
    std::vector<std::string> names;
    for (const auto& t : tiers()) names.push_back(t.name);
    return names;
}

nlohmann::json describe(const FidelityTier& t) {
    return {{"tier", t.name},
            {"timestep_safety", t.timestep_safety},
            {"magnetic_mutual", policy_name(t.magnetic_policy)},
            {"magnetic_cutoff_diameters", t.magnetic_cutoff_diameters}};
}

}  // namespace mrjam
