#pragma once
// The shear-scene file (docs/shear.md): a compact description of a shear-cell experiment - cell,
// suspension, field, rate ladder, measurement window - read and checked before any work, and
// expanded into an engine scene (the same force engine `mrjam run` uses).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/vec3.hpp"
#include "scene/output_block.hpp"
#include "shear/pull_holding.hpp"
#include "shear/shear_tiers.hpp"

namespace mrjam {

struct ShearSpec {
    nlohmann::json input;     // the user's shear scene, as given (kept for checkpoints)
    nlohmann::json resolved;  // with every default filled in (echoed into the report)
    std::string tier;
    std::uint64_t seed = 1;

    Vec3 cell{};  // m; x, y periodic, z between the walls (or periodic, Lees-Edwards)
    // "rafts": frozen layers against two walls carry the shear (the source's cell);
    // "lees_edwards": periodic in z too, the images across z slide at rate * Z (no walls, no rafts).
    bool lees_edwards = false;
    double raft_thickness = 0;  // m, frozen layer at the bottom and at the top (0 with Lees-Edwards)
    double volume_fraction = 0.3;
    bool monolayer = false;       // one layer of grains in the x-z plane (y: thickness, not periodic)
    double area_fraction = 0.5;   // a monolayer's disc area / plane area
    nlohmann::json size_table;    // engine "size" object (number table, or single)
    double largest_diameter = 0;  // of the distribution (for the thickness check)
    nlohmann::json material;      // engine material, scaled
    std::string rolling = "epsd", cohesion = "sjkr";
    double viscosity = 0;
    std::string dissipation = "stokes_drag";  // or "contact_damping"
    double contact_damping = 0;               // N s/m, for contact_damping
    double flux_density = 0;                  // T
    Vec3 field_direction{0, 0, 1};
    nlohmann::json magnetic;              // engine "magnetic" block without the field
    std::string saturation = "material";  // or "none" (linear induced moments, as the source)
    double stiffness_scale = 1, density_scale = 1;
    // scaling/hold_magnetic_pull: the modulus raised until the finest grain's contact holds the
    // largest pair's pull (shear/pull_holding.hpp). Grains finer than `heavier_below` (the rule's
    // diameter or scaling/heavier_below, the larger) get that diameter's Stokes time.
    bool hold_magnetic_pull = false;
    PullHolding pull_holding;          // factor 1 unless asked for and needed
    double heavier_below = 0;          // m; 0: no mass scaling
    double heavier_stokes_number = 0;  // of a heavier_below grain at the fastest rate
    nlohmann::json run;                // engine "run" block (timestep settings)

    // Magnetisation: run until chains settle (see settled() in shear_cell.cpp).
    double magnetise_check_every = 0;             // s between checks
    int magnetise_window = 5;                     // checks in the window
    double magnetise_tolerance = 0.02;            // max relative spread over the window
    double magnetise_min = 0, magnetise_max = 0;  // s
    double field_ramp = 0;                        // s, linear rise of the field from zero at the start

    std::vector<double> rates;        // 1/s, decreasing
    std::vector<double> wall_speeds;  // m/s, each raft moves at +-v
    double strain_first = 0, strain_per_rate = 0;
    long steps_first = 0, steps_per_rate = 0;  // > 0: fixed steps instead of strain
    int samples_per_rate = 40;
    double window_fraction = 0.5;  // last fraction of each rate's samples that is averaged
    int blocks = 5;
    double bingham_min_rate = 200;

    std::vector<double> sweep_fields;  // T; empty: no field sweep
    double sweep_rate = 100;
    double sweep_strain = 0.1;

    // The convergence study (`mrjam shear --converge`, shear/convergence.hpp): the cell's edge
    // (x and z; y too unless a monolayer) at each size, and the seeds run at each.
    std::vector<double> converge_cell_sizes;  // m, increasing
    int converge_seeds = 3;

    nlohmann::json experiment;  // reference data to compare with (echoed, plotted)
    OutputBlock output;         // output.directory: where the study writes

    // The sheared height: between the rafts' inner faces, or the whole period with Lees-Edwards.
    double gap() const { return cell.z - 2 * raft_thickness; }
};

// Reads and checks a shear scene; throws SceneError with the JSON path on bad input.
// `tier` fills defaults; the output directory is relative to the working directory.
ShearSpec read_shear_spec(const nlohmann::json& input, const std::string& tier);

// The engine scene for one cell at flux density `flux_density` (T): grains randomly placed at the
// volume fraction between two walls, the field on, fluid at rest. The protocol is driven by
// ShearCell, so the scene has a single empty stage.
nlohmann::json engine_scene(const ShearSpec& spec, double flux_density);

// The ladder key that sets rate `rate_index`'s length: the first rate's or the later rates', as a
// strain or (by_steps) as a step count.
std::string ladder_length_key(std::size_t rate_index, bool by_steps);

// Maps a path in the engine scene to the shear-scene key a user wrote, so refusals found by the
// engine's reader name the field of the shear scene.
std::string shear_path_of(const std::string& engine_path);

}  // namespace mrjam
