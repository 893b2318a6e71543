#pragma once
// Fidelity tiers of the shear-cell mode: the settings that decide cost (cell size, hence grain
// count; stiffness and density scaling, hence the time step; strain per rate; the magnetic
// range). A tier only fills defaults; anything the shear scene writes wins. The measured yield
// stress, error and wall time of each tier are in docs/shear.md.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mrjam {

struct ShearTier {
    std::string name;
    double cell_size;                // m, edge of the cubic cell when the scene gives no size
    double stiffness_scale;          // Young's modulus multiplier (time step grows as scale^-2/5)
    double density_scale;            // grain density multiplier (time step grows as scale^2/5 for Hertz)
    double strain_first;             // shear strain at the first (highest) rate, which builds the structure
    double strain_per_rate;          // at every later rate
    double magnetic_beyond_contact;  // m, magnetic range beyond contact (source: 8 um)
    double timestep_safety;          // fraction of the critical time
    double magnetise_max;            // s, longest magnetisation before shearing anyway
};

// quick, standard (default), paper: the names --fidelity accepts.
std::vector<std::string> shear_tier_names();
// Throws std::invalid_argument naming the valid tiers.
const ShearTier& shear_tier(const std::string& name);
nlohmann::json describe(const ShearTier& tier);

}  // namespace mrjam
