#pragma once
// The continuum tier of `mrjam jam` (`--fidelity continuum`): no grains, an answer in a second.
// The magnetised fluid in the valve is a Bingham plug whose yield stress tau_y(B) the shear mode
// measured for this fluid (the scene's `continuum` block); the plug holds the pressure
// dP_hold = integral of 4 tau_y(B(z)) / d(z) dz (lib/jam/bingham_plug.hpp) and the valve closes
// when dP_hold exceeds the supply pressure. With the field off tau_y is the table's at B = 0
// (none for an MR fluid), so a plug that holds also releases.
//
// The plug's length is the field's: over a field map's whole axial extent (the field, not the
// DEM tier's modelled stretch, sets where the fluid is solid), and over the scene's modelled tube
// for a uniform field (which has no length of its own; the report says which).
#include <nlohmann/json.hpp>

#include "jam/jam_scene.hpp"

namespace mrjam {

// The report's "results" (outcome in Table 3.2's words, the holding pressure as
// hold.gave_way_at_pressure_Pa, and the estimate's details) and its warnings.
nlohmann::json continuum_results(const JamScene& scene, nlohmann::json& warnings);

}  // namespace mrjam
