#include "shear/shear_plots.hpp"

#include <filesystem>

#include "io/svg_plot.hpp"

namespace mrjam {
namespace {

std::string sibling(const std::string& report_path, const std::string& suffix) {
    std::filesystem::path p(report_path);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
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

void add_bingham(Plot& plot, const nlohmann::json& fits, double x_max) {
    if (!fits.contains("bingham") || !fits["bingham"].value("ok", false)) return;
    const auto& b = fits["bingham"];
    PlotSeries line;
    line.label = "Bingham fit";
    line.line = true;
    line.colour = "#d62728";
    const double ty = b["yield_stress_Pa"].get<double>(), eta = b["plastic_viscosity_Pa_s"].get<double>();
    for (double x : {0.0, x_max}) {
        line.x.push_back(x);
        line.y.push_back((ty + eta * x) * 1e-3);
    }
    plot.series.push_back(line);
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
    if (experiment.contains("yield_stress_Pa")) {
        PlotSeries y;
        y.label = "experimental yield stress";
        y.line = true;
        y.colour = "#2ca02c";
        for (double x : {0.0, x_max}) {
            y.x.push_back(x);
            y.y.push_back(experiment["yield_stress_Pa"].get<double>() * 1e-3);
        }
        plot.series.push_back(y);
    }
}

}  // namespace

nlohmann::json write_shear_plots(const std::string& report_path, const nlohmann::json& report) {
    nlohmann::json paths = nlohmann::json::object();
    const auto& r = report["results"];
    Plot plot;
    plot.title = "Flow curve (" + report["fidelity"].value("tier", std::string()) + " tier)";
    plot.x_label = "shear rate (1/s)";
    plot.y_label = "shear stress (kPa)";
    plot.series.push_back(curve_series(r["flow_curve"], "simulation (upper raft)"));
    double x_max = 0;
    for (double x : plot.series[0].x) x_max = std::max(x_max, x);
    add_bingham(plot, r["fits"], x_max);
    add_experiment(plot, r.value("experiment", nlohmann::json()), x_max);
    const std::string fc = sibling(report_path, "_flow_curve.svg");
    write_svg(fc, plot);
    paths["flow_curve"] = fc;
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

}  // namespace mrjam
