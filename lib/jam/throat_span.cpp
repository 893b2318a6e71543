#include "jam/throat_span.hpp"

#include <cmath>

namespace mrjam {

bool cluster_spans_throat(const System& s, const ContactClusters& c, const ValveGeometry& v, const Wall& wall) {
    if (c.size.empty() || c.size[0] < 2) return false;
    bool upper = false, lower = false;
    const auto& p = s.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (c.label[i] != 0) continue;
        const Vec3& x = p.position[i];
        if (x.z < v.taper_start_z() - p.radius[i] || x.z > v.throat_end_z() + p.radius[i]) continue;
        double overlap;
        Vec3 n;
        if (!wall.touch(x, p.radius[i] * 1.05, overlap, n)) continue;  // touching, with 5 % slack
        if (v.is_slot()) {
            // Across the slot's gap: its faces along the field (y), not the narrow side faces.
            if (std::abs(n.y) <= std::abs(n.x)) continue;
            if (n.y < 0) upper = true;
            if (n.y > 0) lower = true;
            continue;
        }
        if (x.y > 0) upper = true;
        if (x.y < 0) lower = true;
    }
    return upper && lower;
}

}  // namespace mrjam
