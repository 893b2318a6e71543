#pragma once
// The solved field's |B| on the mid-plane z = 0 as a figure a designer reads at a glance: the
// colour scale in mT, a length scale bar, and which fluid region the map is of. Written by
// `mrjam magnetics` beside its report and by `mrjam design` for each constriction.
#include <string>

#include "io/svg_figure.hpp"
#include "magnetics/epm_field.hpp"

namespace mrjam::magnetics {

// Whether the solve made a mid-plane picture (the FEM models do; the circuit model does not).
bool has_midplane_picture(const EpmField& field);

// The picture as a panel. The colour scale saturates at twice the active fluid's mean |B|: the
// iron's flux density would otherwise wash out the fluid, which is what a designer looks at.
SvgPanel midplane_picture_panel(const EpmField& field, const std::string& title);

// Writes the panel as an SVG figure at `svg_path` with its PNG twin (the same path, .png).
void write_midplane_picture(const EpmField& field, const std::string& title, const std::string& svg_path);

}  // namespace mrjam::magnetics
