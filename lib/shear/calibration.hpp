#pragma once
// Calibration: fit one or two named model parameters so the simulated flow curve matches
// measured points. Each evaluation is a full shear study at the measured rates (same seed, so
// the evaluations share their random grains and the objective is smooth in the parameters); the
// search is derivative-free because each evaluation is noisy and expensive: NLopt's bounded
// Nelder-Mead simplex over the parameters' box.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shear/flow_curve_fit.hpp"
#include "shear/shear_cell.hpp"
#include "shear/shear_spec.hpp"

namespace mrjam {

struct CalibrationData {
    std::vector<FlowPoint> points;  // rate 1/s, stress Pa, error Pa (0 if not given)
};

// JSON: [[rate, stress(, error)], ...] or {"points": [...]} or {"flow_curve": [...]}, entries as
// arrays or {"rate", "stress", "error"} objects; CSV: one point per line, comma, semicolon or
// space separated, header and '#' lines skipped. SI units (1/s, Pa). Throws SceneError naming
// --calibrate and the line or entry.
CalibrationData read_calibration_data(const std::string& path);

struct CalibrationParameter {
    std::string name;
    std::string pointer;  // JSON pointer into the shear scene; "" for field_scale
    double lo = 0, hi = 0;
};

// "NAME=MIN:MAX" items; NAME one of rolling_friction, friction, rolling_damping,
// cohesion_energy_density, relative_permeability, field_scale, or a JSON pointer. Throws SceneError.
std::vector<CalibrationParameter> parse_calibration_parameters(const std::vector<std::string>& items,
                                                               const ShearSpec& spec);

// The calibration's search (NLopt's bounded Nelder-Mead simplex from the box's centre, first
// steps a quarter of each range): calls `evaluate` at points inside the parameters' [lo, hi] box,
// at most max_runs times, fewer once `stop` is true after a call.
void minimise_in_box(const std::vector<CalibrationParameter>& params, int max_runs,
                     const std::function<double(const std::vector<double>&)>& evaluate, const bool& stop);

// Runs the search; the result holds status, runs, best (values, residual, flow curve, fits).
nlohmann::json calibrate(const ShearSpec& spec, const CalibrationData& data,
                         const std::vector<CalibrationParameter>& params, int max_runs, const ShearOptions& options);

}  // namespace mrjam
