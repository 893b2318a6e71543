#pragma once
// The scene of `mrjam asteroid avalanche` (docs/asteroid.md, "avalanche"): section 4.4 of the
// source. A column of grains held by a gate in a cell periodic across its width settles in a
// weak uniform gravity, is magnetised by a field along gravity, and runs out when the gate is
// taken away; the heap's angle of repose is what Table 4.5 compares.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/grain_material.hpp"
#include "scene/output_block.hpp"

namespace mrjam {

struct AvalancheSpec {
    nlohmann::json resolved;
    std::string description;
    std::uint64_t seed = 1;
    double diameter = 0;  // m, one size
    // Material (Table 4.5's grains for the examples' values).
    GrainMaterial material;              // Table 4.5's grains by default (avalanche_spec.cpp)
    double cohesion_energy_density = 0;  // SJKR, J/m3
    double relative_permeability = 1000, saturation_magnetisation = 1.7e6;
    // The cell, in grain diameters: x the run-out, y periodic, z up.
    double length = 0, width = 0, height = 0, gate = 0, fill_height = 0;
    double fill_fraction = 0.5;  // of the random packing behind the gate before it settles
    double gravity = 0;          // m/s2, along -z
    double field = 0;            // T, along z (parallel to gravity, as the source)
    bool mutual_dipoles = true;  // the neighbours' fields in each moment (lagged), or the applied field only
    double settle_time = 0, magnetise_time = 0, runout_time = 0;  // s; the run-out ends at rest sooner
    double rest_speed = 0;                                        // m/s, rms speed that counts as at rest
    double timestep_safety = 0.1;
    OutputBlock output;  // output.directory: where the run writes
};

// Reads and checks the scene at a tier (the cell's defaults: quick 100 x 8 x 30 diameters with a
// column 50 wide and 12 high behind the gate, standard and paper 150 x 16 x 45 with 75 x 18);
// throws SceneError naming the key.
AvalancheSpec read_avalanche_spec(const nlohmann::json& scene, const std::string& fidelity);

}  // namespace mrjam
