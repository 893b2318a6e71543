#pragma once
// The fidelity tiers every mode names the same way: quick, standard, paper. Each mode keeps its
// own settings per tier in a PerTier table (its cost and error measured in its docs); a tier only
// fills defaults, and what the scene writes wins.
#include <array>
#include <string>
#include <vector>

namespace mrjam {

enum class Tier { quick, standard, paper };

inline constexpr std::array<Tier, 3> kTiers{Tier::quick, Tier::standard, Tier::paper};

const char* tier_name(Tier tier);
// quick, standard, paper: what --fidelity accepts (a mode may add its own, as jam's continuum).
std::vector<std::string> tier_names();
// The tier called `name`; throws std::invalid_argument naming the valid ones.
Tier tier_from_name(const std::string& name);

// A mode's settings for each tier.
template <class Settings>
struct PerTier {
    Settings quick, standard, paper;
    const Settings& operator[](Tier tier) const {
        return tier == Tier::quick ? quick : tier == Tier::paper ? paper : standard;
    }
};

}  // namespace mrjam
