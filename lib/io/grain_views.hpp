#pragma once
// Pictures of a body of grains: orthographic views along and across an axis, each grain a disc
// painted far to near, coloured by its distance from a centre (viridis) with a colour bar in
// metres and a scale bar, as an SVG a person can open in a browser and its PNG twin
// (io/svg_raster.hpp).
#include <string>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct GrainViews {
    std::string title;
    std::vector<Vec3> position;  // m
    std::vector<double> radius;  // m
    Vec3 centre;                 // the distances are measured from here (the centre of mass)
};

// Two panels: along z (x to the right, y up, seen from +z) and across it (x to the right, z up,
// seen from -y). Throws std::runtime_error naming `path` if it cannot be written and
// std::invalid_argument if the grains and radii differ in number.
void write_grain_views(const std::string& path, const GrainViews& views);

}  // namespace mrjam
