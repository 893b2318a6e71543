#include "shear/shear_tiers.hpp"

#include <stdexcept>

#include "scene/tier.hpp"

namespace mrjam {
namespace {

// Measured in docs/shear.md ("Measured: fidelity tiers"). The source used a 250 um cell (12,000
// grains), E = 1 GPa, dt = 2e-10 s and strains of 0.9 then 0.1 per rate on 18 cores. Here the
// automatic step is 1.29 ns, so no stiffness or density scaling is needed: the tiers shrink the
// cell and the strains. Bundled example, one core: quick 47.7 and 49.3 kPa (seeds 1, 2; 105-110 s),
// standard 42.4 and 55.3 kPa (280-295 s), paper 61.7 kPa (660 s); experiment 44.9 kPa. Seed
// scatter (13 kPa between the two standard seeds) dominates the differences between tiers.
const PerTier<ShearTier> kTable = {
    // name      cell     E x   rho x  strain1 strain/rate  mag      safety  magnetise max
    {"quick", 90e-6, 1.0, 1.0, 0.3, 0.05, 8e-6, 0.1, 40e-6},
    {"standard", 100e-6, 1.0, 1.0, 0.6, 0.1, 8e-6, 0.1, 60e-6},
    {"paper", 125e-6, 1.0, 1.0, 0.9, 0.1, 8e-6, 0.1, 60e-6},
};

}  // namespace

std::vector<std::string> shear_tier_names() { return tier_names(); }

const ShearTier& shear_tier(const std::string& name) { return kTable[tier_from_name(name)]; }

nlohmann::json describe(const ShearTier& t) {
    return {{"tier", t.name},
            {"cell_size_m", t.cell_size},
            {"stiffness_scale", t.stiffness_scale},
            {"density_scale", t.density_scale},
            {"strain_first_rate", t.strain_first},
            {"strain_per_rate", t.strain_per_rate},
            {"magnetic_beyond_contact_m", t.magnetic_beyond_contact},
            {"timestep_safety", t.timestep_safety},
            {"magnetise_max_s", t.magnetise_max}};
}

}  // namespace mrjam
