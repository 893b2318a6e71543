#include "shear/shear_plots.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "io/svg_plot.hpp"

namespace mrjam {
namespace {

std::string sibling(const std::string& report_path, const std::string& suffix) {
    std::filesystem::path p(report_path);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

const std::vector<std::string> kSizeColours{"#1f77b4", "#d62728", "#9467bd", "#ff7f0e", "#8c564b", "#17becf"};

// A horizontal line across [x0, x1] at y (kPa).
PlotSeries level(const std::string& label, const std::string& colour, double x0, double x1, double y, bool dashed) {
    PlotSeries s;
    s.label = label;
    s.colour = colour;
    s.line = true;
    s.dashed = dashed;
    s.x = {x0, x1};
    s.y = {y, y};
    return s;
}

PlotSeries curve_series(const nlohmann::json& flow_curve, const std::string& label) {
    PlotSeries s;
    s.label = label;
    for (const auto& q : flow_curve) {
        s.x.push_back(q["rate_1_s"].get<double>());
        s.y.push_back(q["stress_Pa"].get<double>() * 1e-3);
        s.error.push_back(q["error_Pa"].get<double>() * 1e-3);
    }
    return s;
}

// A Bingham fit's line tau_y + eta * rate (kPa) through the given rates.
PlotSeries bingham_line(const nlohmann::json& b, const std::vector<double>& rates, const std::string& label,
                        const std::string& colour) {
    PlotSeries line;
    line.label = label;
    line.line = true;
    line.colour = colour;
    const double ty = b["yield_stress_Pa"].get<double>(), eta = b["plastic_viscosity_Pa_s"].get<double>();
    for (double x : rates) {
        line.x.push_back(x);
        line.y.push_back((ty + eta * x) * 1e-3);
    }
    return line;
}

void add_bingham(Plot& plot, const nlohmann::json& fits, double x_max) {
    if (!fits.contains("bingham") || !fits["bingham"].value("ok", false)) return;
    plot.series.push_back(bingham_line(fits["bingham"], {0.0, x_max}, "Bingham fit", "#d62728"));
}

void add_experiment(Plot& plot, const nlohmann::json& experiment, double x_max) {
    if (!experiment.is_object()) return;
    if (experiment.contains("flow_curve")) {
        PlotSeries e;
        e.label = experiment.value("label", std::string("experiment"));
        e.colour = "#2ca02c";
        e.hollow = true;
        for (const auto& q : experiment["flow_curve"]) {
            e.x.push_back(q[0].get<double>());
            e.y.push_back(q[1].get<double>() * 1e-3);
        }
        plot.series.push_back(e);
    }
    if (experiment.contains("yield_stress_Pa"))
        plot.series.push_back(level("experimental yield stress", "#2ca02c", 0.0, x_max,
                                    experiment["yield_stress_Pa"].get<double>() * 1e-3, false));
}

// Each rate's raft stress against the shear strain since the first rate began, with where the
// stress settles (MSER) marked: how much of each rate is transient.
Plot stress_strain_plot(const nlohmann::json& r) {
    Plot plot;
    plot.title = "Stress against strain, rate by rate";
    plot.x_label = "shear strain since the first rate";
    plot.y_label = "shear stress (kPa)";
    PlotSeries settle;
    settle.label = "steady from (MSER)";
    settle.colour = "#000000";
    settle.hollow = true;
    double before = 0;
    const auto& curve = r["flow_curve"];
    const auto& series = r["stress_series_upper_Pa"];
    for (std::size_t k = 0; k < curve.size() && k < series.size(); ++k) {
        const auto& q = curve[k];
        const double strain = q["strain"].get<double>();
        const double per_sample =
            strain * q["sample_every_steps"].get<double>() / std::max(1.0, q["steps"].get<double>());
        PlotSeries line;
        char label[48];
        std::snprintf(label, sizeof label, "%.4g 1/s", q["rate_1_s"].get<double>());
        line.label = label;
        line.line = true;
        line.colour = kSizeColours[k % kSizeColours.size()];
        const auto& samples = series[k]["samples"];
        for (std::size_t i = 0; i < samples.size(); ++i) {
            line.x.push_back(before + per_sample * static_cast<double>(i + 1));
            line.y.push_back(samples[i].get<double>() * 1e-3);
        }
        if (q.contains("steady_from_strain") && !samples.empty()) {
            const double at = q["steady_from_strain"].get<double>();
            const auto i = std::min(samples.size() - 1, static_cast<std::size_t>(std::max(0.0, at / per_sample)));
            settle.x.push_back(before + per_sample * static_cast<double>(i + 1));
            settle.y.push_back(samples[i].get<double>() * 1e-3);
        }
        plot.series.push_back(line);
        before += strain;
    }
    if (!settle.x.empty()) plot.series.push_back(settle);
    return plot;
}

// The local slope d ln(stress) / d ln(rate) between successive rates ("" if a stress is not positive):
// 0 for a yield-stress plateau, 1 for a Newtonian fluid, n for a power law.
std::string local_slopes(const PlotSeries& curve) {
    std::string text;
    for (std::size_t k = 0; k + 1 < curve.x.size(); ++k) {
        if (!(curve.y[k] > 0 && curve.y[k + 1] > 0)) return "";
        char one[24];
        std::snprintf(one, sizeof one, "%s%.2f", k ? ", " : "",
                      std::log(curve.y[k] / curve.y[k + 1]) / std::log(curve.x[k] / curve.x[k + 1]));
        text += one;
    }
    return text;
}

// Rates spanning more than kLogRateSpan are drawn on log axes (log-log when every stress is positive),
// with the local slopes in the legend: on linear axes most such rates sit at the origin. The Bingham
// line is then drawn through log-spaced rates, and the experimental yield stress from the lowest rate.
constexpr double kLogRateSpan = 20;

Plot flow_curve_plot(const nlohmann::json& report) {
    const auto& r = report["results"];
    Plot plot;
    plot.title = "Flow curve (" + report["fidelity"].value("tier", std::string()) + " tier)";
    plot.x_label = "shear rate (1/s)";
    plot.y_label = "shear stress (kPa)";
    PlotSeries curve = curve_series(r["flow_curve"], "simulation (upper raft)");
    double x_min = 1e300, x_max = 0;
    for (double x : curve.x) x_min = std::min(x_min, x), x_max = std::max(x_max, x);
    plot.log_x = !curve.x.empty() && x_max > kLogRateSpan * x_min;
    const std::string slopes = plot.log_x ? local_slopes(curve) : "";
    plot.log_y = !slopes.empty();
    if (!slopes.empty()) curve.label += "; d ln stress / d ln rate, high to low rates: " + slopes;
    plot.series.push_back(curve);
    if (!plot.log_x) {
        add_bingham(plot, r["fits"], x_max);
        add_experiment(plot, r.value("experiment", nlohmann::json()), x_max);
        return plot;
    }
    const auto& fits = r["fits"];
    if (fits.contains("bingham") && fits["bingham"].value("ok", false)) {
        std::vector<double> rates;  // log-spaced from half the lowest rate to 1.5 times the highest
        for (int i = 0; i <= 40; ++i) rates.push_back(0.5 * x_min * std::pow(3 * x_max / x_min, i / 40.0));
        plot.series.push_back(bingham_line(fits["bingham"], rates, "Bingham fit", "#d62728"));
    }
    const nlohmann::json experiment = r.value("experiment", nlohmann::json());
    add_experiment(plot, experiment, x_max);
    if (!plot.series.empty() && experiment.contains("yield_stress_Pa")) plot.series.back().x = {0.5 * x_min, x_max};
    return plot;
}

}  // namespace

nlohmann::json write_shear_plots(const std::string& report_path, const nlohmann::json& report) {
    nlohmann::json paths = nlohmann::json::object();
    const auto& r = report["results"];
    const std::string fc = sibling(report_path, "_flow_curve.svg");
    write_svg(fc, flow_curve_plot(report));
    paths["flow_curve"] = fc;
    if (r.contains("stress_series_upper_Pa") && !r["flow_curve"].empty()) {
        const std::string ss = sibling(report_path, "_stress_strain.svg");
        write_svg(ss, stress_strain_plot(r));
        paths["stress_strain"] = ss;
    }
    if (r.contains("field_sweep") && !r["field_sweep"].empty()) {
        Plot f;
        f.title = "Stress vs field at " +
                  std::to_string(static_cast<int>(r["field_sweep"][0]["rate_1_s"].get<double>())) + " 1/s";
        f.x_label = "flux density (mT)";
        f.y_label = "shear stress (kPa)";
        PlotSeries s;
        s.label = "simulation";
        for (const auto& q : r["field_sweep"]) {
            s.x.push_back(q["flux_density_T"].get<double>() * 1e3);
            s.y.push_back(q["stress_Pa"].get<double>() * 1e-3);
            s.error.push_back(q["error_Pa"].get<double>() * 1e-3);
        }
        f.series.push_back(s);
        const std::string fs = sibling(report_path, "_field_sweep.svg");
        write_svg(fs, f);
        paths["field_sweep"] = fs;
    }
    return paths;
}

std::string write_calibration_plot(const std::string& report_path, const nlohmann::json& report,
                                   const CalibrationData& data) {
    Plot plot;
    plot.title = "Calibration: flow curve at the optimum";
    plot.x_label = "shear rate (1/s)";
    plot.y_label = "shear stress (kPa)";
    if (report.contains("best") && report["best"].contains("flow_curve"))
        plot.series.push_back(curve_series(report["best"]["flow_curve"], "simulation at optimum"));
    PlotSeries d;
    d.label = "data";
    d.colour = "#2ca02c";
    d.hollow = true;
    for (const auto& p : data.points) {
        d.x.push_back(p.rate);
        d.y.push_back(p.stress * 1e-3);
        d.error.push_back(p.error * 1e-3);
    }
    plot.series.push_back(d);
    const std::string path = sibling(report_path, "_calibration.svg");
    write_svg(path, plot);
    return path;
}

nlohmann::json write_convergence_plots(const std::string& report_path, const nlohmann::json& report) {
    const auto& r = report["results"];
    const std::string tier = report["fidelity"].value("tier", std::string());
    double edge_lo = INFINITY, edge_hi = 0, rate_hi = 0;
    for (const auto& s : r["sizes"]) {
        edge_lo = std::min(edge_lo, s["edge_m"].get<double>() * 1e6);
        edge_hi = std::max(edge_hi, s["edge_m"].get<double>() * 1e6);
        for (const auto& q : s["flow_curve"]) rate_hi = std::max(rate_hi, q["rate_1_s"].get<double>());
    }
    Plot yield;
    yield.title = "Yield stress against the cell's edge (" + tier + " tier, " +
                  std::to_string(r["seeds_per_size"].get<int>()) + " seeds a size)";
    yield.x_label = "cell edge (um)";
    yield.y_label = "Bingham yield stress (kPa), error: larger of seed spread and fit";
    PlotSeries sizes;
    sizes.label = "each size";
    for (const auto& s : r["sizes"])
        if (s["yield_stress_Pa"].is_number()) {
            sizes.x.push_back(s["edge_m"].get<double>() * 1e6);
            sizes.y.push_back(s["yield_stress_Pa"].get<double>() * 1e-3);
            sizes.error.push_back(s["yield_stress_error_Pa"].get<double>() * 1e-3);
        }
    yield.series.push_back(sizes);
    if (r["yield_stress_Pa"].is_number()) {
        const double y = r["yield_stress_Pa"].get<double>() * 1e-3, e = r["yield_stress_error_Pa"].get<double>() * 1e-3;
        const std::string what = r["converged"].get<bool>() ? "converged" : "largest cell (not converged)";
        yield.series.push_back(level(what, "#d62728", edge_lo, edge_hi, y, false));
        yield.series.push_back(level(what + " +- error", "#d62728", edge_lo, edge_hi, y + e, true));
        yield.series.push_back(level("", "#d62728", edge_lo, edge_hi, y - e, true));
    }
    const nlohmann::json experiment = r.value("experiment", nlohmann::json());
    if (experiment.is_object() && experiment.contains("yield_stress_Pa"))
        yield.series.push_back(level(experiment.value("label", std::string("experiment")), "#2ca02c", edge_lo, edge_hi,
                                     experiment["yield_stress_Pa"].get<double>() * 1e-3, false));
    const std::string yield_path = sibling(report_path, "_convergence.svg");
    write_svg(yield_path, yield);

    Plot curves;
    curves.title = "Flow curves by cell size (mean of the seeds)";
    curves.x_label = "shear rate (1/s)";
    curves.y_label = "shear stress (kPa), error: larger of seed spread and block errors";
    std::size_t k = 0;
    for (const auto& s : r["sizes"]) {
        if (s["flow_curve"].empty()) continue;
        const std::string colour = kSizeColours[k++ % kSizeColours.size()];
        char label[64];
        std::snprintf(label, sizeof label, "%.0f um", s["edge_m"].get<double>() * 1e6);
        PlotSeries points = curve_series(s["flow_curve"], label);
        points.colour = colour;
        curves.series.push_back(points);
        const auto& b = s["bingham_of_mean_curve"];
        if (!b.value("ok", false)) continue;
        PlotSeries line = bingham_line(b, {0.0, rate_hi}, std::string(label) + " Bingham", colour);
        line.dashed = true;
        curves.series.push_back(line);
    }
    add_experiment(curves, experiment, rate_hi);
    const std::string curves_path = sibling(report_path, "_flow_curves.svg");
    write_svg(curves_path, curves);
    return {{"convergence", yield_path}, {"flow_curves", curves_path}};
}

}  // namespace mrjam
