#include "integrator.hpp"

#include <cmath>
#include <sstream>

#include "forces.hpp"

namespace mrjam {
namespace {

// First half kick fused with the drift and the neighbour-list displacement test: one pass over
// the grains instead of three. Returns true when the list must be rebuilt.
bool kick_drift(System& s) {
    Particles& p = s.particles;
    const double h = 0.5 * s.dt, dt = s.dt;
    const std::size_t n = p.size();
    int moved = p.size() + 1 != s.contacts.offsets.size();
#pragma omp parallel for schedule(static) num_threads(s.threads) reduction(| : moved)
    for (std::size_t i = 0; i < n; ++i) {
        if (p.raft[i] >= 0) {  // prescribed rigid motion
            p.velocity[i] = s.rafts[p.raft[i]].velocity;
            p.angular_velocity[i] = Vec3{};
        } else {
            p.velocity[i] += p.force[i] * (h / p.mass[i]);
            p.angular_velocity[i] += p.torque[i] * (h / p.inertia[i]);
        }
        // The force is used up: clear it here, while it is in cache, instead of in a separate
        // pass at the start of the force evaluation.
        p.force[i] = Vec3{};
        p.torque[i] = Vec3{};
        p.position[i] += p.velocity[i] * dt;
        moved |= s.contacts.moved_beyond_skin(i, p.position[i]);
    }
    for (auto& w : s.walls) w.point += w.velocity * dt;
    return moved != 0;
}

// Second half kick fused with the sanity check of every grain; returns the first bad grain
// (non-finite state, or outside the box on a closed axis) or n when all are fine.
std::size_t kick_check(System& s) {
    Particles& p = s.particles;
    const double h = 0.5 * s.dt;
    const std::size_t n = p.size();
    const Domain& dom = s.domain;
    std::size_t bad = n;
#pragma omp parallel for schedule(static) num_threads(s.threads) reduction(min : bad)
    for (std::size_t i = 0; i < n; ++i) {
        if (p.raft[i] < 0) {
            p.velocity[i] += p.force[i] * (h / p.mass[i]);
            p.angular_velocity[i] += p.torque[i] * (h / p.inertia[i]);
        }
        bool ok = finite(p.position[i]) && finite(p.velocity[i]) && finite(p.angular_velocity[i]);
        const double margin = 2 * p.radius[i];
        for (int k = 0; k < 3; ++k)
            ok = ok && (dom.periodic[k] || (p.position[i][k] >= dom.lo[k] - margin && p.position[i][k] <= dom.hi[k] + margin));
        if (!ok && i < bad) bad = i;
    }
    return bad;
}

std::string describe_grain(const System& s, std::size_t i) {
    std::ostringstream out;
    const Particles& p = s.particles;
    out << "grain " << p.id[i] << " (radius " << p.radius[i] << " m, at " << p.position[i].x << ", "
        << p.position[i].y << ", " << p.position[i].z << ")";
    return out.str();
}

void fail_overlap(const System& s) {
    const ContactStats& st = s.contact_stats;
    std::ostringstream out;
    out << "blow-up at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, st.worst_i)
        << " overlaps " << (st.worst_is_wall ? "wall '" + s.walls[st.worst_j].name + "'" : describe_grain(s, st.worst_j))
        << " by " << st.max_overlap_ratio << " of the smaller radius (limit " << s.max_overlap_fraction
        << "). Likely causes: impacts too fast for the Young's modulus (the Hertz overlap of an "
           "impact grows as R (rho v^2 / Y)^(2/5), whatever the step: raise youngs_modulus or "
           "lower the speeds), loads (cohesion, magnetic, gravity, a fast wall) the modulus cannot "
           "hold, or a time step (" << s.dt << " s) too long for the contact stiffness; or raise "
           "run.max_overlap_fraction if large overlaps are intended.";
    throw BlowUp(out.str());
}

void fail_grain(const System& s, std::size_t i) {
    const Particles& p = s.particles;
    std::ostringstream out;
    out << "blow-up at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, i);
    if (!finite(p.position[i]) || !finite(p.velocity[i]) || !finite(p.angular_velocity[i])) {
        out << " has a non-finite position or velocity. Likely cause: an unstable time step, or a force "
               "term without a length scale (zero radius or mass).";
    } else {
        out << " left the box through a side that is not periodic. Likely cause: no wall on that side, "
               "or a grain pushed through a wall by a too-long time step.";
    }
    throw BlowUp(out.str());
}

}  // namespace

void prepare(System& s) {
    s.contacts.build(s.particles, s.domain, s.threads);
    // Forces of the present state without advancing any contact spring: the grains have not
    // moved, so the tangential and rolling histories must not grow (dt = 0 adds nothing).
    const double dt = s.dt;
    s.dt = 0;
    compute_forces(s);
    s.dt = dt;
    if (s.contact_stats.max_overlap_ratio > s.max_overlap_fraction) fail_overlap(s);
}

void advance(System& s) {
    const bool rebuild = kick_drift(s);
    s.time += s.dt;
    ++s.step;
    if (rebuild) s.contacts.build(s.particles, s.domain, s.threads);
    accumulate_forces(s);
    const std::size_t bad = kick_check(s);
    if (bad < s.particles.size()) fail_grain(s, bad);
    if (s.contact_stats.max_overlap_ratio > s.max_overlap_fraction) fail_overlap(s);
}

}  // namespace mrjam
