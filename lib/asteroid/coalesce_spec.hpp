#pragma once
// The scene of `mrjam asteroid coalesce` (docs/asteroid.md, "coalesce"): a spherical cloud of
// equal rubble grains on a cubic lattice (section 4.2 of the source), with thermal speeds, a
// spin about z, an optional central seed grain, permanent magnetisation, self-gravity and an
// escape radius. Read and checked before anything is built.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "asteroid/grain_material.hpp"
#include "scene/output_block.hpp"

namespace mrjam {

// A grain's material (Table 4.1 of the source for the defaults the examples state).
struct RubbleMaterial : GrainMaterial {
    double surface_energy = 0;  // DMT gamma, J/m2
    double magnetisation = 0;   // A/m, permanent, in a random direction per grain
};

struct CoalesceSpec {
    nlohmann::json resolved;  // the scene with every default filled in (echoed into the report)
    std::string description;
    std::uint64_t seed = 1;
    double diameter = 0;  // m, every cloud grain
    RubbleMaterial material;
    long count = 0;                        // cloud grains (the seed grain not counted)
    double lattice_spacing = 0;            // m
    double thermal_speed = 0;              // m/s, standard deviation of each velocity component
    bool thermal_from_temperature = true;  // thermal_speed derived from the source's temperature rule
    double spin = 0;                       // rad/s about z through the centre of mass
    double seed_diameter = 0;              // m; 0: no seed grain
    double seed_magnetisation = 0;         // A/m
    double escape_radius = 3;              // in cloud radii: grains beyond it are removed and counted
    bool allow_unbound = false;
    bool direct_gravity = false;  // direct summation (the reference) instead of the tree
    double opening_angle = 0.5;
    int gravity_interval = 10;     // steps the self-gravity is held
    double magnetic_cutoff = 3;    // in pair diameters (the source's three diameters)
    int magnetic_interval = 1;     // steps the dipole forces are held
    double duration = 0;           // s
    double sample_every = 0;       // s between body diagnostics
    double timestep_safety = 0.1;  // automatic step as a share of the critical time
    OutputBlock output;            // output.directory: where the run writes (set to the mode's default before reading)
};

// The source's "temperature of 8e20 times the cube of the particle diameter" read as k_B T with T
// in kelvin and d in metres: sigma_v = sqrt(k_B 8e20 d^3 / m), independent of d for one density.
double thermal_speed_from_temperature(double density);

class SceneNode;

// The blocks a rubble-pile scene shares (description, seed, grains, cloud, self_gravity, magnetic,
// output; `s.output.directory` is the default directory), read from `root` without finishing
// it, so a mode can read its own blocks after.
void read_rubble_blocks(SceneNode& root, CoalesceSpec& s, const std::string& fidelity);
// The run block: `duration` (required unless the mode computes it and passes it in),
// `sample_every`, `timestep_safety`.
void read_run_block(SceneNode& root, CoalesceSpec& s, std::optional<double> duration);

// Reads and checks the scene at a tier (quick: 4,000 grains; standard and paper: the source's
// 32,662); throws SceneError naming the key.
CoalesceSpec read_coalesce_spec(const nlohmann::json& scene, const std::string& fidelity);

}  // namespace mrjam
