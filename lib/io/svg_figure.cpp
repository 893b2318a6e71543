#include "io/svg_figure.hpp"

#include <glib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "io/png_image.hpp"
#include "io/svg_raster.hpp"

namespace mrjam {

namespace {

std::string hex(const std::array<std::uint8_t, 3>& c) {
    char b[8];
    std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
    return b;
}

// The map's pixels as a PNG data URI (GLib's Base64, already loaded with librsvg).
std::string png_data_uri(const ScalarMapFigure& f) {
    const std::vector<std::uint8_t> png = encode_png(render_scalar_map(f.values, f.nx, f.ny, f.vmin, f.vmax, 1, false));
    gchar* encoded = g_base64_encode(png.data(), png.size());
    std::string uri = std::string("data:image/png;base64,") + encoded;
    g_free(encoded);
    return uri;
}

// A round length (1, 2 or 5 times a power of ten) near a fifth of `extent`, and its label.
std::pair<double, std::string> scale_length(double extent) {
    const double length = nice_step(extent, 5);
    if (length >= 1e-4) return {length, svg_number(length * 1e3) + " mm"};
    return {length, svg_number(length * 1e6) + " um"};
}

// A vertical viridis bar at (x, y), `height` tall, vmin at the bottom, with ticks and the unit.
void colour_bar(std::ostringstream& o, const ScalarMapFigure& f, double x, double y, double height) {
    o << "<defs><linearGradient id=\"viridis\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (int k = 0; k <= 8; ++k)
        o << "<stop offset=\"" << k / 8.0 << "\" stop-color=\"" << hex(viridis(k / 8.0)) << "\"/>";
    o << "</linearGradient></defs>\n";
    o << "<rect x=\"" << x << "\" y=\"" << y << "\" width=\"16\" height=\"" << height
      << "\" fill=\"url(#viridis)\" stroke=\"black\"/>\n";
    const double span = f.vmax - f.vmin, step = nice_step(span, 5);
    for (double t = std::ceil(f.vmin / step) * step; t <= f.vmax + 1e-9 * step; t += step) {
        const double ty = y + height * (1 - (t - f.vmin) / span);
        o << "<line x1=\"" << x + 16 << "\" y1=\"" << ty << "\" x2=\"" << x + 20 << "\" y2=\"" << ty
          << "\" stroke=\"black\"/>\n<text x=\"" << x + 23 << "\" y=\"" << ty + 4 << "\">" << svg_number(t)
          << "</text>\n";
    }
    o << "<text x=\"" << x << "\" y=\"" << y - 8 << "\">" << svg_escape(f.unit) << "</text>\n";
}

}  // namespace

SvgPanel scalar_map_panel(const ScalarMapFigure& f) {
    if (!(f.width_m > 0) || !(f.height_m > 0))
        throw std::invalid_argument("scalar map figure: the plane's extent must be positive");
    if (!(f.vmax > f.vmin)) throw std::invalid_argument("scalar map figure: vmax must exceed vmin");
    // The picture at most 360 x 360 units, in the plane's proportions.
    const double scale = 360.0 / std::max(f.width_m, f.height_m);
    const double pw = f.width_m * scale, ph = f.height_m * scale;
    const double left = 20, top = 40, bar_gap = 20;
    // Wide enough for the caption too (about 6.5 units a character at 12 px sans-serif).
    const double W = std::max(left + pw + bar_gap + 90, 2 * left + 6.5 * static_cast<double>(f.caption.size()));
    const double H = top + ph + 70;
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"" << W
      << "\" height=\"" << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << left + pw / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" << svg_escape(f.title)
      << "</text>\n";
    o << "<image x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" xlink:href=\"" << png_data_uri(f)
      << "\"/>\n";
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    colour_bar(o, f, left + pw + bar_gap, top, ph);
    const auto [length, label] = scale_length(f.width_m);
    const double sy = top + ph + 20;
    o << "<line x1=\"" << left << "\" y1=\"" << sy << "\" x2=\"" << left + length * scale << "\" y2=\"" << sy
      << "\" stroke=\"black\" stroke-width=\"3\"/>\n<text x=\"" << left + length * scale + 8 << "\" y=\"" << sy + 4
      << "\">" << label << "</text>\n";
    if (!f.caption.empty())
        o << "<text x=\"" << left << "\" y=\"" << sy + 28 << "\">" << svg_escape(f.caption) << "</text>\n";
    o << "</svg>\n";
    return {o.str(), W, H};
}

std::string svg_row(const std::string& title, const std::vector<SvgPanel>& panels) {
    double W = 0, H = 0;
    for (const SvgPanel& p : panels) {
        W += p.width;
        H = std::max(H, p.height);
    }
    const double top = 36;
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"" << W
      << "\" height=\"" << H + top << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << W / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">" << svg_escape(title)
      << "</text>\n";
    double x = 0;
    for (const SvgPanel& p : panels) {
        // A nested <svg> is positioned by its own x and y, written into the panel's root element
        // (after an XML declaration, if the panel was read from a file that has one).
        const std::size_t root = p.svg.find("<svg");
        if (root == std::string::npos) throw std::invalid_argument("svg_row: a panel without an <svg> element");
        o << "<svg x=\"" << x << "\" y=\"" << top << "\"" << p.svg.substr(root + 4);
        x += p.width;
    }
    o << "</svg>\n";
    return o.str();
}

void write_figure(const std::string& path, const std::string& svg) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    write_svg_document(path, svg);
}

}  // namespace mrjam
