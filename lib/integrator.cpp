#include "integrator.hpp"

#include <cmath>
#include <sstream>

#include "forces.hpp"

namespace mrjam {
namespace {

void half_kick(System& s) {
    Particles& p = s.particles;
    const double h = 0.5 * s.dt;
    const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (std::size_t i = 0; i < n; ++i) {
        if (p.raft[i] >= 0) continue;  // prescribed motion
        p.velocity[i] += p.force[i] * (h / p.mass[i]);
        p.angular_velocity[i] += p.torque[i] * (h / p.inertia[i]);
    }
}

void drift(System& s) {
    Particles& p = s.particles;
    const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(s.threads)
    for (std::size_t i = 0; i < n; ++i) {
        if (p.raft[i] >= 0) {
            p.velocity[i] = s.rafts[p.raft[i]].velocity;
            p.angular_velocity[i] = Vec3{};
        }
        p.position[i] += p.velocity[i] * s.dt;
    }
    for (auto& w : s.walls) w.point += w.velocity * s.dt;
}

std::string describe_grain(const System& s, std::size_t i) {
    std::ostringstream out;
    const Particles& p = s.particles;
    out << "grain " << p.id[i] << " (radius " << p.radius[i] << " m, at " << p.position[i].x << ", "
        << p.position[i].y << ", " << p.position[i].z << ")";
    return out.str();
}

void check_state(const System& s) {
    const Particles& p = s.particles;
    const ContactStats& st = s.contact_stats;
    if (st.max_overlap_ratio > s.max_overlap_fraction) {
        std::ostringstream out;
        out << "blow-up at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, st.worst_i)
            << " overlaps " << (st.worst_is_wall ? "wall '" + s.walls[st.worst_j].name + "'" : describe_grain(s, st.worst_j))
            << " by " << st.max_overlap_ratio << " of the smaller radius (limit " << s.max_overlap_fraction
            << "). Likely cause: the time step (" << s.dt
            << " s) is too long for the contact stiffness and speeds, or forces (cohesion, magnetic, "
               "gravity, a fast wall) exceed what the Young's modulus can hold; shorten the step, "
               "lower the loads, or raise run.max_overlap_fraction if large overlaps are intended.";
        throw BlowUp(out.str());
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!finite(p.position[i]) || !finite(p.velocity[i]) || !finite(p.force[i]) || !finite(p.angular_velocity[i])) {
            std::ostringstream out;
            out << "blow-up at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, i)
                << " has a non-finite position, velocity or force. Likely cause: an unstable time step or "
                   "a zero radius or mass.";
            throw BlowUp(out.str());
        }
        for (int k = 0; k < 3; ++k) {
            if (s.domain.periodic[k]) continue;
            const double margin = 2 * p.radius[i];
            if (p.position[i][k] < s.domain.lo[k] - margin || p.position[i][k] > s.domain.hi[k] + margin) {
                std::ostringstream out;
                out << "at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, i)
                    << " left the box on axis " << char('x' + k)
                    << ", which is not periodic. Likely cause: no wall on that side, or a grain pushed "
                       "through a wall by a too-long time step.";
                throw BlowUp(out.str());
            }
        }
    }
}

}  // namespace

void prepare(System& s) {
    s.contacts.build(s.particles, s.domain, s.threads);
    compute_forces(s);
    check_state(s);
}

void advance(System& s) {
    half_kick(s);
    drift(s);
    s.time += s.dt;
    ++s.step;
    if (s.contacts.needs_rebuild(s.particles)) s.contacts.build(s.particles, s.domain, s.threads);
    compute_forces(s);
    half_kick(s);
    check_state(s);
}

}  // namespace mrjam
