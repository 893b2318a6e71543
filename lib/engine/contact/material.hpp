#pragma once
// Grain and wall materials, and the per-pair coefficients the contact laws use. Pair values are
// computed once per material pair (a small table) so the hot loop only indexes.
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct Material {
    std::string name;
    double density = 7800;        // kg/m3
    double youngs_modulus = 1e9;  // Pa
    double poisson_ratio = 0.3;
    double restitution = 0.5;              // normal coefficient of restitution, (0, 1]
    double friction = 0.5;                 // Coulomb sliding friction
    double rolling_friction = 0.0;         // EPSD mu_r or SDS mu_roll
    double rolling_damping = 0.0;          // EPSD damping ratio eta_r
    double rolling_stiffness = 0.0;        // SDS k_roll, N/m
    double rolling_viscous = 0.0;          // SDS gamma_roll, N s/m
    double cohesion_energy_density = 0.0;  // SJKR k_c, J/m3
    double surface_energy = 0.0;           // DMT gamma, J/m2
    // Magnetic (used only when the scene has a "magnetic" block). Iron-like defaults.
    double relative_permeability = 1000;      // mu_r of the grain material
    double saturation_magnetisation = 1.7e6;  // A/m, iron
    double remanent_magnetisation = 0;        // A/m, a permanently magnetised grain
    bool random_remanence_direction = true;   // else along remanence_direction
    Vec3 remanence_direction{0, 0, 1};

    double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
};

// Coefficients of one material pair.
struct PairCoefficients {
    double effective_youngs = 0;           // Y*: 1/Y* = (1-nu_i^2)/Y_i + (1-nu_j^2)/Y_j
    double effective_shear = 0;            // G*: 1/G* = 2(2-nu_i)(1+nu_i)/Y_i + ... (Mindlin)
    double tangential_to_normal_root = 0;  // sqrt(k_t / S_n) = sqrt(4 G* / Y*)
    double damping_beta = 0;               // |beta| in gamma = 2 sqrt(5/6) beta sqrt(S m*), from e
    double friction = 0;
    double rolling_friction = 0;
    double rolling_damping = 0;
    double rolling_stiffness = 0;
    double rolling_viscous = 0;
    double cohesion_energy_density = 0;
    double surface_energy = 0;
};

class PairTable {
public:
    PairTable() = default;
    explicit PairTable(const std::vector<Material>& materials);

    const PairCoefficients& operator()(std::uint16_t a, std::uint16_t b) const { return table_[a * n_ + b]; }
    std::size_t size() const { return n_; }

    // Sets one pair's coefficients in place of the mixing rule's means (both orders), as
    // LIGGGHTS's per-pair matrices would: a frictionless, cohesionless symmetry plane, for example.
    void set_pair(std::uint16_t a, std::uint16_t b, const PairCoefficients& c);

    // Coefficients of a pair of materials (also used for a grain against a wall).
    static PairCoefficients combine(const Material& a, const Material& b);

private:
    std::size_t n_ = 0;
    std::vector<PairCoefficients> table_;
};

}  // namespace mrjam
