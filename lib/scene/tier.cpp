#include "scene/tier.hpp"

#include <stdexcept>

namespace mrjam {

const char* tier_name(Tier tier) {
    switch (tier) {
        case Tier::quick:
            return "quick";
        case Tier::standard:
            return "standard";
        case Tier::paper:
            return "paper";
    }
    return "standard";
}

std::vector<std::string> tier_names() {
    std::vector<std::string> names;
    for (Tier t : kTiers) names.emplace_back(tier_name(t));
    return names;
}

Tier tier_from_name(const std::string& name) {
    for (Tier t : kTiers)
        if (name == tier_name(t)) return t;
    throw std::invalid_argument("unknown fidelity tier '" + name + "'; expected one of quick, standard, paper");
}

}  // namespace mrjam
