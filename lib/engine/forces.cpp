#include "forces.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "thread_sums.hpp"

namespace mrjam {
namespace {

// A raft's force summed by one thread, a cache line to itself: the threads add contact forces to
// their own sums of the same few rafts, and sums side by side would share a line between cores.
struct alignas(64) RaftSum {
    Vec3 force;
};

struct ThreadBuffers {
    PerThreadSums force, torque;
    std::vector<ContactStats> stats;
    std::vector<std::vector<RaftSum>> raft_force;
};

// One grain's touching list entries, found by grain_contacts' first pass. The top bit marks a
// contact that starts this step (a list of 2^31 pairs would need 96 GB of history alone).
constexpr std::uint32_t kNewContact = 1u << 31;

std::vector<std::uint32_t>& touching_entries() {
    static thread_local std::vector<std::uint32_t> entries;  // per OpenMP thread, reused
    return entries;
}

ThreadBuffers& buffers() {
    static thread_local ThreadBuffers b;  // reused between steps; one set per calling thread
    return b;
}

void merge_stats(ContactStats& into, const ContactStats& s) {
    into.contacts += s.contacts;
    if (s.max_overlap_ratio > into.max_overlap_ratio) {
        into.max_overlap_ratio = s.max_overlap_ratio;
        into.worst_i = s.worst_i;
        into.worst_j = s.worst_j;
        into.worst_is_wall = s.worst_is_wall;
    }
}

// Sliding: Lees-Edwards images, whose velocity enters the contact velocity (a template flag, so
// the ordinary force loop does no work for it). Both contact passes stay out of line so that
// `perf` names them (bench/step_shares.sh); a call per thread per step costs nothing measurable.
template <RollingModel Rolling, CohesionModel Cohesion, bool Sliding>
[[gnu::noinline]] void grain_contacts(System& s, Vec3* __restrict f, Vec3* __restrict t, ContactStats& stats,
                                      std::vector<RaftSum>& raft_force, std::size_t begin, std::size_t end) {
    const Particles& p = s.particles;
    NeighborList& list = s.contacts;
    const double dt = s.dt;
    // Raw restrict pointers: the compiler may then keep grain data in registers across the
    // force writes instead of reloading it after each one.
    const Vec3* __restrict x = p.position.data();
    const Vec3* __restrict v = p.velocity.data();
    const Vec3* __restrict w = p.angular_velocity.data();
    const double* __restrict radius = p.radius.data();
    const double* __restrict mass = p.mass.data();
    const std::int16_t* __restrict raft = p.raft.data();
    const std::uint32_t* __restrict offsets = list.offsets.data();
    const std::uint32_t* __restrict partners = list.partners.data();
    const std::uint8_t* __restrict image = list.image.data();
    const double* __restrict range_sq = list.range_sq.data();
    std::uint8_t* __restrict touching = list.touching.data();
    ContactHistory* __restrict history = list.history.data();
    const Vec3* __restrict image_velocity = list.image_velocities();

    std::vector<std::uint32_t>& entries = touching_entries();

    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 xi = x[i];
        const double ri = radius[i];
        const bool frozen_i = raft[i] >= 0;
        // First pass: which listed pairs touch, with each pair's history prefetched; the contact
        // law waiting for that history line was the pass's one stall
        // (docs/notes/benchmark_log.md, "The contact pass's one stall").
        const std::uint32_t k0 = offsets[i], k1 = offsets[i + 1];
        if (entries.size() < k1 - k0) entries.resize(k1 - k0);
        std::uint32_t* __restrict found = entries.data();
        std::uint32_t count = 0;
        for (std::uint32_t k = k0; k < k1; ++k) {
            const Vec3 d = xi - x[partners[k]] + list.image_shift(image[k]);
            const std::uint32_t now = norm2(d) < range_sq[k];
            const std::uint32_t before = touching[k];
            if (now != before) touching[k] = static_cast<std::uint8_t>(now);  // write only on change
            __builtin_prefetch(&history[k]);
            found[count] = k | (kNewContact * (now & (before ^ 1u)));
            count += now;
        }
        Vec3 fi{}, ti{};  // this grain's sums, written once after its pairs
        for (std::uint32_t e = 0; e < count; ++e) {
            const std::uint32_t k = found[e] & ~kNewContact;
            // A new contact starts with no tangential or rolling memory.
            if (found[e] & kNewContact) history[k] = ContactHistory{};
            const std::uint32_t j = partners[k];
            const bool frozen_j = raft[j] >= 0;
            if (frozen_i && frozen_j) continue;  // both move rigidly: their force does no work
            const Vec3 d = xi - x[j] + list.image_shift(image[k]);
            const double r2 = norm2(d);
            const double rj = radius[j];
            Vec3 dv = v[i] - v[j];
            if constexpr (Sliding) dv += image_velocity[image[k]];
            ContactInput in = grain_pair_input(d, r2, ri, rj, mass[i], mass[j], dv, w[i], w[j]);
            if constexpr (Rolling == RollingModel::epsd)
                in.rolling_inertia = 1.0 / (1.0 / p.rolling_inertia(i) + 1.0 / p.rolling_inertia(j));
            ContactOutput out;
            hertz_mindlin<Rolling, Cohesion>(s.pairs(p.material[i], p.material[j]), in, history[k], dt, out);
            fi += out.force_on_i;
            f[j] -= out.force_on_i;
            ti += out.torque_on_i;
            t[j] += out.torque_on_j;
            if (frozen_i) raft_force[raft[i]].force += out.force_on_i;
            if (frozen_j) raft_force[raft[j]].force -= out.force_on_i;
            ++stats.contacts;
            const double ratio = in.overlap / std::min(ri, rj);
            if (ratio > stats.max_overlap_ratio) {
                stats.max_overlap_ratio = ratio;
                stats.worst_i = i;
                stats.worst_j = j;
                stats.worst_is_wall = false;
            }
        }
        f[i] += fi;
        t[i] += ti;
    }
}

template <RollingModel Rolling, CohesionModel Cohesion>
[[gnu::noinline]] void wall_contacts(System& s, Vec3* f, Vec3* t, ContactStats& stats, std::vector<Vec3>& wall_force,
                                     std::vector<RaftSum>& raft_force, std::size_t begin, std::size_t end) {
    const Particles& p = s.particles;
    for (std::size_t w = 0; w < s.walls.size(); ++w) {
        Wall& wall = s.walls[w];
        Vec3 on_wall{};  // summed here, not in the threads' small wall buffers (they may share a line)
        auto contact = [&](std::size_t i) {
            double overlap;
            ContactInput in;
            if (!wall.touch(p.position[i], p.radius[i], overlap, in.normal)) {
                wall.history[i] = ContactHistory{};
                return;
            }
            const double ri = p.radius[i];
            in.overlap = overlap;
            in.distance = ri - overlap;
            in.radius_i = ri;
            in.radius_j = 0;
            in.arm_i = ri;  // the wall takes what its contacts carry: no balance to keep
            in.arm_j = 0;
            in.reduced_radius = ri;
            in.reduced_mass = p.mass[i];
            in.rolling_inertia = p.rolling_inertia(i);
            in.contact_velocity = p.velocity[i] - wall.velocity - cross(p.angular_velocity[i] * ri, in.normal);
            in.relative_spin = p.angular_velocity[i];
            in.wall = true;
            ContactOutput out;
            hertz_mindlin<Rolling, Cohesion>(s.pairs(p.material[i], wall.material), in, wall.history[i], s.dt, out);
            f[i] += out.force_on_i;
            t[i] += out.torque_on_i;
            if (p.raft[i] >= 0) raft_force[p.raft[i]].force += out.force_on_i;
            on_wall -= out.force_on_i;
            ++stats.contacts;
            const double ratio = overlap / ri;
            if (ratio > stats.max_overlap_ratio) {
                stats.max_overlap_ratio = ratio;
                stats.worst_i = i;
                stats.worst_j = w;
                stats.worst_is_wall = true;
            }
        };
        if (wall.near_grains_hold(p.size())) {
            const auto& near = wall.near.index;
            // The near grains lie too far apart in the grains' arrays for the hardware's
            // prefetch: what the contact law reads is fetched a few near grains ahead, which
            // takes a sixth off the pass (docs/notes/benchmark_log.md, "Wall contacts
            // prefetched").
            constexpr std::ptrdiff_t ahead = 8;
            for (auto k = std::lower_bound(near.begin(), near.end(), begin); k != near.end() && *k < end; ++k) {
                if (near.end() - k > ahead) {
                    const std::uint32_t g = k[ahead];
                    __builtin_prefetch(&p.position[g]);
                    __builtin_prefetch(&p.radius[g]);
                    __builtin_prefetch(&p.velocity[g]);
                    __builtin_prefetch(&p.angular_velocity[g]);
                    __builtin_prefetch(&p.mass[g]);
                    __builtin_prefetch(&p.raft[g]);
                    __builtin_prefetch(&f[g]);
                    __builtin_prefetch(&t[g]);
                    __builtin_prefetch(&wall.history[g]);
                }
                contact(*k);
            }
        } else {
            for (std::size_t i = begin; i < end; ++i) contact(i);
        }
        wall_force[w] += on_wall;
    }
}

template <RollingModel Rolling, CohesionModel Cohesion>
void compute_all(System& s, bool zero_first) {
    Particles& p = s.particles;
    const std::size_t n = p.size();
    const int nthreads = std::max(1, s.threads);
    ThreadBuffers& b = buffers();
    b.force.resize(nthreads);
    b.torque.resize(nthreads);
    b.stats.assign(nthreads, ContactStats{});
    b.raft_force.assign(nthreads, std::vector<RaftSum>(s.rafts.size()));
    std::vector<std::vector<Vec3>> wall_force(nthreads, std::vector<Vec3>(s.walls.size()));
    for (auto& w : s.walls) w.history.resize(n);
    // The per-grain terms (drag, gravity) ride on the contact pass's threads, each over the
    // thread's own grains after its contacts: no pass over memory of their own.
    const std::vector<ForceTerm*>& per_grain = s.terms.per_grain_terms();
    for (ForceTerm* term : per_grain) term->begin_pass(s);

#pragma omp parallel num_threads(nthreads)
    {
        const int tid = omp_get_thread_num();
        // Thread 0 writes straight into the grains' arrays; the others into private buffers.
        Vec3* f = b.force.target(tid, p.force);
        Vec3* t = b.torque.target(tid, p.torque);
        if (tid == 0 && zero_first) {
            std::fill(p.force.begin(), p.force.end(), Vec3{});
            std::fill(p.torque.begin(), p.torque.end(), Vec3{});
        }
        // Static contiguous split by owner: deterministic for a given thread count. The pair work
        // per owner is roughly uniform for dense packings.
        const std::size_t begin = n * tid / nthreads, end = n * (tid + 1) / nthreads;
        if (s.physics.contact) {
            // Counted on this thread's stack: the threads' counts side by side in one cache line
            // cost a quarter of a two-thread step whenever the compiler left them in memory
            // (docs/notes/benchmark_log.md, "Counts that shared a cache line").
            ContactStats stats;
            if (s.domain.lees_edwards)
                grain_contacts<Rolling, Cohesion, true>(s, f, t, stats, b.raft_force[tid], begin, end);
            else
                grain_contacts<Rolling, Cohesion, false>(s, f, t, stats, b.raft_force[tid], begin, end);
            wall_contacts<Rolling, Cohesion>(s, f, t, stats, wall_force[tid], b.raft_force[tid], begin, end);
            b.stats[tid] = stats;
        }
        for (ForceTerm* term : per_grain) term->add_per_grain(s, f, begin, end);
#pragma omp barrier
        b.force.reduce_into(p.force, begin, end);
        b.torque.reduce_into(p.torque, begin, end);
    }
    for (ForceTerm* term : per_grain) term->end_pass();

    s.contact_stats = ContactStats{};
    for (const auto& st : b.stats) merge_stats(s.contact_stats, st);
    for (std::size_t w = 0; w < s.walls.size(); ++w) {
        s.walls[w].force = Vec3{};
        for (int tid = 0; tid < nthreads; ++tid) s.walls[w].force += wall_force[tid][w];
    }
    for (std::size_t r = 0; r < s.rafts.size(); ++r) {
        s.rafts[r].force = Vec3{};
        for (int tid = 0; tid < nthreads; ++tid) s.rafts[r].force += b.raft_force[tid][r].force;
    }
    // The whole-system terms (magnetic dipoles, pair damping), in the list's order.
    for (ForceTerm* term : s.terms.whole_system_terms()) term->add(s);
}

template <RollingModel Rolling>
void dispatch_cohesion(System& s, bool zero_first) {
    switch (s.physics.cohesion) {
        case CohesionModel::none:
            return compute_all<Rolling, CohesionModel::none>(s, zero_first);
        case CohesionModel::sjkr:
            return compute_all<Rolling, CohesionModel::sjkr>(s, zero_first);
        case CohesionModel::dmt:
            return compute_all<Rolling, CohesionModel::dmt>(s, zero_first);
    }
}

void dispatch(System& s, bool zero_first) {
    switch (s.physics.rolling) {
        case RollingModel::none:
            return dispatch_cohesion<RollingModel::none>(s, zero_first);
        case RollingModel::epsd:
            return dispatch_cohesion<RollingModel::epsd>(s, zero_first);
        case RollingModel::sds:
            return dispatch_cohesion<RollingModel::sds>(s, zero_first);
    }
}

}  // namespace

void compute_forces(System& s) { dispatch(s, true); }
void accumulate_forces(System& s) { dispatch(s, false); }

double contact_elastic_energy(const System& s) {
    const Particles& p = s.particles;
    const NeighborList& list = s.contacts;
    double energy = 0;
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i) {
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const double overlap = p.radius[i] + p.radius[j] - norm(d);
            if (overlap <= 0) continue;
            const double rstar = p.radius[i] * p.radius[j] / (p.radius[i] + p.radius[j]);
            const double ystar = s.pairs(p.material[i], p.material[j]).effective_youngs;
            energy += 8.0 / 15.0 * ystar * std::sqrt(rstar) * std::pow(overlap, 2.5);
        }
    }
    for (const Wall& w : s.walls) {
        for (std::size_t i = 0; i < p.size(); ++i) {
            double overlap;
            Vec3 n;
            if (!w.touch(p.position[i], p.radius[i], overlap, n)) continue;
            const double ystar = s.pairs(p.material[i], w.material).effective_youngs;
            energy += 8.0 / 15.0 * ystar * std::sqrt(p.radius[i]) * std::pow(overlap, 2.5);
        }
    }
    return energy;
}

}  // namespace mrjam
