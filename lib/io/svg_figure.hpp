#pragma once
// Figures of several panels: a scalar map (a field on a plane) drawn with its colour scale in
// physical units and a length scale bar, and a row of panels (plots, maps) under one title, as
// one SVG file with its PNG twin. The map's pixels travel inside the SVG as a PNG data URI, so
// the figure is one self-contained file.
#include <string>
#include <vector>

#include "io/svg_plot.hpp"

namespace mrjam {

struct ScalarMapFigure {
    std::string title;
    std::vector<double> values;  // nx x ny, x fastest, row 0 at the bottom (as render_scalar_map)
    int nx = 0, ny = 0;
    double width_m = 0, height_m = 0;  // the plane's extent the nodes span
    double vmin = 0, vmax = 1;         // the colour scale, in the values' unit
    std::string unit;                  // e.g. "mT"
    std::string caption;               // a line under the map ("" for none)
};

// The map as a panel: the picture (aspect ratio of the plane), a viridis colour bar with ticks
// labelled in `unit`, and a scale bar of a round length. Throws std::invalid_argument on sizes
// that do not match or a non-positive extent.
SvgPanel scalar_map_panel(const ScalarMapFigure& figure);

// The panels side by side under `title`, as one SVG document.
std::string svg_row(const std::string& title, const std::vector<SvgPanel>& panels);

// Writes the document to `path` with its PNG twin (io/svg_raster.hpp), creating the directory.
void write_figure(const std::string& path, const std::string& svg);

}  // namespace mrjam
