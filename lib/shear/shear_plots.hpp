#pragma once
// Images written next to a shear report: the flow curve with its Bingham fit against the
// experimental points, and the stress-vs-field curve of a field sweep.
#include <nlohmann/json.hpp>
#include <string>

#include "shear/calibration.hpp"

namespace mrjam {

// Returns {"flow_curve": path, "field_sweep": path (when there is one)}.
nlohmann::json write_shear_plots(const std::string& report_path, const nlohmann::json& report);

// The convergence study's pictures: the yield stress against the cell's edge with its errors and
// the converged value, and each size's mean flow curve with its Bingham line. Returns
// {"convergence": path, "flow_curves": path}.
nlohmann::json write_convergence_plots(const std::string& report_path, const nlohmann::json& report);

// The calibration's flow curve at the optimum against the data; returns its path.
std::string write_calibration_plot(const std::string& report_path, const nlohmann::json& report,
                                   const CalibrationData& data);

}  // namespace mrjam
