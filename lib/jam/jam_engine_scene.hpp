#pragma once
// The engine scene a jam scene becomes (the generic JSON `mrjam run` reads): the valve's passage
// wall and, for a slab, its two plane faces; the grains filling the passage at the feed fraction;
// the carrier flow's profile; the field; and the protocol's three stages (flow, field on, release).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "jam/jam_scene.hpp"
#include "scene/output_block.hpp"

namespace mrjam {

// What read_jam_scene() read that the JamScene itself does not keep.
struct JamEngineInputs {
    long long seed = 1;
    nlohmann::json material;                 // the grains' engine material, named "iron"
    std::vector<double> diameters, mass;     // the size table, m and relative mass
    std::string profile;                     // fluid/profile (prescribed shape of the carrier flow)
    double viscosity = 0;                    // Pa s
    nlohmann::json field;                    // the engine's magnetic/field block
    double cutoff_diameters = 0;             // the dipoles' cutoff; 0 leaves the engine tier's
    long long magnetic_update_interval = 1;  // steps between magnetic evaluations
    double close_pairs_min_gap = 0;          // the linear close-pair correction's floor in radii; 0: off
    bool close_pairs_saturating = false;     // the saturating close-pair correction
    long long flow_lookup_interval = 1;      // steps between carrier-flow lookups at the grains
    double neighbour_skin = 0;               // Verlet skin, of the mean diameter (0: the engine's)
    bool frictionless_slab = true;           // model/slab_faces
    double heavier_below = 0;                // model/heavier_below, m: finer grains get its Stokes time (0: off)
    OutputBlock output;                      // the scene's output block, passed to the engine
};

nlohmann::json jam_engine_scene(const JamScene& js, const JamEngineInputs& in);

// The engine's stages for the protocol's order: flow (no field, the reference), then closed first
// magnetise (field on, fluid at rest) and pressure (supply on), or open first field_on; then
// release (the hold, if any, and the field off).
nlohmann::json jam_stages(const JamProtocol& p);

}  // namespace mrjam
