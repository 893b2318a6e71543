#include "jam/batch_outlet.hpp"

#include <algorithm>
#include <vector>

#include "core/format.hpp"
#include "grain_removal.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

BatchOutlet::BatchOutlet(const System& s, double z_end, double z_throat_exit, double largest_diameter) {
    const double r = 0.5 * largest_diameter;
    double reach = s.contacts.pair_cutoff(r, r);
    if (s.magnetic.enabled) reach = std::max(reach, s.magnetic.pairs.pair_cutoff(r, r));
    z_ = z_end - reach - largest_diameter;
    if (z_ < z_throat_exit + largest_diameter)
        throw SceneError("/model/downstream_length",
                         "a batch's outlet needs " + format_number((reach + 2 * largest_diameter) * 1e3) +
                             " mm of tube past the throat's exit (a grain's reach across the periodic seam and room "
                             "to leave); lengthen model/downstream_length or use supply \"periodic\"");
}

std::size_t BatchOutlet::drain(System& s, ThroatFlux& flux) const {
    const auto& x = s.particles.position;
    std::vector<char> out(x.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (x[i].z >= z_) {
            out[i] = 1;
            any = true;
        }
    if (!any) return 0;
    std::size_t kept = 0;
    const auto index = surviving_index(out, kept);
    flux.remove_grains(index, kept);
    return remove_grains(s, index, kept);
}

}  // namespace mrjam
