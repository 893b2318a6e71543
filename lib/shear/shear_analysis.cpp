#include "shear/shear_analysis.hpp"

#include <cmath>

namespace mrjam {

std::vector<FlowPoint> flow_points(const nlohmann::json& results) {
    std::vector<FlowPoint> pts;
    if (!results.contains("flow_curve")) return pts;
    for (const auto& p : results["flow_curve"])
        pts.push_back({p["rate_1_s"].get<double>(), p["stress_Pa"].get<double>(), p["error_Pa"].get<double>()});
    return pts;
}

nlohmann::json summarise(const ShearSpec& spec, const nlohmann::json& cells, const nlohmann::json& current,
                         const nlohmann::json& field_sweep) {
    nlohmann::json r = nlohmann::json::object();
    const nlohmann::json* main = nullptr;
    bool main_partial = false;
    if (!cells.empty())
        main = &cells[0];
    else if (current.is_object() && current["cell"] == 0) {
        main = &current;
        main_partial = true;
    }
    r["flow_curve"] = nlohmann::json::array();
    if (main) {
        for (const auto& q : (*main)["rates"]) {
            nlohmann::json p = q;
            p.erase("series_upper_Pa");
            r["flow_curve"].push_back(p);
        }
        r["magnetisation"] = main->value("magnetisation", nlohmann::json());
        r["cell"] = {{"size_m", {spec.cell.x, spec.cell.y, spec.cell.z}},
                     {"raft_thickness_m", spec.raft_thickness},
                     {"gap_m", spec.gap()},
                     {"boundaries", spec.lees_edwards ? "lees_edwards" : "rafts"},
                     {"monolayer", spec.monolayer},
                     {"grains", (*main)["grains"]},
                     {"timestep_s", (*main)["timestep_s"]}};
        if (main->contains("rafts")) r["cell"]["rafts"] = (*main)["rafts"];
        if (spec.monolayer) {
            r["cell"]["area_fraction"] = spec.area_fraction;
            r["cell"]["stress_thickness_m"] = spec.cell.y;  // stresses are per X Y (Y: the layer's stated thickness)
        }
        r["stress_series_upper_Pa"] = nlohmann::json::array();
        for (const auto& q : (*main)["rates"])
            r["stress_series_upper_Pa"].push_back({{"rate_1_s", q["rate_1_s"]}, {"samples", q["series_upper_Pa"]}});
    }
    r["flow_curve_complete"] = main && !main_partial;
    const auto pts = flow_points(r);
    const ModelFit bingham = fit_bingham(pts, spec.bingham_min_rate);
    const ModelFit casson = fit_casson(pts);
    const ModelFit hb = fit_herschel_bulkley(pts);
    r["fits"] = {{"bingham", to_json(bingham)}, {"casson", to_json(casson)}, {"herschel_bulkley", to_json(hb)}};
    r["yield_stress_Pa"] = bingham.ok ? nlohmann::json(bingham.yield_stress) : nlohmann::json(nullptr);
    r["yield_stress_error_Pa"] = bingham.ok ? nlohmann::json(bingham.yield_stress_error) : nlohmann::json(nullptr);
    if (!bingham.ok) r["yield_stress_note"] = bingham.note;
    // The fitted rates whose stress was not steady in its window: the intercept carries their
    // transient. A first rate still rising lowers the fastest point, tilts the line down and
    // raises the intercept above every point (measured in docs/notes/shear_strain.md).
    r["fit_rates_not_steady_1_s"] = nlohmann::json::array();
    for (const auto& q : r["flow_curve"])
        if (q["rate_1_s"].get<double>() >= spec.bingham_min_rate &&
            (!q.value("steady_before_window", true) || q.value("drifting_in_window", false)))
            r["fit_rates_not_steady_1_s"].push_back(q["rate_1_s"]);

    if (!spec.sweep_fields.empty()) r["field_sweep"] = field_sweep.is_array() ? field_sweep : nlohmann::json::array();
    if (spec.experiment.is_object()) {
        nlohmann::json cmp = spec.experiment;
        if (cmp.contains("yield_stress_Pa") && bingham.ok) {
            const double e = cmp["yield_stress_Pa"].get<double>();
            cmp["relative_error"] = (bingham.yield_stress - e) / e;
            cmp["relative_uncertainty"] = bingham.yield_stress_error / e;
        }
        r["experiment"] = cmp;
    }
    return r;
}

}  // namespace mrjam
