#include "magnetic/magnetic_model.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "thread_sums.hpp"

namespace mrjam {
namespace {

// The moment a grain takes in local field h: permanent part plus the induced part, capped.
inline Vec3 moment_in(const Particles& p, std::size_t i, const Vec3& h) {
    Vec3 induced = h * p.induced_coefficient[i];
    const double mag2 = norm2(induced), cap = p.saturation_moment[i];
    if (mag2 > cap * cap) induced *= cap / std::sqrt(mag2);
    return p.orientation[i].rotate(p.permanent_moment[i]) + induced;
}

struct Buffers {
    PerThreadSums force, torque, field;
};

// One pass over the magnetic pairs. Always sums the neighbour field at every grain (into
// model.neighbour_field); with `with_forces` also adds the pair forces (eq. 4.8) to `force` and,
// when any grain is permanent, the pair torques to `torque`.
template <bool WithForces, bool WithTorques>
void pair_pass(MagneticModel& model, Particles& p, int threads, Buffers& b, std::vector<Vec3>& force,
               std::vector<Vec3>& torque) {
    const std::size_t n = p.size();
    const NeighborList& list = model.pairs;
    const int nt = std::max(1, threads);
    b.field.resize(nt);
    b.force.resize(nt);
    b.torque.resize(nt);
    model.neighbour_field.assign(n, Vec3{});
    if (WithTorques) torque.assign(n, Vec3{});
#pragma omp parallel num_threads(nt)
    {
        const int tid = omp_get_thread_num();
        // Thread 0 accumulates straight into the shared arrays, the others into private buffers
        // summed below in thread order (deterministic for a given thread count).
        Vec3* __restrict h = b.field.target(tid, model.neighbour_field);
        Vec3* __restrict f = WithForces ? b.force.target(tid, force) : nullptr;
        Vec3* __restrict t = WithTorques ? b.torque.target(tid, torque) : nullptr;
        const Vec3* __restrict x = p.position.data();
        const Vec3* __restrict m = p.dipole_moment.data();
        const std::uint32_t* __restrict offsets = list.offsets.data();
        const std::uint32_t* __restrict partners = list.partners.data();
        const std::uint8_t* __restrict image = list.image.data();
        const double* __restrict range_sq = list.range_sq.data();
        const std::size_t begin = n * tid / nt, end = n * (tid + 1) / nt;
        for (std::size_t i = begin; i < end; ++i) {
            const Vec3 xi = x[i], mi = m[i];
            Vec3 hi{}, fi{}, ti{};
            for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
                const std::uint32_t j = partners[k];
                const Vec3 d = xi - x[j] + list.image_shift(image[k]);
                const double r2 = norm2(d);
                if (r2 >= range_sq[k]) continue;
                // Written in the unnormalised separation d so the dot products do not wait for
                // the square root: rhat = d / r, m.rhat = (m.d) / r.
                const double inv_r2 = 1.0 / r2;
                const double c = kInvFourPi * inv_r2 * std::sqrt(inv_r2);  // 1 / (4 pi r^3)
                const Vec3 mj = m[j];
                const double mi_d = dot(mi, d), mj_d = dot(mj, d);
                // Dipole fields (even in d): at i from j, at j from i.
                const Vec3 h_at_i = dipole_field(mj, d, mj_d, inv_r2, c);
                const Vec3 h_at_j = dipole_field(mi, d, mi_d, inv_r2, c);
                hi += h_at_i;
                h[j] += h_at_j;
                if constexpr (WithForces) {
                    const Vec3 pair_force = dipole_pair_force(mi, mj, d, inv_r2, c, mi_d, mj_d);
                    fi += pair_force;
                    f[j] -= pair_force;
                }
                if constexpr (WithTorques) {
                    ti += cross(mi, h_at_i) * kMu0;
                    t[j] += cross(mj, h_at_j) * kMu0;
                }
            }
            h[i] += hi;
            if constexpr (WithForces) f[i] += fi;
            if constexpr (WithTorques) t[i] += ti;
        }
#pragma omp barrier
        b.field.reduce_into(model.neighbour_field, begin, end);
        if (WithForces) b.force.reduce_into(force, begin, end);
        if (WithTorques) b.torque.reduce_into(torque, begin, end);
    }
}

// Fills model.applied_flux_density at the grains' positions for this evaluation (a uniform field
// needs no table: its users take the one value).
void look_up_applied_field(MagneticModel& model, const Particles& p, double time, int threads) {
    if (model.field->uniform()) return;
    const std::size_t n = p.size();
    model.applied_flux_density.resize(n);
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
    for (std::size_t i = 0; i < n; ++i) model.applied_flux_density[i] = model.field->flux_density(p.position[i], time);
}

// New moments from the applied field and the last neighbour field; returns max |dm| / max |m|.
// With the neighbours' field the update is under-relaxed: the induced part moves a share
// `relaxation` (omega) of the way to its Jacobi target C (H0 + T m). Plain Jacobi (omega = 1)
// diverges once an eigenvalue of C T lies below -1, and for iron grains (mu_r 1000) it does in
// any packing denser than about 0.4: -1.06 at 0.45, -1.33 at 0.64, -1.38 in a touching fcc
// lattice (docs/magnetic_forces.md, "Under-relaxed mutual dipoles"); the alternating mode then
// grows until the saturation cap holds it. Relaxed, the error contracts by 1 - omega (1 - lambda),
// which for omega = 2/3 holds for every eigenvalue above -2. A permanent moment is not relaxed:
// it turns with its grain.
double update_moments(const MagneticModel& model, Particles& p, double time, bool with_neighbours, int threads) {
    double max_change = 0, max_moment = 0;
    const std::size_t n = p.size();
    const bool uniform = model.field->uniform();
    const Vec3 h_uniform = uniform ? model.field->flux_density(Vec3{}, time) * (1.0 / kMu0) : Vec3{};
    const double omega = with_neighbours ? model.settings.relaxation : 1.0;
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads)) reduction(max : max_change, max_moment)
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 h = uniform ? h_uniform : model.applied_flux_density[i] * (1.0 / kMu0);
        if (with_neighbours) h += model.neighbour_field[i];
        Vec3 m = moment_in(p, i, h);
        if (omega != 1.0 && p.induced_coefficient[i] != 0.0) {
            const Vec3 permanent = p.orientation[i].rotate(p.permanent_moment[i]);
            const Vec3 induced_old = p.dipole_moment[i] - permanent;
            m = permanent + induced_old + (m - permanent - induced_old) * omega;
        }
        max_change = std::max(max_change, norm(m - p.dipole_moment[i]));
        max_moment = std::max(max_moment, norm(m));
        p.dipole_moment[i] = m;
    }
    return max_moment > 0 ? max_change / max_moment : 0.0;
}

// Adds the held magnetic forces (and torques) of the last evaluation to the grains.
void add_held(const MagneticModel& model, Particles& p, int threads) {
    const std::size_t n = p.size();
    const bool torques = model.any_permanent;
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
    for (std::size_t i = 0; i < n; ++i) {
        p.force[i] += model.held_force[i];
        if (torques) p.torque[i] += model.held_torque[i];
    }
}

// The applied field's own terms on each grain: the gradient force grad(m . B_ext) (eq. 4.6, m
// held fixed) and, on a permanent moment, the torques of the pairs and of the field (eqs. 4.7,
// 4.9). Per grain and independent, so split over the threads: in the valve's field map the two
// lookups cost a tenth of a step, which one thread alone would leave serial.
void add_applied_field_terms(const MagneticModel& model, const Particles& p, double time, int threads,
                             std::vector<Vec3>& force, std::vector<Vec3>& grain_torque,
                             const std::vector<Vec3>& pair_torque) {
    const std::size_t n = p.size();
    const bool uniform = model.field->uniform();
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads))
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& m = p.dipole_moment[i];
        if (model.any_permanent && norm2(p.permanent_moment[i]) > 0) {
            // Only a permanent moment turns its grain; an induced one follows the field.
            const Vec3 b = uniform ? model.field->flux_density(p.position[i], time) : model.applied_flux_density[i];
            grain_torque[i] += pair_torque[i] + cross(m, b);
        }
        if (!uniform) {
            const Gradient g = model.field->gradient(p.position[i], time);
            for (int k = 0; k < 3; ++k) force[i][k] += m.x * g[0][k] + m.y * g[1][k] + m.z * g[2][k];
        }
    }
}

}  // namespace

void initialise_moments(MagneticModel& model, Particles& p, double time) {
    p.dipole_moment.resize(p.size());
    look_up_applied_field(model, p, time, 1);
    update_moments(model, p, time, false, 1);
}

bool magnet_acts(const MagneticModel& model, double time) {
    return model.enabled && (model.any_permanent || !model.field->off_at(time));
}

void add_magnetic_forces(MagneticModel& model, Particles& p, double time, int threads) {
    static thread_local Buffers buffers;
    static thread_local std::vector<Vec3> torque;
    const MagneticSettings& s = model.settings;
    const std::size_t n = p.size();
    // A magnet switched off (the jam predictor's no-field flow and release): induced moments
    // vanish at once (the self-consistent solution without an applied field is zero; the lagged
    // update would only let them decay over a few steps), and there is nothing to sum.
    if (!magnet_acts(model, time)) {
        p.dipole_moment.assign(n, Vec3{});
        model.neighbour_field.assign(n, Vec3{});
        model.held_force.clear();
        model.held_torque.clear();
        ++model.skipped_passes;
        return;
    }
    if (model.pairs.offsets.size() != n + 1)
        throw std::logic_error("add_magnetic_forces: the magnetic pair list was not built for these grains");
    // Multiple time stepping: reuse the last evaluation while it is young enough (and was made
    // for these grains: a removal or a switch-on clears it).
    const bool holding = model.hold.holding();
    if (model.hold.reuse_now(model.held_force.size(), n)) {
        add_held(model, p, threads);
        model.hold.reused_once();
        return;
    }
    // Where this evaluation's forces go: straight onto the grains, or (holding) into the held
    // arrays first, so the following steps can add them again.
    if (holding) {
        model.held_force.assign(n, Vec3{});
        model.held_torque.assign(model.any_permanent ? n : 0, Vec3{});
    }
    std::vector<Vec3>& force = holding ? model.held_force : p.force;
    std::vector<Vec3>& grain_torque = holding ? model.held_torque : p.torque;
    look_up_applied_field(model, p, time, threads);
    // Moments for this step's forces.
    if (s.policy == MutualPolicy::fixed) {
        update_moments(model, p, time, false, threads);
    } else if (s.policy == MutualPolicy::iterations) {
        for (int k = 0; k < s.iterations; ++k) {
            pair_pass<false, false>(model, p, threads, buffers, force, torque);
            update_moments(model, p, time, true, threads);
            ++model.field_passes;
        }
    } else if (s.policy == MutualPolicy::converged) {
        for (int k = 0; k < s.max_iterations; ++k) {
            pair_pass<false, false>(model, p, threads, buffers, force, torque);
            ++model.field_passes;
            if (update_moments(model, p, time, true, threads) < s.tolerance) break;
        }
    }
    // Forces; for the lagged policy the same pass gives the neighbour field of the next moments.
    if (model.any_permanent)
        pair_pass<true, true>(model, p, threads, buffers, force, torque);
    else
        pair_pass<true, false>(model, p, threads, buffers, force, torque);
    ++model.force_passes;
    if (s.policy == MutualPolicy::lagged) ++model.field_passes;
    if (s.close_pairs.enabled) add_close_pair_forces(model, p, time, threads, force);

    if (model.any_permanent || !model.field->uniform())
        add_applied_field_terms(model, p, time, threads, force, grain_torque, torque);
    if (s.policy == MutualPolicy::lagged) update_moments(model, p, time, true, threads);
    if (holding) {
        add_held(model, p, threads);
        model.hold.evaluated();
    }
}

const char* policy_name(MutualPolicy policy) {
    switch (policy) {
        case MutualPolicy::fixed:
            return "fixed";
        case MutualPolicy::lagged:
            return "lagged";
        case MutualPolicy::iterations:
            return "iterations";
        case MutualPolicy::converged:
            return "converged";
    }
    return "?";
}

double mean_iterations(const MagneticModel& model) {
    return model.force_passes ? static_cast<double>(model.field_passes) / model.force_passes : 0.0;
}

}  // namespace mrjam
