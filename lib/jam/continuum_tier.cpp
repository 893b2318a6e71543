#include "jam/continuum_tier.hpp"

#include <algorithm>
#include <memory>

#include "core/format.hpp"

namespace mrjam {

nlohmann::json continuum_results(const JamScene& js, nlohmann::json& warnings) {
    ValveGeometry passage = js.valve;
    std::function<double(double)> axial;
    std::string plug_extent;
    if (js.field_map) {
        // The whole solved field, as far as the valve's tube reaches into it.
        passage.upstream_length = std::max(passage.upstream_length, -js.field_map->lower_corner().z);
        passage.downstream_length = std::max(passage.downstream_length, js.field_map->upper_corner().z);
        const double scale = js.engine_scene["magnetic"]["field"]["scale"].get<double>();
        axial = [map = js.field_map, scale](double z) { return scale * norm(map->flux_density({0, 0, z}, 0.0)); };
        plug_extent = "the field map's axial extent";
    } else {
        const double b = js.peak_flux_density;
        axial = [b](double) { return b; };
        plug_extent = "the modelled tube (model/upstream_length + downstream_length): a uniform field has no length";
        warnings.push_back(
            "a uniform field fills the whole modelled tube, so the continuum plug is as long as the tube (" +
            format_number((passage.upstream_length + passage.downstream_length) * 1e3) +
            " mm): give a field map for the plug the magnet makes");
    }
    const BinghamPlugEstimate e =
        bingham_plug_hold(passage, axial, *js.yield_stress, js.flow.supply_pressure, js.continuum_samples);
    if (e.table_extrapolated)
        warnings.push_back("the field reaches " + format_number(e.peak_flux_density * 1e3, 3) +
                           " mT, beyond the yield-stress table's last field (" +
                           format_number(e.table_last_flux_density * 1e3, 3) +
                           " mT): its last yield stress is held there; measure the fluid at that field");
    // With the field off the plug keeps the table's yield stress at B = 0 (none for an MR fluid).
    const bool releases =
        !bingham_plug_hold(
             passage, [](double) { return 0.0; }, *js.yield_stress, js.flow.supply_pressure, js.continuum_samples)
             .jams;
    nlohmann::json r;
    r["jammed"] = e.jams;
    r["stops_flow"] = e.jams;
    r["released"] = e.jams ? nlohmann::json(releases) : nlohmann::json(nullptr);
    r["outcome"] = !e.jams ? "fail-no-jam" : releases ? "success" : "fail-irreversible";
    r["hold"] = {{"gave_way_at_pressure_Pa", e.hold_pressure}, {"held", e.jams}};
    r["continuum"] = e.to_json();
    r["continuum"]["plug_extent"] = plug_extent;
    r["continuum"]["yield_stress_table"] = js.yield_stress->to_json();
    r["model"] =
        "continuum (lib/jam/continuum_tier.hpp): a Bingham plug, dP_hold = integral of 4 tau_y(B(z)) / d(z) dz "
        "over the passage, tau_y(B) from the shear mode";
    return r;
}

}  // namespace mrjam
