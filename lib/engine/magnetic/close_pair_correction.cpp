#include "magnetic/close_pair_correction.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "magnetic/magnetic_model.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "particles.hpp"
#include "thread_sums.hpp"

namespace mrjam {

namespace {

constexpr int kTablePoints = 96;  // in log(gap): linear interpolation within 0.1 % (tests)

}  // namespace

ClosePairTable::ClosePairTable(double mu, const ClosePairSettings& settings)
    : mu_(mu), min_gap_(settings.min_gap), range_(settings.range) {
    if (!(min_gap_ > 0) || !(range_ > min_gap_)) throw std::invalid_argument("close pairs: need 0 < min_gap < range");
    const double lo = std::log(min_gap_), hi = std::log(range_);
    for (int k = 0; k < kTablePoints; ++k) {
        const double log_gap = lo + (hi - lo) * k / (kTablePoints - 1);
        const double s = 2.0 + std::exp(log_gap);
        Correction c;
        for (PairOrientation o : {PairOrientation::axial, PairOrientation::transverse}) {
            const SpherePairResponse exact = converged_sphere_pair_response(mu, s, o, 1e-7);
            const SpherePairResponse dipoles = mutual_dipole_pair_response(mu, s, o);
            const double dalpha = exact.dpolarisability_ds - dipoles.dpolarisability_ds;
            const double alpha = exact.polarisability - dipoles.polarisability;
            if (o == PairOrientation::axial) {
                c.dalpha_axial = dalpha;
                c.alpha_axial = alpha;
            } else {
                c.dalpha_transverse = dalpha;
                c.alpha_transverse = alpha;
            }
        }
        log_gap_.push_back(log_gap);
        rows_.push_back(c);
    }
}

ClosePairTable::Correction ClosePairTable::at(double gap) const {
    if (log_gap_.empty() || gap >= range_) return {};
    const double g = std::max(gap, min_gap_);
    const double u = (std::log(g) - log_gap_.front()) / (log_gap_.back() - log_gap_.front()) * (kTablePoints - 1);
    const int k = std::clamp(static_cast<int>(u), 0, kTablePoints - 2);
    const double t = std::clamp(u - k, 0.0, 1.0);
    const Correction& a = rows_[k];
    const Correction& b = rows_[k + 1];
    // Fade out over the last half of the range so the force has no step where it ends.
    const double fade = std::clamp((range_ - gap) / (0.5 * range_), 0.0, 1.0);
    const auto mix = [&](double x, double y) { return fade * (x + t * (y - x)); };
    return {mix(a.dalpha_axial, b.dalpha_axial), mix(a.dalpha_transverse, b.dalpha_transverse),
            mix(a.alpha_axial, b.alpha_axial), mix(a.alpha_transverse, b.alpha_transverse)};
}

// From the pair's co-energy W' = 2 pi mu0 a^3 H^2 (alpha_ax cos^2 theta + alpha_tr sin^2 theta),
// theta the angle between the line of centres and H: the force along the line is dW'/d(s a) and
// the one across it (in the plane of the line and H, towards larger theta) dW'/d theta / (s a).
Vec3 close_pair_force(const ClosePairTable& table, const Vec3& d, double a, const Vec3& h) {
    const double r = norm(d), h2 = norm2(h);
    if (r == 0.0 || h2 == 0.0) return {};
    const double s = r / a;
    const ClosePairTable::Correction c = table.at(s - 2.0);
    const Vec3 rhat = d * (1.0 / r), hhat = h * (1.0 / std::sqrt(h2));
    const double cos_t = dot(rhat, hhat), cos2 = cos_t * cos_t, sin2 = 1.0 - cos2;
    const double scale = 2.0 * M_PI * kMu0 * h2 * a * a;
    const double along = scale * (cos2 * c.dalpha_axial + sin2 * c.dalpha_transverse);
    // sin(theta) t_hat = rhat cos(theta) - hhat: no division by sin(theta) on the axis.
    const double across = 2.0 * scale / s * (c.alpha_transverse - c.alpha_axial) * cos_t;
    return rhat * along + (rhat * cos_t - hhat) * across;
}

void add_close_pair_forces(const MagneticModel& model, const Particles& p, double time, int threads,
                           std::vector<Vec3>& force) {
    const ClosePairTable& table = model.close_pair_table;
    const std::size_t n = p.size();
    const NeighborList& list = model.pairs;
    const int nt = std::max(1, threads);
    const double reach = 2.0 + model.settings.close_pairs.range;  // centre distance over mean radius
    const bool uniform = model.field->uniform();
    const Vec3 h_uniform = uniform ? model.field->flux_density(Vec3{}, time) * (1.0 / kMu0) : Vec3{};
    static thread_local PerThreadSums calling_thread_sums;
    PerThreadSums& sums = calling_thread_sums;  // one object for the team
    sums.resize(nt);
#pragma omp parallel num_threads(nt)
    {
        const int tid = omp_get_thread_num();
        Vec3* f = sums.target(tid, force);
        const std::size_t begin = n * tid / nt, end = n * (tid + 1) / nt;
        for (std::size_t i = begin; i < end; ++i) {
            for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
                const std::uint32_t j = list.partners[k];
                const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
                const double a = 0.5 * (p.radius[i] + p.radius[j]);
                const double r2 = norm2(d);
                if (r2 >= reach * reach * a * a) continue;
                // The field the pair sits in: applied plus neighbours, less the partner's dipole.
                const double inv_r2 = 1.0 / r2;
                const double c = kInvFourPi * inv_r2 * std::sqrt(inv_r2);  // 1 / (4 pi r^3)
                const Vec3 mi = p.dipole_moment[i], mj = p.dipole_moment[j];
                const Vec3 from_j = dipole_field(mj, d, dot(mj, d), inv_r2, c);
                const Vec3 from_i = dipole_field(mi, d, dot(mi, d), inv_r2, c);
                // A field map was looked up once per grain for this evaluation (the moments').
                const Vec3 applied_i = uniform ? h_uniform : model.applied_flux_density[i] * (1.0 / kMu0);
                const Vec3 applied_j = uniform ? h_uniform : model.applied_flux_density[j] * (1.0 / kMu0);
                const Vec3 h =
                    (applied_i + applied_j + model.neighbour_field[i] + model.neighbour_field[j] - from_j - from_i) *
                    0.5;
                const Vec3 pair_force = close_pair_force(table, d, a, h);
                f[i] += pair_force;
                f[j] -= pair_force;
            }
        }
#pragma omp barrier
        sums.reduce_into(force, begin, end);
    }
}

}  // namespace mrjam
