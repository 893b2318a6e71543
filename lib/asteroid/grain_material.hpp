#pragma once
// The rubble grains' contact material, read and written once for the asteroid modes: each mode
// keeps its own defaults (the avalanche's Table 4.5 grains, the cloud's section 4.2 ones) and
// adds what only it has (cohesion and permeability, or surface energy and remanence).
#include <nlohmann/json.hpp>
#include <string>

namespace mrjam {

class SceneNode;

struct GrainMaterial {
    double density = 0;         // kg/m3
    double youngs_modulus = 0;  // Pa
    double poisson_ratio = 0.3;
    double restitution = 0.1;
    double friction = 0.4;
    // Rolling resistance: "sds" (LAMMPS's spring-dashpot-slider, the source's coalescence and
    // spin-up, section 4.2) or "epsd" (LIGGGHTS's elastic-plastic spring-dashpot, its avalanches,
    // section 4.4.1.1); none while rolling_friction is 0.
    std::string rolling_model = "sds";
    double rolling_friction = 0;   // mu_roll (both models: torque at most mu_roll R* |F_n|)
    double rolling_stiffness = 0;  // SDS k_roll, N/m
    double rolling_viscous = 0;    // SDS gamma_roll, N s/m
    double rolling_damping = 0;    // EPSD viscous damping ratio eta_r (its stiffness is 2.25 k_n mu_r^2 R*^2)

    std::string engine_rolling() const { return rolling_friction > 0 ? rolling_model : "none"; }
};

// A mode's defaults for the keys a scene may leave out.
struct GrainMaterialDefaults {
    double poisson_ratio, restitution, friction;
    const char* rolling_model;  // the source's model for this mode
};

// Reads density and Young's modulus (required), the elastic and frictional keys and the rolling
// resistance (`rolling_model`; SDS: rolling_friction with rolling_stiffness, or neither, and
// rolling_viscous; EPSD: rolling_friction and rolling_damping) from a scene's grains/material
// block; the caller reads its own keys and finishes the node.
GrainMaterial read_grain_material(SceneNode& node, const GrainMaterialDefaults& defaults);

// The engine scene's material entry for these keys, under `name`; the caller adds its own.
nlohmann::json grain_material_json(const char* name, const GrainMaterial& m);

}  // namespace mrjam
