#include "scene/fidelity.hpp"

#include "scene/tier.hpp"

namespace mrjam {
namespace {

// Chosen from measured tables. Magnetic (docs/magnetic_forces.md, `mrjam-bench magnetic-accuracy`,
// 8,116 chained grains, errors of the magnetic stress sigma_zz against converged dipoles at 8
// diameters): lagged dipoles are within 0.02% of converged ones while converging costs ~27 field
// passes per step, so every tier is lagged; the cutoff sets the error: 2 d -0.55%, 3 d -0.14%,
// 5 d +0.014%, at about 17, 60 and 280 neighbours per grain. Time step (docs/accuracy.md): the
// restitution error is proportional to the step; the paper tier halves the standard step.
const PerTier<FidelityTier> kTable = {
    {"quick", 0.2, MutualPolicy::lagged, 2.0},
    {"standard", 0.1, MutualPolicy::lagged, 3.0},
    {"paper", 0.05, MutualPolicy::lagged, 5.0},
};

}  // namespace

const FidelityTier& fidelity_tier(const std::string& name) { return kTable[tier_from_name(name)]; }

std::vector<std::string> fidelity_tier_names() { return tier_names(); }

nlohmann::json describe(const FidelityTier& t) {
    return {{"tier", t.name},
            {"timestep_safety", t.timestep_safety},
            {"magnetic_mutual", policy_name(t.magnetic_policy)},
            {"magnetic_cutoff_diameters", t.magnetic_cutoff_diameters}};
}

}  // namespace mrjam
