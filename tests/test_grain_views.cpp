// The body pictures (lib/io/grain_views.hpp): read back as text, the discs' number, colours,
// positions and painting order, the colour bar's range and the scale bar.
#include <doctest/doctest.h>

#include <cstdio>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/grain_views.hpp"
#include "io/png_image.hpp"
#include "test_support.hpp"

namespace {

std::string hex(std::array<std::uint8_t, 3> c) {
    char b[8];
    std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
    return b;
}

struct Disc {
    double cx, cy, r;
    std::string fill;
};

std::vector<Disc> discs(const std::string& svg) {
    std::vector<Disc> out;
    const std::regex circle("<circle cx='([^']+)' cy='([^']+)' r='([^']+)' fill='([^']+)'");
    for (auto it = std::sregex_iterator(svg.begin(), svg.end(), circle); it != std::sregex_iterator(); ++it)
        out.push_back({std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]), (*it)[4]});
    return out;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("grain views: two panels of discs coloured by distance, painted far to near, with both bars") {
        mrjam_test::TempDir dir("mrjam_views");
        mrjam::GrainViews g;
        g.title = "a <test> & body";
        // The centre grain and one 2 m out along +x, one 1 m out along +z (nearer the +z viewer).
        g.position = {{10, 20, 30}, {12, 20, 30}, {10, 20, 31}};
        g.radius = {0.5, 0.5, 0.5};
        g.centre = {10, 20, 30};
        const std::string path = dir.file("views.svg");
        mrjam::write_grain_views(path, g);
        const std::string svg = mrjam_test::slurp(path);
        CHECK(mrjam_test::slurp(dir.file("views.png")).rfind("\x89PNG", 0) == 0);
        const std::vector<Disc> d = discs(svg);
        REQUIRE(d.size() == 6);  // every grain in each panel
        // Panel 1 (seen from +z) paints in increasing z: the z = 31 grain last. Its colour is the
        // distance 1 of a farthest 2: viridis(0.5); the centre grain's is viridis(0).
        CHECK(d[2].fill == hex(mrjam::viridis(0.5)));
        CHECK(d[0].fill == hex(mrjam::viridis(0)));
        CHECK(d[1].fill == hex(mrjam::viridis(1)));
        // x runs right in both panels: the +x grain sits right of the centre one, at the same height
        // in panel 1 (y up), and the +z grain sits above the centre in panel 2 (z up; y is depth).
        CHECK(d[1].cx > d[0].cx);
        CHECK(d[1].cy == doctest::Approx(d[0].cy));
        const Disc* centre2 = nullptr;
        const Disc* up2 = nullptr;
        for (std::size_t k = 3; k < 6; ++k) {
            if (d[k].fill == hex(mrjam::viridis(0))) centre2 = &d[k];
            if (d[k].fill == hex(mrjam::viridis(0.5))) up2 = &d[k];
        }
        REQUIRE(centre2);
        REQUIRE(up2);
        CHECK(up2->cy < centre2->cy);
        // Drawn at their radius: 2 m (+ radius, + 5 %) fills half a panel of 420 px.
        CHECK(d[0].r == doctest::Approx(0.5 * 210 / (2.5 * 1.05)).epsilon(1e-3));
        // The title escaped, the colour bar labelled in metres, a scale bar in metres.
        CHECK(svg.find("a &lt;test&gt; &amp; body") != std::string::npos);
        CHECK(svg.find("distance from the centre of mass (m)") != std::string::npos);
        CHECK(svg.find(">1 m</text>") != std::string::npos);  // 0.4 x 2.625 m rounds down to 1 m
    }

    TEST_CASE("grain views: mismatched input and unwritable paths are refused") {
        mrjam_test::TempDir dir("mrjam_views");
        mrjam::GrainViews g;
        g.position = {{0, 0, 0}};
        CHECK_THROWS_AS(mrjam::write_grain_views(dir.file("a.svg"), g), std::invalid_argument);
        g.radius = {1};
        CHECK_THROWS_AS(mrjam::write_grain_views(dir.file("no_dir/a.svg"), g), std::runtime_error);
    }
}
