#include "magnetics/field_picture.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mrjam::magnetics {

bool has_midplane_picture(const EpmField& field) {
    const FieldGrid& g = field.picture;
    return g.count[0] > 1 && g.count[1] > 1 && g.values.size() == std::size_t(g.count[0]) * g.count[1];
}

SvgPanel midplane_picture_panel(const EpmField& field, const std::string& title) {
    if (!has_midplane_picture(field)) throw std::invalid_argument("this field solve made no mid-plane picture");
    const FieldGrid& g = field.picture;
    ScalarMapFigure f;
    f.title = title;
    f.nx = g.count[0];
    f.ny = g.count[1];
    f.values.resize(g.values.size());
    double top = 0;
    for (std::size_t i = 0; i < g.values.size(); ++i) {
        f.values[i] = g.values[i].x * 1e3;  // the picture grid carries |B| in its x component, tesla
        if (std::isfinite(f.values[i])) top = std::max(top, f.values[i]);
    }
    f.vmin = 0;
    f.vmax = std::max(1e-6, std::min(top, 2e3 * field.mean_b_active));
    f.unit = "|B| (mT)";
    // Each node is drawn as a cell of the grid's spacing, centred on it.
    f.width_m = f.nx * g.spacing.x;
    f.height_m = f.ny * g.spacing.y;
    f.caption = "mid-plane z = 0; colours saturate at " + std::to_string(static_cast<int>(std::lround(f.vmax))) +
                " mT, twice the active fluid's mean";
    return scalar_map_panel(f);
}

void write_midplane_picture(const EpmField& field, const std::string& title, const std::string& svg_path) {
    write_figure(svg_path, midplane_picture_panel(field, title).svg);
}

}  // namespace mrjam::magnetics
