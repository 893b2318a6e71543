#include "terms/pair_damping_term.hpp"

#include "system.hpp"

namespace mrjam {

// Serial: it is off by default and, when on, cheap next to the contact law.
void PairDampingTerm::add(System& s) {
    Particles& p = s.particles;
    const NeighborList& list = s.contacts;
    const double c = coefficient_;
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i) {
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            if (!list.touching[k]) continue;
            const std::uint32_t j = list.partners[k];
            if (p.raft[i] >= 0 && p.raft[j] >= 0) continue;
            const Vec3 f = (p.velocity[i] - p.velocity[j] + list.image_velocity(list.image[k])) * (-c);
            p.force[i] += f;
            p.force[j] -= f;
            if (p.raft[i] >= 0) s.rafts[p.raft[i]].force += f;
            if (p.raft[j] >= 0) s.rafts[p.raft[j]].force -= f;
        }
    }
}

double pair_damping_coefficient(const System& s) {
    const PairDampingTerm* t = s.terms.find<PairDampingTerm>();
    return t ? t->coefficient() : 0.0;
}

}  // namespace mrjam
