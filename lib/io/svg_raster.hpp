#pragma once
// SVG pictures rendered to PNG with librsvg and cairo (Debian's librsvg2-dev), for readers and
// tools that show PNG but not SVG: every plot mrjam writes as SVG gets a PNG twin beside it.
#include <string>

namespace mrjam {

// Renders the SVG document `svg` (UTF-8 text) on white at `scale` pixels per SVG unit and writes
// it to `png_path`; throws std::runtime_error naming the file and librsvg's or cairo's message.
void write_png_from_svg(const std::string& svg, const std::string& png_path, double scale = 2.0);

// The PNG twin of an SVG file: the same path with the extension .png.
std::string png_twin(const std::string& svg_path);

// Writes the SVG document to `path` and its PNG twin beside it at `scale`; throws
// std::runtime_error naming the file that could not be written.
void write_svg_document(const std::string& path, const std::string& svg, double scale = 2.0);

}  // namespace mrjam
