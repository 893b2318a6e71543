#include "io/grain_views.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "io/png_image.hpp"
#include "io/svg_plot.hpp"
#include "io/svg_raster.hpp"

namespace mrjam {
namespace {

constexpr double kPanel = 420, kMargin = 40, kTop = 70, kGap = 60, kBarWidth = 18;

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", v);
    return b;
}

std::string hex(std::array<std::uint8_t, 3> c) {
    char b[8];
    std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
    return b;
}

// 1, 2 or 5 times a power of ten, at most `most`.
double round_length(double most) {
    const double p = std::pow(10.0, std::floor(std::log10(most)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * p <= most) return m * p;
    return p;
}

struct Panel {
    const char* label;
    int right, up;      // the components drawn to the right and up
    int depth;          // painted in this component's order (far first)
    bool near_is_high;  // the viewer sits on the + side of `depth`
    double left;        // the panel's left edge in the picture
};

double component(const Vec3& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

void draw_panel(std::ostream& svg, const GrainViews& g, const Panel& p, double half, double reach) {
    const double scale = 0.5 * kPanel / half;  // pixels per metre
    const double cx = p.left + 0.5 * kPanel, cy = kTop + 0.5 * kPanel;
    svg << "<rect x='" << p.left << "' y='" << kTop << "' width='" << kPanel << "' height='" << kPanel
        << "' fill='#f4f4f4' stroke='#888'/>\n";
    svg << "<text x='" << cx << "' y='" << kTop - 8 << "' text-anchor='middle' font-size='14'>" << p.label
        << "</text>\n";
    std::vector<std::size_t> order(g.position.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const double da = component(g.position[a], p.depth), db = component(g.position[b], p.depth);
        return p.near_is_high ? da < db : da > db;
    });
    for (std::size_t i : order) {
        const Vec3 r = g.position[i] - g.centre;
        const double t = reach > 0 ? norm(r) / reach : 0.0;
        svg << "<circle cx='" << num(cx + component(r, p.right) * scale) << "' cy='"
            << num(cy - component(r, p.up) * scale) << "' r='" << num(std::max(0.3, g.radius[i] * scale)) << "' fill='"
            << hex(viridis(t)) << "' stroke='#222' stroke-width='0.3'/>\n";
    }
    // The scale bar under the panel.
    const double bar = round_length(0.4 * half);
    const double y = kTop + kPanel + 22;
    svg << "<line x1='" << p.left << "' y1='" << y << "' x2='" << num(p.left + bar * scale) << "' y2='" << y
        << "' stroke='black' stroke-width='3'/>\n";
    svg << "<text x='" << num(p.left + bar * scale + 8) << "' y='" << y + 5 << "' font-size='13'>" << num(bar)
        << " m</text>\n";
}

void draw_colour_bar(std::ostream& svg, double left, double reach) {
    constexpr int kSteps = 64;
    for (int k = 0; k < kSteps; ++k) {
        const double t = (k + 0.5) / kSteps;
        svg << "<rect x='" << left << "' y='" << num(kTop + kPanel * (1 - double(k + 1) / kSteps)) << "' width='"
            << kBarWidth << "' height='" << num(kPanel / kSteps + 0.5) << "' fill='" << hex(viridis(t)) << "'/>\n";
    }
    svg << "<rect x='" << left << "' y='" << kTop << "' width='" << kBarWidth << "' height='" << kPanel
        << "' fill='none' stroke='#444'/>\n";
    const double step = round_length(reach / 3);
    for (double v = 0; v <= reach * (1 + 1e-9); v += step) {
        const double y = kTop + kPanel * (1 - v / reach);
        svg << "<line x1='" << left + kBarWidth << "' y1='" << num(y) << "' x2='" << left + kBarWidth + 5 << "' y2='"
            << num(y) << "' stroke='#444'/>\n";
        svg << "<text x='" << left + kBarWidth + 8 << "' y='" << num(y + 4) << "' font-size='12'>" << num(v)
            << "</text>\n";
    }
    const double x = left + kBarWidth + 52, y = kTop + 0.5 * kPanel;
    svg << "<text x='" << x << "' y='" << y << "' font-size='13' text-anchor='middle' transform='rotate(-90 " << x
        << " " << y << ")'>distance from the centre of mass (m)</text>\n";
}

}  // namespace

void write_grain_views(const std::string& path, const GrainViews& g) {
    if (g.position.size() != g.radius.size())
        throw std::invalid_argument("write_grain_views: " + std::to_string(g.position.size()) + " positions but " +
                                    std::to_string(g.radius.size()) + " radii");
    double half = 0, reach = 0;
    for (std::size_t i = 0; i < g.position.size(); ++i) {
        const Vec3 r = g.position[i] - g.centre;
        half = std::max({half, std::abs(r.x) + g.radius[i], std::abs(r.y) + g.radius[i], std::abs(r.z) + g.radius[i]});
        reach = std::max(reach, norm(r));
    }
    if (!(half > 0)) half = 1;
    half *= 1.05;
    const Panel along{"along the spin axis z (seen from +z; x right, y up)", 0, 1, 2, true, kMargin};
    const Panel across{"across it (seen from -y; x right, z up)", 0, 2, 1, false, kMargin + kPanel + kGap};
    const double width = across.left + kPanel + 110, height = kTop + kPanel + 45;
    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
        << "' font-family='sans-serif'>\n<rect width='100%' height='100%' fill='white'/>\n";
    svg << "<text x='" << kMargin << "' y='28' font-size='16'>" << svg_escape(g.title) << "</text>\n";
    svg << "<text x='" << kMargin << "' y='48' font-size='12' fill='#555'>" << g.position.size()
        << " grains; each drawn at its radius, nearer grains over farther ones</text>\n";
    draw_panel(svg, g, along, half, reach);
    draw_panel(svg, g, across, half, reach);
    draw_colour_bar(svg, across.left + kPanel + 14, reach > 0 ? reach : 1.0);
    svg << "</svg>\n";
    write_svg_document(path, svg.str(), 1.0);
}

}  // namespace mrjam
