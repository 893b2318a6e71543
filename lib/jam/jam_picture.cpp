#include "jam/jam_picture.hpp"

#include <cmath>

#include "io/png_image.hpp"

namespace mrjam {

void write_throat_picture(const std::filesystem::path& path, const System& s, const ContactClusters& clusters,
                          const ValveGeometry& v, int width) {
    const double z0 = s.domain.lo.z, z1 = s.domain.hi.z, rb = v.bore_radius();
    const double scale = width / (z1 - z0);  // pixels per metre; z runs left to right
    const int height = static_cast<int>(std::ceil(2 * rb * scale)) + 1;
    RgbImage image(width, height);
    auto to_pixel = [&](double y, double z) {
        return std::pair{static_cast<int>((z - z0) * scale), static_cast<int>((rb - y) * scale)};
    };
    // The wall: everything outside the passage, in dark grey.
    for (int px = 0; px < width; ++px) {
        const double z = z0 + (px + 0.5) / scale;
        const double R = v.passage_half_height(z);  // the wall in the cut plane x = 0
        for (int py = 0; py < height; ++py) {
            const double y = rb - (py + 0.5) / scale;
            if (std::abs(y) >= R) image.set(px, py, {60, 60, 60});
        }
    }
    const auto& p = s.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.position[i].x, r = p.radius[i];
        if (std::abs(x) >= r) continue;
        const double rc = std::sqrt(r * r - x * x);  // radius of the cut disc
        std::array<std::uint8_t, 3> colour{170, 170, 170};
        if (clusters.label[i] == 0 && clusters.size[0] > 1)
            colour = {40, 90, 220};
        else if (clusters.size[clusters.label[i]] > 1)
            colour = {220, 50, 40};
        const auto [cx, cy] = to_pixel(p.position[i].y, p.position[i].z);
        const int reach = static_cast<int>(std::ceil(rc * scale));
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx)
                if ((dx * dx + dy * dy) <= rc * rc * scale * scale) image.set(cx + dx, cy + dy, colour);
    }
    write_png(path, image);
}

}  // namespace mrjam
