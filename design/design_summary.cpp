#include "design/design_summary.hpp"

#include <fstream>
#include <regex>
#include <sstream>

#include "io/svg_figure.hpp"
#include "io/svg_raster.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double number_or(const json& v, double fallback) { return v.is_number() ? v.get<double>() : fallback; }

// The row whose field the figure shows: the widest reliable constriction, else the most likely to jam.
const json* chosen_row(const json& rows, const std::string& widest) {
    const json* best = nullptr;
    for (const json& row : rows) {
        if (!widest.empty()) {
            if (row.value("constriction", std::string()) == widest) return &row;
            continue;
        }
        const double p = number_or(row["jam_probability"], -1), d = number_or(row["diameter_m"], 0);
        if (!best || p > number_or((*best)["jam_probability"], -1) ||
            (p == number_or((*best)["jam_probability"], -1) && d < number_or((*best)["diameter_m"], 0)))
            best = &row;
    }
    return best;
}

// A figure file written by scalar_map_panel, read back as a panel (its size from the root element).
std::optional<SvgPanel> read_panel(const std::string& path) {
    std::ifstream in(path);
    if (!in) return std::nullopt;
    std::stringstream text;
    text << in.rdbuf();
    SvgPanel p{text.str(), 0, 0};
    std::smatch m;
    static const std::regex size(R"re(<svg[^>]*width="([0-9.eE+-]+)" height="([0-9.eE+-]+)")re");
    if (!std::regex_search(p.svg, m, size)) return std::nullopt;
    p.width = std::stod(m[1]);
    p.height = std::stod(m[2]);
    return p;
}

Plot against_diameter(const std::string& title, const std::string& y_label) {
    Plot plot;
    plot.title = title;
    plot.x_label = "throat diameter (um)";
    plot.y_label = y_label;
    return plot;
}

std::vector<SvgPanel> plot_panels(const json& rows) {
    Plot probability = against_diameter("Jam probability", "jam probability over the seeds");
    Plot flow = against_diameter("Open valve's flow", "open flow at the supply pressure (ml/min)");
    PlotSeries p, q;
    p.label = "jams (95 % interval)";
    q.label = "open flow";
    q.colour = "#d62728";
    for (const json& row : rows) {
        const double d_um = number_or(row["diameter_m"], 0) * 1e6;
        if (row["jam_probability"].is_number()) {
            const double value = row["jam_probability"].get<double>();
            const json& ci = row["jam_probability_95ci"];
            p.x.push_back(d_um);
            p.y.push_back(value);
            p.error_low.push_back(ci.is_array() ? value - ci[0].get<double>() : 0.0);
            p.error_high.push_back(ci.is_array() ? ci[1].get<double>() - value : 0.0);
        }
        if (row["open_flow_rate_ml_min"].is_number()) {
            q.x.push_back(d_um);
            q.y.push_back(row["open_flow_rate_ml_min"].get<double>());
        }
    }
    probability.series = {p};
    flow.series = {q};
    return {plot_panel(probability), plot_panel(flow)};
}

}  // namespace

DesignSummary write_design_summary(const json& rows, const std::string& widest, const fs::path& svg_path) {
    DesignSummary out;
    if (!rows.is_array() || rows.empty()) return out;
    std::vector<SvgPanel> panels = plot_panels(rows);
    const json* chosen = chosen_row(rows, widest);
    if (chosen && chosen->contains("field_picture"))
        if (std::optional<SvgPanel> field = read_panel((*chosen)["field_picture"].get<std::string>())) {
            panels.push_back(*field);
            out.field_of = (*chosen)["constriction"].get<std::string>();
        }
    const std::string title =
        widest.empty() ? "No constriction jams reliably" +
                             (out.field_of.empty() ? std::string() : "; the field of the likeliest, " + out.field_of)
                       : "Widest constriction that jams reliably: " + widest;
    write_figure(svg_path.string(), svg_row(title, panels));
    out.svg_path = svg_path.string();
    out.png_path = png_twin(out.svg_path);
    return out;
}

}  // namespace mrjam
