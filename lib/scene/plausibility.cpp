#include "scene/plausibility.hpp"

#include <algorithm>
#include <cmath>

#include "core/format.hpp"
#include "scene/scene_node.hpp"
#include "terms/gravity_term.hpp"

namespace mrjam {

namespace {

void check_starting_speeds(const Scene& scene) {
    const double dt = scene.system.dt;
    for (std::size_t b = 0; b < scene.batch_speed_over_radius.size(); ++b) {
        const double k = scene.batch_speed_over_radius[b];
        if (!(k * dt > 0.5)) continue;
        throw SceneError("/grains/" + std::to_string(b),
                         "a grain starts fast enough to cross " + format_number(k * dt, 3) +
                             " of its radius in one step of " + format_number(dt, 3) +
                             " s (half is the most a contact can resolve): check the units of velocity or "
                             "random_velocity");
    }
}

// The Hertz overlap of the heaviest grain resting on a like one under its own weight:
// m g = (4/3) Y* sqrt(R/2) d^(3/2).
void check_gravity(const System& s) {
    const GravityTerm* g = s.terms.find<GravityTerm>();
    const Particles& p = s.particles;
    if (!g || p.size() == 0) return;
    const double a = norm(g->acceleration());
    double r_min = p.radius[0];
    std::size_t heaviest = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        r_min = std::min(r_min, p.radius[i]);
        if (p.mass[i] > p.mass[heaviest]) heaviest = i;
    }
    if (a * s.dt * s.dt > 0.1 * r_min)
        throw SceneError("/gravity", "a grain would fall " + format_number(a * s.dt * s.dt / r_min, 3) +
                                         " of the smallest radius in one step of " + format_number(s.dt, 3) +
                                         " s: check gravity's units (" + format_number(a, 3) + " m/s2)");
    if (!s.physics.contact) return;
    const double r = p.radius[heaviest];
    const double ystar = s.pairs(p.material[heaviest], p.material[heaviest]).effective_youngs;
    const double overlap = std::pow(p.mass[heaviest] * a / (4.0 / 3.0 * ystar * std::sqrt(0.5 * r)), 2.0 / 3.0);
    if (overlap > s.max_overlap_fraction * r)
        throw SceneError("/gravity", "under " + format_number(a, 3) +
                                         " m/s2 the heaviest grain's weight alone would press it " +
                                         format_number(overlap / r, 3) + " of its radius into a neighbour, past " +
                                         "run/max_overlap_fraction (" + format_number(s.max_overlap_fraction) +
                                         "): check gravity's units, or stiffen the material");
}

}  // namespace

void check_plausible_motion(const Scene& scene) {
    check_starting_speeds(scene);
    check_gravity(scene.system);
}

}  // namespace mrjam
