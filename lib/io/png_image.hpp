#pragma once
// 8-bit RGB images written as PNG through libpng's simplified API, and a colour-map renderer for
// scalar fields on a grid.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace mrjam {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // row-major, top row first, 3 bytes per pixel

    RgbImage() = default;
    // A width x height image filled with `fill` (white by default); throws on negative sizes.
    RgbImage(int w, int h, std::array<std::uint8_t, 3> fill = {255, 255, 255});

    // (x, y) with y = 0 the TOP row, as in the file. Out-of-range pixels are ignored (clipping).
    void set(int x, int y, std::array<std::uint8_t, 3> colour);
    std::array<std::uint8_t, 3> get(int x, int y) const;  // throws std::out_of_range outside
};

// Writes `image` as a PNG; throws std::runtime_error naming `path` if it cannot be written and
// std::invalid_argument if the image is empty or its pixel buffer has the wrong size (or
// std::runtime_error with libpng's message if it fails).
void write_png(const std::filesystem::path& path, const RgbImage& image);

// The PNG file contents, as write_png writes them (exposed for tests and in-memory use).
std::vector<std::uint8_t> encode_png(const RgbImage& image);

// Matplotlib's viridis (van der Walt & Smith, 2015; CC0), t clamped to [0, 1] (NaN -> 0),
// linearly interpolated between 9 samples: within ~3/255 of the 256-entry table.
std::array<std::uint8_t, 3> viridis(double t);

// Draws a nx x ny grid of values (x fastest, row y = 0 at the BOTTOM of the image) as squares
// of pixels_per_cell pixels, coloured with viridis over [vmin, vmax] (clamped; vmin == vmax maps
// everything to the middle colour). NaN cells are grey. With `with_colour_bar`, a vertical bar
// (vmin at the bottom, vmax at the top) is drawn to the right after a white gap. Throws
// std::invalid_argument on sizes that do not match or are not positive, or non-finite or
// inverted limits.
RgbImage render_scalar_map(const std::vector<double>& values, int nx, int ny, double vmin, double vmax,
                           int pixels_per_cell, bool with_colour_bar);

}  // namespace mrjam
