// The plots' PNG twins (lib/io/svg_raster.hpp): write_svg's picture rendered by librsvg, read
// back with libpng's decoder and checked for its size, its background, its series where the
// plot puts them, and its text.
#include <doctest/doctest.h>
#include <png.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/png_image.hpp"
#include "io/svg_figure.hpp"
#include "io/svg_plot.hpp"
#include "io/svg_raster.hpp"
#include "test_support.hpp"

namespace {

struct Decoded {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    const std::uint8_t* at(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

Decoded decode(const std::string& path) {
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_file(&png, path.c_str()));
    png.format = PNG_FORMAT_RGB;
    Decoded d{static_cast<int>(png.width), static_cast<int>(png.height),
              std::vector<std::uint8_t>(PNG_IMAGE_SIZE(png))};
    REQUIRE(png_image_finish_read(&png, nullptr, d.rgb.data(), 0, nullptr));
    return d;
}

// Pixels within 40 of the colour in every channel (anti-aliased edges are farther), and their box.
struct Found {
    int count = 0, x_lo = 1 << 30, x_hi = -1, y_lo = 1 << 30, y_hi = -1;
};
Found find_colour(const Decoded& d, int r, int g, int b) {
    Found f;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x) {
            const std::uint8_t* p = d.at(x, y);
            if (std::abs(p[0] - r) > 40 || std::abs(p[1] - g) > 40 || std::abs(p[2] - b) > 40) continue;
            ++f.count;
            f.x_lo = std::min(f.x_lo, x), f.x_hi = std::max(f.x_hi, x);
            f.y_lo = std::min(f.y_lo, y), f.y_hi = std::max(f.y_hi, y);
        }
    return f;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("svg raster: every SVG plot has a PNG twin with its series, legend and text") {
        mrjam_test::TempDir dir("mrjam_svg_png");
        mrjam::Plot plot;
        plot.title = "Holding pressure";
        plot.x_label = "constriction";
        plot.y_label = "pressure (kPa)";
        mrjam::PlotSeries red{"rises", {0, 1, 2, 3}, {0, 1, 2, 3}, {}, {}, {}, "#d62728", true};
        mrjam::PlotSeries blue{"flat", {0, 1, 2, 3}, {1.5, 1.5, 1.5, 1.5}, {}, {}, {}, "#1f77b4"};
        plot.series = {red, blue};
        const std::string svg = dir.file("plot.svg");
        mrjam::write_svg(svg, plot);
        REQUIRE(mrjam::png_twin(svg) == dir.file("plot.png"));
        const Decoded d = decode(dir.file("plot.png"));
        // The SVG is 720 x 480 units, rendered at 2 pixels a unit.
        CHECK(d.width == 1440);
        CHECK(d.height == 960);
        const std::uint8_t* corner = d.at(2, 2);
        CHECK((corner[0] == 255 && corner[1] == 255 && corner[2] == 255));
        // The red line climbs from the plot area's lower left to its upper right (the frame is
        // 80..520 by 40..420 units, the legend to its right): a diagonal, so its box is wide and tall.
        const Found r = find_colour(d, 0xd6, 0x27, 0x28);
        CHECK(r.count > 1000);
        CHECK(r.x_lo >= 2 * 80 - 4);
        CHECK(r.y_hi <= 2 * 420 + 4);
        CHECK(r.y_lo >= 2 * 40 - 4);
        CHECK(r.x_hi - r.x_lo > 800);  // the line's span, and the legend's sample beyond the frame
        CHECK(r.y_hi - r.y_lo > 600);
        // The blue markers sit on one horizontal line at half the red line's height (plus the legend).
        const Found b = find_colour(d, 0x1f, 0x77, 0xb4);
        CHECK(b.count > 4 * 50);
        CHECK(b.x_hi > 2 * 520);  // the legend's marker, right of the frame
        // Text drawn with a font: dark pixels in the title's band above the frame.
        int dark_in_title = 0;
        for (int y = 2 * 8; y < 2 * 26; ++y)
            for (int x = 2 * 250; x < 2 * 470; ++x)
                if (d.at(x, y)[0] < 100 && d.at(x, y)[1] < 100 && d.at(x, y)[2] < 100) ++dark_in_title;
        CHECK(dark_in_title > 100);
    }

    TEST_CASE(
        "svg raster: a document that does not parse, or a folder that is not there, is an error naming the file") {
        mrjam_test::TempDir dir("mrjam_svg_png_bad");
        const std::string png = dir.file("bad.png");
        try {
            mrjam::write_png_from_svg("<svg width=\"10\" height=\"10\"><rect", png);
            FAIL("a truncated SVG was rendered");
        } catch (const std::runtime_error& e) {
            CHECK(std::string(e.what()).find(png) != std::string::npos);
        }
        CHECK_FALSE(std::filesystem::exists(png));
        const std::string fine = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"></svg>";
        CHECK_THROWS_AS(mrjam::write_png_from_svg(fine, dir.file("no_dir/a.png")), std::runtime_error);
        mrjam::write_png_from_svg(fine, png, 3.0);
        const Decoded d = decode(png);
        CHECK(d.width == 30);
        CHECK(d.height == 30);
    }

    TEST_CASE("svg figure: a scalar map's pixels, colour scale and scale bar reach the PNG; panels sit side by side") {
        mrjam_test::TempDir dir("mrjam_svg_map");
        // A 2 mm x 1 mm plane, 8 x 4 nodes: the left half at the scale's bottom, the right at its top.
        mrjam::ScalarMapFigure f;
        f.title = "two halves";
        f.nx = 8;
        f.ny = 4;
        for (int y = 0; y < f.ny; ++y)
            for (int x = 0; x < f.nx; ++x) f.values.push_back(x < 4 ? 0.0 : 300.0);
        f.width_m = 2e-3;
        f.height_m = 1e-3;
        f.vmin = 0;
        f.vmax = 300;
        f.unit = "|B| (mT)";
        const mrjam::SvgPanel panel = mrjam::scalar_map_panel(f);
        // Ticks every 100 mT (about five over the scale), a 0.5 mm bar (about a fifth of the width).
        for (const char* label : {">0<", ">100<", ">300<", ">0.5 mm<", ">|B| (mT)<"})
            CHECK_MESSAGE(panel.svg.find(label) != std::string::npos, std::string(label));
        const std::string svg = dir.file("map.svg");
        mrjam::write_figure(svg, panel.svg);
        const Decoded d = decode(mrjam::png_twin(svg));
        // The picture is 360 x 180 units from (20, 40), drawn at 2 pixels a unit; the embedded
        // PNG's colours must come through: viridis' ends in the two halves.
        const auto low = mrjam::viridis(0), high = mrjam::viridis(1);
        const std::uint8_t* left = d.at(2 * (20 + 90), 2 * (40 + 90));
        const std::uint8_t* right = d.at(2 * (20 + 270), 2 * (40 + 90));
        for (int c = 0; c < 3; ++c) {
            CHECK(std::abs(left[c] - low[c]) <= 3);
            CHECK(std::abs(right[c] - high[c]) <= 3);
        }
        // Side by side under a title: the row is as wide as the panels together.
        const std::string row = mrjam::svg_row("both", {panel, panel});
        CHECK(row.find("width=\"" + std::to_string(static_cast<int>(2 * panel.width))) != std::string::npos);
        CHECK(row.find("<svg x=\"" + std::to_string(static_cast<int>(panel.width)) + "\"") != std::string::npos);
        f.width_m = 0;
        CHECK_THROWS_AS(mrjam::scalar_map_panel(f), std::invalid_argument);
    }
}
