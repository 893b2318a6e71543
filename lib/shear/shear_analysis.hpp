#pragma once
// From the rates a study finished to the results of a report: the flow curve, the yield-stress
// fits (Bingham, Casson, Herschel-Bulkley), the stress-vs-field curve and the comparison with
// the experiment the scene names.
#include <nlohmann/json.hpp>
#include <vector>

#include "shear/flow_curve_fit.hpp"
#include "shear/shear_spec.hpp"

namespace mrjam {

// cells: the finished cells (the main ladder's); current: the cell in progress or null;
// field_sweep: the field sweep's finished fields (shear/field_sweep.hpp), null without a sweep.
nlohmann::json summarise(const ShearSpec& spec, const nlohmann::json& cells, const nlohmann::json& current,
                         const nlohmann::json& field_sweep = nullptr);

// The flow curve of a results object (rate, stress, error), for fits and plots.
std::vector<FlowPoint> flow_points(const nlohmann::json& results);

}  // namespace mrjam
