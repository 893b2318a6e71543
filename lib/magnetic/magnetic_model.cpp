#include "magnetic/magnetic_model.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

namespace mrjam {
namespace {

constexpr double kInvFourPi = 1.0 / (4.0 * M_PI);

// Field of dipole m at separation r (from the dipole to the point), A/m.
inline Vec3 dipole_field(const Vec3& m, const Vec3& rhat, double inv_r3) {
    return (rhat * (3.0 * dot(m, rhat)) - m) * (kInvFourPi * inv_r3);
}

// The moment a grain takes in local field h: permanent part plus the induced part, capped.
inline Vec3 moment_in(const Particles& p, std::size_t i, const Vec3& h) {
    Vec3 induced = h * p.induced_coefficient[i];
    const double mag2 = norm2(induced), cap = p.saturation_moment[i];
    if (mag2 > cap * cap) induced *= cap / std::sqrt(mag2);
    return p.orientation[i].rotate(p.permanent_moment[i]) + induced;
}

struct Buffers {
    std::vector<std::vector<Vec3>> force, torque, field;
};

// One pass over the magnetic pairs. Always sums the neighbour field at every grain; with
// `with_forces` also the pair forces (eq. 4.8) and, for permanent grains, the torques.
void pair_pass(MagneticModel& model, const Particles& p, int threads, bool with_forces, Buffers& b) {
    const std::size_t n = p.size();
    const NeighborList& list = model.pairs;
    const int nt = std::max(1, threads);
    b.field.resize(nt);
    if (with_forces) { b.force.resize(nt); b.torque.resize(nt); }
#pragma omp parallel num_threads(nt)
    {
        const int tid = omp_get_thread_num();
        b.field[tid].assign(n, Vec3{});
        Vec3* h = b.field[tid].data();
        Vec3* f = nullptr;
        Vec3* t = nullptr;
        if (with_forces) {
            b.force[tid].assign(n, Vec3{});
            b.torque[tid].assign(n, Vec3{});
            f = b.force[tid].data();
            t = b.torque[tid].data();
        }
        const Vec3* x = p.position.data();
        const Vec3* m = p.dipole_moment.data();
        const std::size_t begin = n * tid / nt, end = n * (tid + 1) / nt;
        for (std::size_t i = begin; i < end; ++i) {
            const Vec3 xi = x[i], mi = m[i];
            Vec3 hi{}, fi{};
            for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
                const std::uint32_t j = list.partners[k];
                const Vec3 d = xi - x[j] + list.image_shift(list.image[k]);
                const double r2 = norm2(d);
                if (r2 >= list.range_sq[k]) continue;
                const double inv_r = 1.0 / std::sqrt(r2);
                const Vec3 rhat = d * inv_r;  // from j to i
                const double inv_r3 = inv_r * inv_r * inv_r;
                const Vec3& mj = m[j];
                const Vec3 h_at_i = dipole_field(mj, rhat, inv_r3);
                const Vec3 h_at_j = dipole_field(mi, rhat, inv_r3);  // the field is even in rhat
                hi += h_at_i;
                h[j] += h_at_j;
                if (with_forces) {
                    const double mi_r = dot(mi, rhat), mj_r = dot(mj, rhat);
                    const Vec3 force = (mj * mi_r + mi * mj_r + rhat * dot(mi, mj) - rhat * (5.0 * mi_r * mj_r)) *
                                       (3.0 * kMu0 * kInvFourPi * inv_r3 * inv_r);
                    fi += force;
                    f[j] -= force;
                    if (model.any_permanent) {
                        t[i] += cross(mi, h_at_i) * kMu0;
                        t[j] += cross(mj, h_at_j) * kMu0;
                    }
                }
            }
            h[i] += hi;
            if (with_forces) f[i] += fi;
        }
    }
    // Sum the thread buffers into the first, in thread order (deterministic).
    for (int tid = 1; tid < nt; ++tid)
        for (std::size_t i = 0; i < n; ++i) {
            b.field[0][i] += b.field[tid][i];
            if (with_forces) { b.force[0][i] += b.force[tid][i]; b.torque[0][i] += b.torque[tid][i]; }
        }
    model.neighbour_field.swap(b.field[0]);
}

// New moments from the applied field and the last neighbour field; returns max |dm| / max |m|.
double update_moments(const MagneticModel& model, Particles& p, double time, bool with_neighbours, int threads) {
    double max_change = 0, max_moment = 0;
    const std::size_t n = p.size();
#pragma omp parallel for schedule(static) num_threads(std::max(1, threads)) reduction(max : max_change, max_moment)
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 h = model.field->flux_density(p.position[i], time) * (1.0 / kMu0);
        if (with_neighbours) h += model.neighbour_field[i];
        const Vec3 m = moment_in(p, i, h);
        max_change = std::max(max_change, norm(m - p.dipole_moment[i]));
        max_moment = std::max(max_moment, norm(m));
        p.dipole_moment[i] = m;
    }
    return max_moment > 0 ? max_change / max_moment : 0.0;
}

}  // namespace

void initialise_moments(const MagneticModel& model, Particles& p, double time) {
    p.dipole_moment.resize(p.size());
    update_moments(model, p, time, false, 1);
}

void add_magnetic_forces(MagneticModel& model, Particles& p, double time, int threads) {
    static thread_local Buffers buffers;
    const MagneticSettings& s = model.settings;
    const std::size_t n = p.size();
    // Moments for this step's forces.
    if (s.policy == MutualPolicy::fixed) {
        update_moments(model, p, time, false, threads);
    } else if (s.policy == MutualPolicy::iterations) {
        for (int k = 0; k < s.iterations; ++k) {
            pair_pass(model, p, threads, false, buffers);
            update_moments(model, p, time, true, threads);
            ++model.field_passes;
        }
    } else if (s.policy == MutualPolicy::converged) {
        for (int k = 0; k < s.max_iterations; ++k) {
            pair_pass(model, p, threads, false, buffers);
            ++model.field_passes;
            if (update_moments(model, p, time, true, threads) < s.tolerance) break;
        }
    }
    // Forces; for the lagged policy the same pass gives the neighbour field of the next moments.
    pair_pass(model, p, threads, true, buffers);
    ++model.force_passes;
    if (s.policy == MutualPolicy::lagged) ++model.field_passes;
    const Vec3* f = buffers.force[0].data();
    const Vec3* t = buffers.torque[0].data();
    for (std::size_t i = 0; i < n; ++i) {
        p.force[i] += f[i];
        // Only a permanent moment turns its grain; an induced one follows the field instead.
        const bool permanent = norm2(p.permanent_moment[i]) > 0;
        if (permanent) p.torque[i] += t[i];
        if (model.field->uniform() && !model.any_permanent) continue;
        const Vec3 b = model.field->flux_density(p.position[i], time);
        if (permanent) p.torque[i] += cross(p.dipole_moment[i], b);  // m x B_ext (eq. 4.7)
        if (!model.field->uniform()) {
            // grad(m . B_ext) with m held fixed (eq. 4.6): F_k = sum_l m_l dB_l/dx_k.
            const Gradient g = model.field->gradient(p.position[i], time);
            const Vec3& m = p.dipole_moment[i];
            for (int k = 0; k < 3; ++k) p.force[i][k] += m.x * g[0][k] + m.y * g[1][k] + m.z * g[2][k];
        }
    }
    if (s.policy == MutualPolicy::lagged) update_moments(model, p, time, true, threads);
}

double mean_iterations(const MagneticModel& model) {
    return model.force_passes ? static_cast<double>(model.field_passes) / model.force_passes : 0.0;
}

}  // namespace mrjam
