#include "io/svg_raster.hpp"

#include <cairo.h>
#include <librsvg/rsvg.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "core/shared_library.hpp"

namespace mrjam {

namespace {

// librsvg and the cairo it draws with, opened on the first rendering (core/shared_library.hpp);
// the declarations come from their headers, the functions through dlsym. GObject and cairo are
// librsvg's own dependencies, found through its handle. One list names every function once.
// clang-format off
#define MRJAM_RASTER_FUNCTIONS(X) \
    X(rsvg_handle_new_from_data) \
    X(rsvg_handle_get_intrinsic_size_in_pixels) \
    X(rsvg_handle_render_document) \
    X(g_object_unref) \
    X(cairo_image_surface_create) \
    X(cairo_surface_flush) \
    X(cairo_surface_write_to_png) \
    X(cairo_surface_destroy) \
    X(cairo_status_to_string) \
    X(cairo_create) \
    X(cairo_destroy) \
    X(cairo_set_source_rgb) \
    X(cairo_paint)
// clang-format on

struct Raster {
#define MRJAM_RASTER_POINTER(name) decltype(&::name) name = nullptr;
    MRJAM_RASTER_FUNCTIONS(MRJAM_RASTER_POINTER)
#undef MRJAM_RASTER_POINTER
};

Raster load() {
    const std::string fix = "install librsvg with bash scripts/install-deps.sh";
    const SharedLibrary rsvg = SharedLibrary::open<std::runtime_error>(MRJAM_RSVG_SONAME, MRJAM_RSVG_PATH, fix);
    Raster r;
#define MRJAM_RASTER_RESOLVE(name) rsvg.resolve<std::runtime_error>(r.name, #name, fix);
    MRJAM_RASTER_FUNCTIONS(MRJAM_RASTER_RESOLVE)
#undef MRJAM_RASTER_RESOLVE
    return r;
}

const Raster& raster() {
    static const Raster r = load();
    return r;
}

struct HandleFree {
    void operator()(RsvgHandle* h) const { raster().g_object_unref(h); }
};
struct SurfaceFree {
    void operator()(cairo_surface_t* s) const { raster().cairo_surface_destroy(s); }
};
struct ContextFree {
    void operator()(cairo_t* c) const { raster().cairo_destroy(c); }
};

// librsvg's GError as an exception naming the file.
[[noreturn]] void fail(const std::string& png_path, const char* what, GError* error) {
    const std::string message = error ? error->message : "unknown error";
    if (error) g_error_free(error);
    throw std::runtime_error("cannot render " + png_path + ": " + what + ": " + message);
}

}  // namespace

void write_png_from_svg(const std::string& svg, const std::string& png_path, double scale) {
    const Raster& r = raster();
    GError* error = nullptr;
    std::unique_ptr<RsvgHandle, HandleFree> handle(
        r.rsvg_handle_new_from_data(reinterpret_cast<const guint8*>(svg.data()), svg.size(), &error));
    if (!handle) fail(png_path, "the SVG does not parse", error);
    double width = 0, height = 0;
    if (!r.rsvg_handle_get_intrinsic_size_in_pixels(handle.get(), &width, &height) || width <= 0 || height <= 0)
        throw std::runtime_error("cannot render " + png_path + ": the SVG has no width and height in pixels");
    const int w = static_cast<int>(std::ceil(width * scale)), h = static_cast<int>(std::ceil(height * scale));
    std::unique_ptr<cairo_surface_t, SurfaceFree> surface(r.cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h));
    std::unique_ptr<cairo_t, ContextFree> cr(r.cairo_create(surface.get()));
    r.cairo_set_source_rgb(cr.get(), 1, 1, 1);  // white under a transparent SVG
    r.cairo_paint(cr.get());
    const RsvgRectangle viewport{0, 0, static_cast<double>(w), static_cast<double>(h)};
    if (!r.rsvg_handle_render_document(handle.get(), cr.get(), &viewport, &error)) fail(png_path, "librsvg", error);
    r.cairo_surface_flush(surface.get());
    const cairo_status_t status = r.cairo_surface_write_to_png(surface.get(), png_path.c_str());
    if (status != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error("cannot write " + png_path + ": " + r.cairo_status_to_string(status));
}

std::string png_twin(const std::string& svg_path) {
    return std::filesystem::path(svg_path).replace_extension(".png").string();
}

void write_svg_document(const std::string& path, const std::string& svg, double scale) {
    {
        std::ofstream f(path);
        f << svg;
        if (!f) throw std::runtime_error("cannot write " + path);
    }
    write_png_from_svg(svg, png_twin(path), scale);
}

}  // namespace mrjam
