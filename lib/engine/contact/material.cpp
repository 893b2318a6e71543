#include "contact/material.hpp"

#include <cmath>

#include "contact/restitution.hpp"

namespace mrjam {

PairCoefficients PairTable::combine(const Material& a, const Material& b) {
    PairCoefficients c;
    c.effective_youngs = 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
    c.effective_shear = 1.0 / (2 * (2 - a.poisson_ratio) * (1 + a.poisson_ratio) / a.youngs_modulus +
                               2 * (2 - b.poisson_ratio) * (1 + b.poisson_ratio) / b.youngs_modulus);
    c.tangential_to_normal_root = std::sqrt(4.0 * c.effective_shear / c.effective_youngs);
    // Mixed pairs take the mean of the two materials' coefficients (LIGGGHTS would need a full
    // matrix; scenes here mix at most a grain and a wall material).
    const double e = 0.5 * (a.restitution + b.restitution);
    c.damping_beta = damping_beta_for_restitution(e);
    c.friction = 0.5 * (a.friction + b.friction);
    c.rolling_friction = 0.5 * (a.rolling_friction + b.rolling_friction);
    c.rolling_damping = 0.5 * (a.rolling_damping + b.rolling_damping);
    c.rolling_stiffness = 0.5 * (a.rolling_stiffness + b.rolling_stiffness);
    c.rolling_viscous = 0.5 * (a.rolling_viscous + b.rolling_viscous);
    c.cohesion_energy_density = 0.5 * (a.cohesion_energy_density + b.cohesion_energy_density);
    c.surface_energy = 0.5 * (a.surface_energy + b.surface_energy);
    return c;
}

PairTable::PairTable(const std::vector<Material>& materials) : n_(materials.size()), table_(n_ * n_) {
    for (std::size_t a = 0; a < n_; ++a)
        for (std::size_t b = 0; b < n_; ++b) table_[a * n_ + b] = combine(materials[a], materials[b]);
}

void PairTable::set_pair(std::uint16_t a, std::uint16_t b, const PairCoefficients& c) {
    for (std::size_t k : {a * n_ + b, b * n_ + a}) table_[k] = c;
}

}  // namespace mrjam
