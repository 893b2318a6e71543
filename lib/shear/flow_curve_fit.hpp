#pragma once
// Yield-stress models fitted to a flow curve (shear rate, stress, error bar):
//   Bingham           tau = tau_y + eta gamma_dot           (least squares over rates >= a threshold,
//                                                             200 1/s in the source, sec. 2.4.2)
//   Casson            sqrt(tau) = sqrt(tau_y) + sqrt(eta gamma_dot)
//   Herschel-Bulkley  tau = tau_y + K gamma_dot^n
// Each fit is unweighted least squares (as the source's linear regression). The parameter
// uncertainty is the larger of two estimates: the scatter of the points about the fit
// (residual variance, when there are more points than parameters) and the points' own error
// bars propagated through the fit; so two points with large error bars do not give a
// falsely exact intercept.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mrjam {

struct FlowPoint {
    double rate;    // 1/s
    double stress;  // Pa
    double error;   // Pa, one standard error (0 if unknown)
};

struct ModelFit {
    std::string model;  // "bingham", "casson", "herschel_bulkley"
    bool ok = false;    // false: too few usable points (see note)
    std::string note;
    double yield_stress = 0;  // Pa
    double yield_stress_error = 0;
    double viscosity = 0;  // Bingham and Casson plastic viscosity, Pa s
    double viscosity_error = 0;
    double consistency = 0;  // Herschel-Bulkley K, Pa s^n
    double flow_index = 1;   // Herschel-Bulkley n
    double flow_index_error = 0;
    double rms_residual = 0;  // Pa, in stress
    std::size_t points = 0;
    double min_rate = 0;  // the rates used
    double stress_at(double rate) const;
};

ModelFit fit_bingham(const std::vector<FlowPoint>& curve, double min_rate);
ModelFit fit_casson(const std::vector<FlowPoint>& curve);
ModelFit fit_herschel_bulkley(const std::vector<FlowPoint>& curve);

nlohmann::json to_json(const ModelFit& fit);

}  // namespace mrjam
