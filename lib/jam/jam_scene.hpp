#pragma once
// A `mrjam jam` scene: a valve, a fluid, a grain mix, a field and a protocol, turned into an
// engine scene (the generic JSON `mrjam run` reads) plus the settings of the jam protocol.
//
// The supply is kept steady by making the modelled stretch of tube periodic along the flow:
// grains that leave downstream re-enter upstream at the same radius, so the throat sees a
// constant feed at the mix's volume fraction without inflow/outflow bookkeeping (the bore far
// from the throat is a straight cylinder, so the seam is invisible to it).
#include <algorithm>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "geometry/valve.hpp"
#include "jam/bingham_plug.hpp"
#include "magnetic/external_field.hpp"

namespace mrjam {

// The order of the experiment. Table 3.2 (section 3.4.1) was measured closed first: the magnet
// switched on with the fluid at rest, then the supply pressure applied, then the magnet off.
// Section 3.3's second experiment (and the source's simulation, section 3.4.4) flows first and
// switches the magnet on in the moving fluid: Figure 3.8's time to arrest.
enum class JamOrder { closed_first, open_first };

struct JamProtocol {
    JamOrder order = JamOrder::closed_first;
    double flow_time = 1e-3;  // s, flow with no field: the no-field reference flux (its second half)
    // closed_first: after the reference the supply is cut and the magnet switched on with the fluid at
    // rest; the grains are magnetised until the structure settles (both the mean contact number and
    // the grains' magnetic energy change by less than settle_tolerance from one settle_window to the
    // next), or for magnetise_time at most; then the supply pressure is applied.
    double magnetise_time = 1e-3;    // s, at most
    double settle_window = 0.1e-3;   // s
    double settle_tolerance = 0.02;  // relative change per window that counts as settled
    // The carrier's viscosity while magnetising at rest, as a share of its own. The experiment's
    // closed period lasted seconds (operated by hand), in which the field's gradient draws the grains
    // towards its maximum at millimetres a second; the model's fraction of a millisecond sees a
    // micron of it. Below 1 the overdamped drawing runs that many times faster towards the same
    // settled end state (docs/notes/jam_experiment.md, "The experiment's closed period").
    double magnetise_viscosity_share = 1.0;
    double max_time = 3e-3;         // s, judged period (pressure on, or field on open first), unless arrest comes first
    double arrest_window = 0.2e-3;  // s, the flux must stay low this long
    double arrest_fraction = 0.05;  // arrest: flux below this fraction of the no-field flux
    double hold_time = 0;      // s, field kept on after an arrest before the release test (does the jam hold, seal?)
    double hold_pressure = 0;  // Pa, supply pressure from the arrest on (the experiment raised it to > 405 kPa); the
                               // scene's supply_pressure unless given
    double hold_pressure_ramp = 0;   // s, reached linearly over this long after the arrest (0: a step)
    double release_time = 1e-3;      // s, field off after an arrest
    double release_fraction = 0.25;  // released: flux back above this fraction of the no-field flux
    long observe_every = 50;         // steps between flux observations
    double steady_window = 0;        // s, "or steady flow" (jam/steady_flow.hpp); 0: run to max_time
    double steady_tolerance = 0.15;  // relative change from one window to the next that counts as steady

    // The longest run before any hold and release: the reference, the magnetisation (closed first)
    // and the judged period.
    double longest_run_before_arrest() const {
        return flow_time + (order == JamOrder::closed_first ? magnetise_time : 0.0) + max_time;
    }

    // The supply pressure `since` seconds after the arrest was called, from the scene's `supply`.
    double supply_after_arrest(double since, double supply) const {
        const double share = hold_pressure_ramp > 0 ? std::clamp(since / hold_pressure_ramp, 0.0, 1.0) : 1.0;
        return supply + share * (hold_pressure - supply);
    }
};

// The carrier flow: the source's prescribed profile, or driven by the supply pressure through
// the grains' Kozeny-Carman resistance on axial cells (lib/jam/axial_resistance.hpp), or driven by
// it and two-way coupled, the fluid finding its way round the grains (lib/jam/coupled_flow.hpp).
struct JamFlow {
    bool pressure_driven = false;  // "pressure" or "coupled"
    bool coupled = false;
    int rings = 0;                   // coupled: rings per slice
    double wall_gap = 0;             // coupled: the mix's volume-weighted mean radius, m
    double supply_pressure = 105e3;  // Pa
    double bore_speed = 0.273;       // m/s, the source's speed in the bore (sets the open flow rate)
    double cell_length = 0;          // m, resistance cells (default: 2 largest-grain diameters)
    double jet_length = 0;           // m, the converging profile's re-opening past the exit (0: other profiles)
};

struct JamScene {
    nlohmann::json engine_scene;  // for build_scene()
    nlohmann::json resolved;      // the jam scene with defaults, for the report
    JamProtocol protocol;
    JamFlow flow;
    ValveGeometry valve;
    double slab_half_thickness = 0;  // 0: the full bore
    double largest_diameter = 0;
    double feed_fraction = 0;  // the mix's volume fraction
    std::string field_type;    // uniform or map
    // The map as read to check that it covers the valve (unscaled), kept for callers that look
    // the field up themselves (the design's values on the axis); null for a uniform field.
    std::shared_ptr<const FieldMap> field_map;
    double peak_flux_density = 0;  // T: the uniform field, or the map's strongest node times its scale
    // T: the applied field above which even a lone grain is saturated (mu0 M_s / (3 beta)), so the
    // grains' moments, and the magnetic forces, stop growing with the field.
    double lone_grain_saturation_flux_density = 0;
    bool batch_supply = false;  // model/supply "batch": grains leaving downstream are removed, none enter
    std::string tier;
    // The continuum tier's yield stress of this fluid against the field (the block `continuum`,
    // from `mrjam shear`); required by that tier, optional (and unused) in the others.
    std::optional<YieldStressTable> yield_stress;
    int continuum_samples = 2000;  // Simpson intervals over the passage

    // A slab thinner than the bore cuts the valve with two plane faces; otherwise the full bore.
    bool is_slab() const { return slab_half_thickness > 0 && slab_half_thickness < valve.bore_radius(); }
    // Half the modelled width across the slab (x): the slab's, or the bore's radius.
    double half_width() const { return is_slab() ? slab_half_thickness : valve.bore_radius(); }
};

// The DEM tiers and "continuum" (a Bingham plug, lib/jam/continuum_tier.hpp).
std::vector<std::string> jam_tier_names();
// Throws SceneError (path + fix) for bad or impossible input. `base_directory` resolves a field
// map's relative path.
JamScene read_jam_scene(const nlohmann::json& scene, const std::string& tier, const std::string& base_directory);

}  // namespace mrjam
