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
// the declarations come from their headers, the functions through dlsym.
struct Raster {
    decltype(&::rsvg_handle_new_from_data) new_from_data = nullptr;
    decltype(&::rsvg_handle_get_intrinsic_size_in_pixels) intrinsic_size = nullptr;
    decltype(&::rsvg_handle_render_document) render_document = nullptr;
    decltype(&::g_object_unref) object_unref = nullptr;
    decltype(&::cairo_image_surface_create) image_surface_create = nullptr;
    decltype(&::cairo_surface_flush) surface_flush = nullptr;
    decltype(&::cairo_surface_write_to_png) write_to_png = nullptr;
    decltype(&::cairo_surface_destroy) surface_destroy = nullptr;
    decltype(&::cairo_status_to_string) status_to_string = nullptr;
    decltype(&::cairo_create) create = nullptr;
    decltype(&::cairo_destroy) destroy = nullptr;
    decltype(&::cairo_set_source_rgb) set_source_rgb = nullptr;
    decltype(&::cairo_paint) paint = nullptr;
};

Raster load() {
    const std::string fix = "install librsvg with bash scripts/install-deps.sh";
    const SharedLibrary rsvg = SharedLibrary::open<std::runtime_error>(MRJAM_RSVG_SONAME, MRJAM_RSVG_PATH, fix);
    Raster r;
    rsvg.resolve<std::runtime_error>(r.new_from_data, "rsvg_handle_new_from_data", fix);
    rsvg.resolve<std::runtime_error>(r.intrinsic_size, "rsvg_handle_get_intrinsic_size_in_pixels", fix);
    rsvg.resolve<std::runtime_error>(r.render_document, "rsvg_handle_render_document", fix);
    // GObject and cairo are librsvg's own dependencies: found through its handle.
    rsvg.resolve<std::runtime_error>(r.object_unref, "g_object_unref", fix);
    rsvg.resolve<std::runtime_error>(r.image_surface_create, "cairo_image_surface_create", fix);
    rsvg.resolve<std::runtime_error>(r.surface_flush, "cairo_surface_flush", fix);
    rsvg.resolve<std::runtime_error>(r.write_to_png, "cairo_surface_write_to_png", fix);
    rsvg.resolve<std::runtime_error>(r.surface_destroy, "cairo_surface_destroy", fix);
    rsvg.resolve<std::runtime_error>(r.status_to_string, "cairo_status_to_string", fix);
    rsvg.resolve<std::runtime_error>(r.create, "cairo_create", fix);
    rsvg.resolve<std::runtime_error>(r.destroy, "cairo_destroy", fix);
    rsvg.resolve<std::runtime_error>(r.set_source_rgb, "cairo_set_source_rgb", fix);
    rsvg.resolve<std::runtime_error>(r.paint, "cairo_paint", fix);
    return r;
}

const Raster& raster() {
    static const Raster r = load();
    return r;
}

struct HandleFree {
    void operator()(RsvgHandle* h) const { raster().object_unref(h); }
};
struct SurfaceFree {
    void operator()(cairo_surface_t* s) const { raster().surface_destroy(s); }
};
struct ContextFree {
    void operator()(cairo_t* c) const { raster().destroy(c); }
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
        r.new_from_data(reinterpret_cast<const guint8*>(svg.data()), svg.size(), &error));
    if (!handle) fail(png_path, "the SVG does not parse", error);
    double width = 0, height = 0;
    if (!r.intrinsic_size(handle.get(), &width, &height) || width <= 0 || height <= 0)
        throw std::runtime_error("cannot render " + png_path + ": the SVG has no width and height in pixels");
    const int w = static_cast<int>(std::ceil(width * scale)), h = static_cast<int>(std::ceil(height * scale));
    std::unique_ptr<cairo_surface_t, SurfaceFree> surface(r.image_surface_create(CAIRO_FORMAT_RGB24, w, h));
    std::unique_ptr<cairo_t, ContextFree> cr(r.create(surface.get()));
    r.set_source_rgb(cr.get(), 1, 1, 1);  // white under a transparent SVG
    r.paint(cr.get());
    const RsvgRectangle viewport{0, 0, static_cast<double>(w), static_cast<double>(h)};
    if (!r.render_document(handle.get(), cr.get(), &viewport, &error)) fail(png_path, "librsvg", error);
    r.surface_flush(surface.get());
    const cairo_status_t status = r.write_to_png(surface.get(), png_path.c_str());
    if (status != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error("cannot write " + png_path + ": " + r.status_to_string(status));
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
