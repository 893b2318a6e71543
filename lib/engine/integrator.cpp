#include "integrator.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "forces.hpp"
#include "terms/magnetic_term.hpp"

namespace mrjam {
namespace {

// One pass over the grains that can do two jobs, fused so the arrays stream through cache once:
//  Finish: the second half kick of the step just computed, and the sanity check of every grain
//          (non-finite state, or outside the box on a closed axis);
//  Start:  the first half kick of the next step, clearing the used force, the drift, and the
//          neighbour-list displacement test.
// The arithmetic per grain is the same whether the jobs are fused or not, so a run gives the
// same bits however its steps are grouped. Returns the first bad grain, or n.
// Planar: a monolayer (a template flag, so the 3D pass carries no test for it).
template <bool Finish, bool Start, bool Planar>
std::size_t kick_pass(System& s, bool& rebuild) {
    Particles& p = s.particles;
    const double h = 0.5 * s.dt, dt = s.dt;
    const std::size_t n = p.size();
    const Domain& dom = s.domain;
    Vec3* __restrict x = p.position.data();
    Vec3* __restrict v = p.velocity.data();
    Vec3* __restrict w = p.angular_velocity.data();
    Vec3* __restrict f = p.force.data();
    Vec3* __restrict t = p.torque.data();
    const double* __restrict mass = p.mass.data();
    const double* __restrict inertia = p.inertia.data();
    const std::int16_t* __restrict raft = p.raft.data();
    std::size_t bad = n;
    // A list built for another grain count is stale whatever the displacements.
    const bool stale = p.size() + 1 != s.contacts.offsets.size();
    int moved = 0;
    const Vec3* __restrict built = s.contacts.positions_at_build();
    if constexpr (Start) {
        // The Lees-Edwards images slide with the drift below; the lists' image shifts follow.
        if (s.domain.lees_edwards) {
            s.domain.shear_offset += s.domain.shear_velocity * dt;
            s.contacts.set_shear_offset(s.domain);
            if (s.magnetic.enabled) s.magnetic.pairs.set_shear_offset(s.domain);
        }
    }
    const double rebuild_sq = s.contacts.rebuild_displacement_sq(s.domain);
    if (rebuild_sq < 0) moved = 1;  // the offset alone has used up the skin
    // Monolayer: no out-of-plane velocity, spin only about the normal. Applied after each kick, so
    // an out-of-plane force or initial velocity never moves a grain off its plane.
    const int plane_normal = dom.monolayer_normal;
    auto confine = [plane_normal](Vec3& vi, Vec3& wi) {
        vi[plane_normal] = 0;
        const double spin = wi[plane_normal];
        wi = Vec3{};
        wi[plane_normal] = spin;
    };
    bool closed[3];
    bool any_closed = false;
    for (int k = 0; k < 3; ++k) any_closed |= (closed[k] = !dom.periodic[k]);
#pragma omp parallel for schedule(static) num_threads(s.threads) reduction(min : bad) reduction(| : moved)
    for (std::size_t i = 0; i < n; ++i) {
        const bool free = raft[i] < 0;
        if constexpr (Finish) {
            if (free) {
                v[i] += f[i] * (h / mass[i]);
                w[i] += t[i] * (h / inertia[i]);
                if constexpr (Planar) confine(v[i], w[i]);
            }
            // One sum is non-finite if any term is: a cheap test for NaN and infinity.
            const double sum = x[i].x + x[i].y + x[i].z + v[i].x + v[i].y + v[i].z + w[i].x + w[i].y + w[i].z;
            bool ok = std::isfinite(sum);
            if (any_closed) {
                const double margin = 2 * p.radius[i];
                for (int k = 0; k < 3; ++k)
                    ok = ok && (!closed[k] || (x[i][k] >= dom.lo[k] - margin && x[i][k] <= dom.hi[k] + margin));
            }
            if (!ok && i < bad) bad = i;
        }
        if constexpr (Start) {
            if (free) {
                v[i] += f[i] * (h / mass[i]);
                w[i] += t[i] * (h / inertia[i]);
                if constexpr (Planar) confine(v[i], w[i]);
            } else {  // prescribed rigid motion
                v[i] = s.rafts[raft[i]].velocity;
                w[i] = Vec3{};
            }
            f[i] = Vec3{};  // used up: cleared here, in cache, not in a pass of its own
            t[i] = Vec3{};
            x[i] += v[i] * dt;
            if (s.magnetic.any_permanent) p.orientation[i].advance(w[i], dt);  // carries the body-fixed moment
            if (!stale && !moved) moved = norm2(x[i] - built[i]) > rebuild_sq;
        }
    }
    if constexpr (Start) {
        for (auto& wall : s.walls) wall.point += wall.velocity * dt;
        rebuild = stale || moved != 0;
    }
    return bad;
}

// The magnetic list shares the contact list's skin and is rebuilt with it. Its reach covers the
// contacts' (a cutoff of at least one diameter), so it is built first from the grid and the
// contact list is filtered from it: one grid search instead of two. While the magnet is off (the
// jam predictor's no-field flow) it is not built at all, only marked stale, and the first step
// with the magnet on rebuilds both (magnet_list_due).
void build_pair_lists(System& s) {
    if (!magnet_acts(s.magnetic, s.time)) {
        s.contacts.build(s.particles, s.domain, s.threads);
        if (s.magnetic.enabled) s.magnetic.pairs.mark_stale();
        return;
    }
    s.magnetic.pairs.build(s.particles, s.domain, s.threads);
    if (s.contacts.fits_within(s.magnetic.pairs))
        s.contacts.build_within(s.magnetic.pairs, s.particles, s.domain, s.threads);
    else
        s.contacts.build(s.particles, s.domain, s.threads);
}

// With the pair lists, each wall's near grains: a grain moves less than half a skin between
// rebuilds, so one a skin clear of a wall at the rebuild cannot reach it before the next.
void rebuild_neighbours(System& s) {
    s.domain.wrap_shear_offset();
    build_pair_lists(s);
    const double margin = s.contacts.settings().skin;
    for (Wall& w : s.walls) w.find_near_grains(s.particles.position, s.particles.radius, margin);
}

bool magnet_list_due(const System& s) {
    return magnet_acts(s.magnetic, s.time) && !s.magnetic.pairs.current(s.particles.size());
}

std::string describe_grain(const System& s, std::size_t i) {
    std::ostringstream out;
    const Particles& p = s.particles;
    out << "grain " << p.id[i] << " (radius " << p.radius[i] << " m, at " << p.position[i].x << ", " << p.position[i].y
        << ", " << p.position[i].z << ")";
    return out.str();
}

void fail_overlap(const System& s) {
    const ContactStats& st = s.contact_stats;
    std::ostringstream out;
    out << "blow-up at step " << s.step << " (t = " << s.time << " s): " << describe_grain(s, st.worst_i)
        << " overlaps "
        << (st.worst_is_wall ? "wall '" + s.walls[st.worst_j].name + "'" : describe_grain(s, st.worst_j)) << " by "
        << st.max_overlap_ratio << " of the smaller radius (limit " << s.max_overlap_fraction
        << "). Likely causes: impacts too fast for the Young's modulus (the Hertz overlap of an "
           "impact grows as R (rho v^2 / Y)^(2/5), whatever the step: raise youngs_modulus or "
           "lower the speeds), loads (cohesion, magnetic, gravity, a fast wall) the modulus cannot "
           "hold, or a time step ("
        << s.dt
        << " s) too long for the contact stiffness; or raise "
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
    // The magnetic model's state lives in System::magnetic and its forces come from the term:
    // a System built by hand with one and not the other would run without its forces, or
    // rebuild pair lists for nothing.
    if (s.magnetic.enabled != (s.terms.find<MagneticTerm>() != nullptr))
        throw std::logic_error(s.magnetic.enabled
                                   ? "System::magnetic is enabled but no MagneticTerm is in the list"
                                   : "a MagneticTerm is in the list but System::magnetic is not enabled");
    rebuild_neighbours(s);
    // Forces of the present state without advancing any contact spring: the grains have not
    // moved, so the tangential and rolling histories must not grow (dt = 0 adds nothing).
    const double dt = s.dt;
    s.dt = 0;
    compute_forces(s);
    s.dt = dt;
    if (s.contact_stats.max_overlap_ratio > s.max_overlap_fraction) fail_overlap(s);
}

void advance(System& s) { advance_steps(s, 1); }

void advance_steps(System& s, long count) {
    if (count <= 0) return;
    bool rebuild = false;
    const bool planar = s.domain.monolayer_normal >= 0;
    planar ? kick_pass<false, true, true>(s, rebuild) : kick_pass<false, true, false>(s, rebuild);
    for (long c = 0; c < count; ++c) {
        s.time += s.dt;
        ++s.step;
        if (rebuild || magnet_list_due(s)) rebuild_neighbours(s);
        accumulate_forces(s);
        if (s.contact_stats.max_overlap_ratio > s.max_overlap_fraction) fail_overlap(s);
        const bool more = c + 1 < count;
        const std::size_t bad =
            planar ? (more ? kick_pass<true, true, true>(s, rebuild) : kick_pass<true, false, true>(s, rebuild))
                   : (more ? kick_pass<true, true, false>(s, rebuild) : kick_pass<true, false, false>(s, rebuild));
        if (bad < s.particles.size()) fail_grain(s, bad);
    }
}

}  // namespace mrjam
