#include "io/png_image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

namespace mrjam {
namespace {

using Bytes = std::vector<std::uint8_t>;

void check_image(const RgbImage& image) {
    if (image.width <= 0 || image.height <= 0)
        throw std::invalid_argument("PNG image must have positive width and height, got " +
                                    std::to_string(image.width) + " x " + std::to_string(image.height));
    const std::size_t expected = 3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
    if (image.rgb.size() != expected)
        throw std::invalid_argument("PNG image pixel buffer has " + std::to_string(image.rgb.size()) +
                                    " bytes, expected " + std::to_string(expected));
}

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb kNanGrey{128, 128, 128};
constexpr Rgb kWhite{255, 255, 255};

// Fills the pixels_per_cell square of cell (i, j), j counted from the bottom of a grid of ny rows.
void fill_cell(RgbImage& image, int i, int j, int ny, int ppc, Rgb colour) {
    const int top = (ny - 1 - j) * ppc;
    for (int y = top; y < top + ppc; ++y)
        for (int x = i * ppc; x < (i + 1) * ppc; ++x) image.set(x, y, colour);
}

Rgb cell_colour(double v, double vmin, double vmax) {
    if (std::isnan(v)) return kNanGrey;
    if (vmax == vmin) return viridis(0.5);
    return viridis((v - vmin) / (vmax - vmin));  // +-inf clamp to the ends inside viridis
}

}  // namespace

RgbImage::RgbImage(int w, int h, std::array<std::uint8_t, 3> fill) : width(w), height(h) {
    if (w < 0 || h < 0) throw std::invalid_argument("image size must not be negative");
    rgb.resize(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (std::size_t i = 0; i < rgb.size(); i += 3) std::copy(fill.begin(), fill.end(), rgb.begin() + i);
}

void RgbImage::set(int x, int y, std::array<std::uint8_t, 3> colour) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x);
    std::copy(colour.begin(), colour.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i));
}

std::array<std::uint8_t, 3> RgbImage::get(int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height) throw std::out_of_range("pixel outside the image");
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

std::vector<std::uint8_t> encode_png(const RgbImage& image) {
    check_image(image);
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    png.width = static_cast<png_uint_32>(image.width);
    png.height = static_cast<png_uint_32>(image.height);
    png.format = PNG_FORMAT_RGB;
    // Two passes, as libpng's simplified API asks: the size first, then the bytes.
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgb.data(), 0, nullptr))
        throw std::runtime_error(std::string("libpng could not encode the image: ") + png.message);
    Bytes out(size);
    if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgb.data(), 0, nullptr))
        throw std::runtime_error(std::string("libpng could not encode the image: ") + png.message);
    out.resize(size);
    return out;
}

void write_png(const std::filesystem::path& path, const RgbImage& image) {
    const Bytes bytes = encode_png(image);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open PNG file " + path.string() + " for writing");
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw std::runtime_error("failed writing PNG file " + path.string());
}

std::array<std::uint8_t, 3> viridis(double t) {
    // Matplotlib's viridis sampled at t = 0, 1/8, ..., 1 (the 256-entry table, rounded to 8 bits).
    static constexpr std::array<Rgb, 9> kStops{{{68, 1, 84},
                                                {71, 44, 122},
                                                {59, 81, 139},
                                                {44, 113, 142},
                                                {33, 144, 141},
                                                {39, 173, 129},
                                                {92, 200, 99},
                                                {170, 220, 50},
                                                {253, 231, 37}}};
    if (!(t > 0)) t = 0;  // also NaN
    if (t > 1) t = 1;
    const double s = t * (kStops.size() - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(s), kStops.size() - 2);
    const double f = s - static_cast<double>(i);
    Rgb c{};
    for (int k = 0; k < 3; ++k)
        c[k] = static_cast<std::uint8_t>(std::lround((1 - f) * kStops[i][k] + f * kStops[i + 1][k]));
    return c;
}

RgbImage render_scalar_map(const std::vector<double>& values, int nx, int ny, double vmin, double vmax,
                           int pixels_per_cell, bool with_colour_bar) {
    if (nx <= 0 || ny <= 0 || pixels_per_cell <= 0)
        throw std::invalid_argument("scalar map needs positive nx, ny and pixels_per_cell");
    if (values.size() != static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny))
        throw std::invalid_argument("scalar map has " + std::to_string(values.size()) + " values, expected nx*ny = " +
                                    std::to_string(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny)));
    if (!std::isfinite(vmin) || !std::isfinite(vmax) || vmax < vmin)
        throw std::invalid_argument("scalar map needs finite limits with vmin <= vmax");

    const int map_w = nx * pixels_per_cell, map_h = ny * pixels_per_cell;
    // The bar is as wide as two cells but never thinner than 8 pixels, after a one-cell gap
    // (at least 4 pixels) so it cannot be mistaken for the last column of the map.
    const int gap = std::max(4, pixels_per_cell), bar = std::max(8, 2 * pixels_per_cell);
    RgbImage image(with_colour_bar ? map_w + gap + bar : map_w, map_h, kWhite);

    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            fill_cell(image, i, j, ny, pixels_per_cell,
                      cell_colour(values[static_cast<std::size_t>(j) * nx + i], vmin, vmax));

    if (with_colour_bar)
        for (int y = 0; y < map_h; ++y) {  // top row vmax, bottom row vmin
            const Rgb c = viridis(map_h == 1 ? 0.5 : static_cast<double>(map_h - 1 - y) / (map_h - 1));
            for (int x = map_w + gap; x < image.width; ++x) image.set(x, y, c);
        }
    return image;
}

}  // namespace mrjam
