#include "sweep/sweep_plots.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "io/svg_plot.hpp"
#include "scene/units.hpp"

namespace mrjam {
using json = nlohmann::json;

namespace {

const std::vector<std::string> kColours{"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#17becf"};

// A point of a picture: its value at the swept keys and its output, with bars.
struct Sample {
    json values;
    double y = NAN, below = 0, above = 0;
};

// From an aggregate over seeds (share with its interval, or mean with sd) or a row's raw value.
Sample sample_of(const json& values, const json& out, bool aggregated) {
    Sample s{values};
    if (!aggregated) {
        if (out.is_boolean()) s.y = out.get<bool>() ? 1.0 : 0.0;
        if (out.is_number()) s.y = out.get<double>();
    } else if (out.contains("share")) {
        s.y = out["share"].get<double>();
        s.below = s.y - out["ci95"][0].get<double>();
        s.above = out["ci95"][1].get<double>() - s.y;
    } else if (out.contains("mean")) {
        s.y = out["mean"].get<double>();
        s.below = s.above = out["sd"].get<double>();
    }
    return s;
}

// A swept value as a number on the axis: a quantity in SI, a plain number, or a word's leading
// number ("20x" -> 20); NaN for a word without one.
double axis_number(const json& v, std::string& unit) {
    if (v.is_number()) return v.get<double>();
    if (!v.is_string()) return NAN;
    const std::string text = v.get<std::string>();
    try {
        const units::Quantity q = units::parse(text);
        unit = units::spoken(q.dimension);
        unit = unit.substr(0, unit.find(','));  // "Pa, e.g. ..." -> "Pa"
        return q.value;
    } catch (const std::exception&) {
    }
    try {
        return std::stod(text);
    } catch (const std::exception&) {
        return NAN;
    }
}

// A value as a legend or title shows it: a whole block (a zipped axis's) cut short.
std::string shown(const json& v) {
    const std::string text = v.is_string() ? v.get<std::string>() : v.dump();
    return text.size() <= 48 ? text : text.substr(0, 45) + "...";
}

// One picture: a series per value of `lines`, x from the swept values.
Plot picture(const SweepPlot& p, const std::vector<Sample>& samples, const std::string& title,
             const std::string& y_note) {
    Plot plot;
    plot.title = p.title.empty() ? title : p.title;
    plot.y_label = p.y_label.empty() ? p.output + y_note : p.y_label;
    std::string unit;
    std::vector<std::string> words;  // x values that are words without a number, in order
    for (const Sample& s : samples)
        if (std::isnan(axis_number(s.values[p.x], unit)) &&
            std::find(words.begin(), words.end(), shown(s.values[p.x])) == words.end())
            words.push_back(shown(s.values[p.x]));
    plot.x_label = p.x + (unit.empty() || unit == "1" ? "" : " (" + unit + ")");
    if (!p.x_label.empty()) plot.x_label = p.x_label;
    if (!words.empty()) {
        plot.x_label = (p.x_label.empty() ? p.x : p.x_label) + ":";
        for (std::size_t k = 0; k < words.size(); ++k) plot.x_label += " " + std::to_string(k + 1) + " = " + words[k];
    }
    std::map<std::string, std::size_t> series_of;
    for (const Sample& s : samples) {
        if (std::isnan(s.y)) continue;
        // A series per value (the whole value: two blocks may share their shown start).
        const std::string line = p.lines.empty() ? p.output : s.values[p.lines].dump();
        if (!series_of.count(line)) {
            series_of[line] = plot.series.size();
            PlotSeries series;
            series.label = p.lines.empty() ? p.output : p.lines + " = " + shown(s.values[p.lines]);
            for (const PlotSeries& other : plot.series)
                if (other.label == series.label) series.label = p.lines + " = " + s.values[p.lines].dump();
            series.colour = kColours[plot.series.size() % kColours.size()];
            plot.series.push_back(series);
        }
        PlotSeries& series = plot.series[series_of[line]];
        double x = axis_number(s.values[p.x], unit);
        if (std::isnan(x))
            x = static_cast<double>(std::find(words.begin(), words.end(), shown(s.values[p.x])) - words.begin() + 1);
        series.x.push_back(x);
        series.y.push_back(s.y);
        series.error_low.push_back(s.below);
        series.error_high.push_back(s.above);
    }
    // Values spanning two decades or more (a logarithmic range) on a logarithmic axis.
    double lo = INFINITY, hi = 0;
    for (const PlotSeries& series : plot.series)
        for (double x : series.x) lo = std::min(lo, x), hi = std::max(hi, x);
    plot.log_x = words.empty() && lo > 0 && hi >= 100 * lo;
    return plot;
}

}  // namespace

std::vector<std::string> write_sweep_plots(const SweepSpec& spec, const json& table, const std::string& dir) {
    const bool aggregated = table.contains("aggregates");
    const json& entries = aggregated ? table["aggregates"] : table["rows"];
    std::vector<std::string> written;
    for (const SweepPlot& p : spec.plots) {
        // One picture per combination of the keys neither on the x axis nor the lines.
        std::vector<std::string> order;
        std::map<std::string, std::vector<Sample>> pictures;
        std::string y_note;
        for (const json& e : entries) {
            if (!aggregated && e["state"] != "done") continue;
            // Titled by the first key of each other axis (a zipped axis's keys move together).
            std::string title = p.output + " against " + p.x;
            for (const SweepAxis& a : spec.axes) {
                const std::string& k = a.keys.front();
                if (k != p.x && k != p.lines && k != "seed" && a.values.size() > 1)
                    title += ", " + k + " = " + shown(e["values"][k]);
            }
            if (!pictures.count(title)) order.push_back(title);
            const json& out = e["outputs"][p.output];
            if (aggregated && y_note.empty())
                y_note = out.contains("share")  ? " (share of the seeds, 95 % interval)"
                         : out.contains("mean") ? " (mean and sd over the seeds)"
                                                : "";
            Sample sample = sample_of(e["values"], out, aggregated);
            // A row's own interval (a jam probability over a design's seeds), where the output has one.
            const json ci = e.contains("outputs_95ci") ? e["outputs_95ci"].value(p.output, json()) : json();
            if (!aggregated && ci.is_array() && ci.size() == 2 && ci[0].is_number() && ci[1].is_number() &&
                !std::isnan(sample.y)) {
                sample.below = sample.y - ci[0].get<double>();
                sample.above = ci[1].get<double>() - sample.y;
                if (y_note.empty()) y_note = " (95 % interval)";
            }
            pictures[title].push_back(sample);
        }
        std::string stem = "plot_" + p.output + "_vs_" + p.x;
        for (char& c : stem)
            if (c == '/') c = '_';
        for (std::size_t k = 0; k < order.size(); ++k) {
            const std::string file =
                (std::filesystem::path(dir) / (stem + (order.size() > 1 ? "_" + std::to_string(k + 1) : "") + ".svg"))
                    .string();
            write_svg(file, picture(p, pictures[order[k]], order[k], y_note));
            written.push_back(file);
        }
    }
    return written;
}

}  // namespace mrjam
