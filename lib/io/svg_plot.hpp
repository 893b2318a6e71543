#pragma once
// A minimal SVG line/scatter plot writer (no plotting dependency): linear or logarithmic axes
// with ticks, series drawn as markers with error bars or as lines (solid or dashed), and a legend.
#include <string>
#include <vector>

namespace mrjam {

struct PlotSeries {
    std::string label;                // "": drawn, but not in the legend
    std::vector<double> x, y, error;  // error may be empty
    // Asymmetric bars (a confidence interval): y - error_low to y + error_high; when given, they
    // replace `error`.
    std::vector<double> error_low, error_high;
    std::string colour = "#1f77b4";
    bool line = false;    // line instead of markers
    bool hollow = false;  // open markers
    bool dashed = false;  // a dashed line (with `line`)
};

struct Plot {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
    bool y_from_zero = true;  // linear y only
    // Logarithmic axes: ticks at whole decades; points with a value <= 0 on a log axis are left out.
    bool log_x = false, log_y = false;
};

// A finished SVG element (<svg ...>...</svg>) and its size in SVG units, to be written alone or
// placed beside others in one figure (io/svg_figure.hpp).
struct SvgPanel {
    std::string svg;
    double width = 0, height = 0;
};

// The plot as an SVG element.
SvgPanel plot_panel(const Plot& plot);

// A "nice" spacing, 1, 2 or 5 times a power of ten, of at least span / count: about `count`
// ticks over the span.
double nice_step(double span, int count);

// A number as the plots label it (printf's %g).
std::string svg_number(double v);

// Text made safe inside an SVG element: <, > and & as entities.
std::string svg_escape(const std::string& s);

// Writes the plot as an SVG file and its PNG twin (rendered by librsvg at twice the SVG's size,
// io/svg_raster.hpp); throws std::runtime_error if either cannot be written.
void write_svg(const std::string& path, const Plot& plot);

}  // namespace mrjam
