#pragma once
// A minimal SVG line/scatter plot writer (no plotting dependency): linear axes with ticks,
// series drawn as markers with error bars or as lines, and a legend.
#include <string>
#include <vector>

namespace mrjam {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y, error;  // error may be empty
    std::string colour = "#1f77b4";
    bool line = false;    // line instead of markers
    bool hollow = false;  // open markers
};

struct Plot {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
    bool y_from_zero = true;
};

// Writes the plot as an SVG file; throws std::runtime_error if it cannot be written.
void write_svg(const std::string& path, const Plot& plot);

}  // namespace mrjam
