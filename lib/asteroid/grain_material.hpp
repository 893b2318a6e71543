#pragma once
// The rubble grains' contact material, read and written once for the asteroid modes: each mode
// keeps its own defaults (the avalanche's Table 4.5 grains, the cloud's section 4.2 ones) and
// adds what only it has (cohesion and permeability, or surface energy and remanence).
#include <nlohmann/json.hpp>

namespace mrjam {

class SceneNode;

struct GrainMaterial {
    double density = 0;         // kg/m3
    double youngs_modulus = 0;  // Pa
    double poisson_ratio = 0.3;
    double restitution = 0.1;
    double friction = 0.4;
    double rolling_friction = 0;   // SDS mu_roll
    double rolling_stiffness = 0;  // SDS k_roll, N/m
    double rolling_viscous = 0;    // SDS gamma_roll, N s/m
};

// A mode's defaults for the keys a scene may leave out.
struct GrainMaterialDefaults {
    double poisson_ratio, restitution, friction;
};

// Reads density and Young's modulus (required), the elastic and frictional keys and the SDS
// rolling resistance (both its friction and its stiffness, or neither) from a scene's
// grains/material block; the caller reads its own keys and finishes the node.
GrainMaterial read_grain_material(SceneNode& node, const GrainMaterialDefaults& defaults);

// The engine scene's material entry for these keys, under `name`; the caller adds its own.
nlohmann::json grain_material_json(const char* name, const GrainMaterial& m);

}  // namespace mrjam
