// The PNG writer (lib/io/png_image.hpp), checked by reading its files back with libpng's reader
// (an independent decoder path: signature, chunk CRCs, inflate and unfiltering all checked by it).
#include <doctest/doctest.h>
#include <png.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/png_image.hpp"
#include "test_support.hpp"

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes read_bytes(const std::string& path) {
    const std::string s = mrjam_test::slurp(path);
    return Bytes(s.begin(), s.end());
}

// A deterministic image whose bytes differ from pixel to pixel.
mrjam::RgbImage pattern(int w, int h) {
    mrjam::RgbImage img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.set(x, y,
                    {static_cast<std::uint8_t>(x * 7 + y), static_cast<std::uint8_t>(y * 13 + 5),
                     static_cast<std::uint8_t>((x ^ y) * 3)});
    return img;
}

// Writes the image, checks the file is what encode_png gives, decodes it with libpng and checks
// the size, the format and every pixel; returns the decoded pixels.
Bytes round_trip(const mrjam::RgbImage& img) {
    mrjam_test::TempDir dir("mrjam_png");
    const std::string path = dir.file("image.png");
    mrjam::write_png(path, img);
    const Bytes file = read_bytes(path);
    CHECK(file == mrjam::encode_png(img));
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    REQUIRE(png_image_begin_read_from_memory(&png, file.data(), file.size()));
    CHECK(png.width == static_cast<png_uint_32>(img.width));
    CHECK(png.height == static_cast<png_uint_32>(img.height));
    CHECK((png.format & PNG_FORMAT_FLAG_COLOR) != 0);
    CHECK((png.format & PNG_FORMAT_FLAG_ALPHA) == 0);
    png.format = PNG_FORMAT_RGB;
    Bytes pixels(PNG_IMAGE_SIZE(png));
    REQUIRE(png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr));
    CHECK(pixels == img.rgb);
    return pixels;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("png: images round-trip through libpng's reader, pixel for pixel") {
        round_trip(pattern(5, 3));
        round_trip(pattern(1, 1));
        round_trip(pattern(200, 150));  // image data above one 64 KiB deflate block
        round_trip(pattern(21845, 1));  // a single row longer than that
    }

    TEST_CASE("png: the image data is compressed") {
        // A uniform 200 x 150 image is 90,150 bytes of scanlines; deflate takes it to a few hundred.
        const mrjam::RgbImage flat(200, 150, {10, 200, 30});
        CHECK(mrjam::encode_png(flat).size() < 2000);
        CHECK(round_trip(flat).size() == flat.rgb.size());
    }

    TEST_CASE("png: errors name the path; malformed images are refused") {
        mrjam_test::TempDir dir("mrjam_png");
        const std::string bad = dir.file("no_such_dir/out.png");
        try {
            mrjam::write_png(bad, pattern(2, 2));
            FAIL("expected std::runtime_error");
        } catch (const std::runtime_error& e) {
            CHECK(std::string(e.what()).find(bad) != std::string::npos);
        }
        mrjam::RgbImage broken = pattern(2, 2);
        broken.rgb.pop_back();
        CHECK_THROWS_AS(mrjam::encode_png(broken), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::encode_png(mrjam::RgbImage{}), std::invalid_argument);
    }

    TEST_CASE("png: viridis endpoints, clamping and monotone lightness") {
        using Rgb = std::array<std::uint8_t, 3>;
        CHECK(mrjam::viridis(0) == Rgb{68, 1, 84});
        CHECK(mrjam::viridis(1) == Rgb{253, 231, 37});
        CHECK(mrjam::viridis(-3) == mrjam::viridis(0));
        CHECK(mrjam::viridis(7) == mrjam::viridis(1));
        CHECK(mrjam::viridis(std::nan("")) == mrjam::viridis(0));
        CHECK(mrjam::viridis(0.5) == Rgb{33, 144, 141});
        // Viridis is designed with lightness increasing monotonically; the green channel carries most
        // of it and must never decrease along the map.
        int previous = -1;
        for (int i = 0; i <= 100; ++i) {
            const int g = mrjam::viridis(i / 100.0)[1];
            CHECK(g >= previous);
            previous = g;
        }
    }

    TEST_CASE("png: scalar map puts row y = 0 at the bottom, NaN grey, colour bar on the right") {
        const int nx = 3, ny = 2, ppc = 4;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        // x fastest: row y = 0 is {0, 1, 2}, row y = 1 is {3, NaN, 10 (clamped to vmax)}.
        const std::vector<double> values{0, 1, 2, 3, nan, 10};
        const mrjam::RgbImage plain = mrjam::render_scalar_map(values, nx, ny, 0, 4, ppc, false);
        CHECK(plain.width == nx * ppc);
        CHECK(plain.height == ny * ppc);
        auto cell = [&](const mrjam::RgbImage& img, int i, int j, int dx, int dy) {
            return img.get(i * ppc + dx, (ny - 1 - j) * ppc + dy);
        };
        for (const int d : {0, ppc - 1}) {  // every corner pixel of each cell
            CHECK(cell(plain, 0, 0, d, d) == mrjam::viridis(0));
            CHECK(cell(plain, 1, 0, d, 0) == mrjam::viridis(0.25));
            CHECK(cell(plain, 2, 0, 0, d) == mrjam::viridis(0.5));
            CHECK(cell(plain, 0, 1, d, d) == mrjam::viridis(0.75));
            CHECK(cell(plain, 1, 1, d, d) == std::array<std::uint8_t, 3>{128, 128, 128});
            CHECK(cell(plain, 2, 1, d, d) == mrjam::viridis(1));
        }
        CHECK(plain.get(0, plain.height - 1) == mrjam::viridis(0));  // bottom-left pixel is value[0]

        const mrjam::RgbImage bar = mrjam::render_scalar_map(values, nx, ny, 0, 4, ppc, true);
        CHECK(bar.width > plain.width);
        CHECK(bar.height == plain.height);
        CHECK(bar.get(bar.width - 1, 0) == mrjam::viridis(1));                         // top of the bar: vmax
        CHECK(bar.get(bar.width - 1, bar.height - 1) == mrjam::viridis(0));            // bottom: vmin
        CHECK(bar.get(plain.width, 0) == std::array<std::uint8_t, 3>{255, 255, 255});  // the gap
        for (int y = 0; y < plain.height; ++y)
            for (int x = 0; x < plain.width; ++x) CHECK(bar.get(x, y) == plain.get(x, y));

        round_trip(bar);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, 4, 2, 0, 1, 1, false), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, nx, ny, 1, 0, 1, false), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::render_scalar_map(values, nx, ny, 0, 1, 0, false), std::invalid_argument);
    }
}
