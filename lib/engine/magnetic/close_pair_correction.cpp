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

// The finite-element table: kSatGaps (radii), kSatFieldsOverMs, and per field a row over the
// gaps of the force coefficient F / (mu0 H0^2 a^2) and the polarisability.
#include "magnetic/saturating_pair_table.inc"

constexpr int kSatGapCount = sizeof(kSatGaps) / sizeof(kSatGaps[0]);
constexpr int kSatFieldCount = sizeof(kSatFieldsOverMs) / sizeof(kSatFieldsOverMs[0]);

// Position of x on an ascending grid: the cell index and the fraction into it (clamped to the ends).
std::pair<int, double> locate(const std::vector<double>& grid, double x) {
    const auto above = std::upper_bound(grid.begin(), grid.end(), x);
    const int k = std::clamp(static_cast<int>(above - grid.begin()) - 1, 0, static_cast<int>(grid.size()) - 2);
    return {k, std::clamp((x - grid[k]) / (grid[k + 1] - grid[k]), 0.0, 1.0)};
}

}  // namespace

const double kSaturatingPairPermeability = kSatPermeability;

const char* close_pair_model_name(ClosePairModel model) {
    return model == ClosePairModel::saturating ? "saturating" : "linear";
}

DipolePairCoefficients capped_dipole_pair(double mu, double s, double h_over_ms) {
    const double beta = clausius_mossotti(mu);
    // m = 4 pi beta (H0 + the partner's axial field 2 m / (4 pi s^3)), in a^3 H0; if that exceeds
    // the cap M_s V, so does the right side at the cap, and both moments sit at it.
    const double m = std::min(4 * M_PI * beta / (1 - 2 * beta / (s * s * s)), 4 * M_PI / 3 / h_over_ms);
    return {-6 * m * m / (4 * M_PI * std::pow(s, 4)), 2 * m / (4 * M_PI)};
}

ClosePairTable::ClosePairTable(double mu, const ClosePairSettings& settings, double saturation_magnetisation)
    : mu_(mu),
      min_gap_(settings.model == ClosePairModel::saturating ? kSatGaps[0] : settings.min_gap),
      range_(settings.range),
      saturation_(saturation_magnetisation),
      model_(settings.model) {
    if (!(min_gap_ > 0) || !(range_ > min_gap_)) throw std::invalid_argument("close pairs: need 0 < min_gap < range");
    if (model_ == ClosePairModel::saturating && (std::abs(mu - kSatPermeability) > 1e-6 * kSatPermeability ||
                                                 !(saturation_ > 0) || range_ > kSatGaps[kSatGapCount - 1]))
        throw std::invalid_argument("saturating close pairs: tabulated for relative permeability " +
                                    std::to_string(kSatPermeability) + ", M_s > 0 and a range up to " +
                                    std::to_string(kSatGaps[kSatGapCount - 1]) + " radii");
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
    if (model_ == ClosePairModel::saturating) build_saturating_grid();
}

// The finite-element force is near a power law in gap and field (attraction at every node), so
// its logarithm is what is interpolated; the moment is smooth as it is.
void ClosePairTable::build_saturating_grid() {
    for (double g : kSatGaps) sat_log_gap_.push_back(std::log(g));
    for (double h : kSatFieldsOverMs) sat_log_field_.push_back(std::log(h));
    for (int f = 0; f < kSatFieldCount; ++f)
        for (int g = 0; g < kSatGapCount; ++g) {
            if (!(kSatForce[f][g] < 0)) throw std::logic_error("saturating pair table: a node does not attract");
            sat_nodes_.push_back({std::log(-kSatForce[f][g]), kSatPolarisability[f][g]});
        }
}

// Bilinear in (log gap, log H/M_s), less the engine's own capped dipole pair at the same gap
// and field. Above the grid's top field the iron is saturated, its moment fixed: the force
// stays, so its coefficient per H^2 falls as (H_top / H)^2 and the polarisability as H_top / H.
void ClosePairTable::saturating_axial(double gap, double axial_field, Correction& c) const {
    const double h = std::max(axial_field / saturation_, 1e-12);
    const double top = kSatFieldsOverMs[kSatFieldCount - 1];
    const double g_clamped = std::max(gap, kSatGaps[0]);
    // Plain locals, not structured bindings: C++17 lambdas cannot capture those (clang refuses).
    const std::pair<int, double> gap_cell = locate(sat_log_gap_, std::log(g_clamped));
    const std::pair<int, double> field_cell = locate(sat_log_field_, std::log(std::clamp(h, kSatFieldsOverMs[0], top)));
    const int g = gap_cell.first, f = field_cell.first;
    const double tg = gap_cell.second, tf = field_cell.second;
    const auto at = [&](int fi, int gi) -> const SaturatingNode& { return sat_nodes_[fi * kSatGapCount + gi]; };
    const auto blend = [&](double SaturatingNode::*m) {
        const double low = at(f, g).*m + tg * (at(f, g + 1).*m - at(f, g).*m);
        const double high = at(f + 1, g).*m + tg * (at(f + 1, g + 1).*m - at(f + 1, g).*m);
        return low + tf * (high - low);
    };
    const double over = h > top ? top / h : 1.0;
    const DipolePairCoefficients dip = capped_dipole_pair(mu_, 2.0 + g_clamped, h);
    c.dalpha_axial = (-std::exp(blend(&SaturatingNode::log_force)) * over * over - dip.force) / (2 * M_PI);
    c.alpha_axial = blend(&SaturatingNode::polarisability) * over - dip.polarisability;
}

ClosePairTable::Correction ClosePairTable::at(double gap, double axial_field) const {
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
    Correction c{mix(a.dalpha_axial, b.dalpha_axial), mix(a.dalpha_transverse, b.dalpha_transverse),
                 mix(a.alpha_axial, b.alpha_axial), mix(a.alpha_transverse, b.alpha_transverse)};
    if (model_ == ClosePairModel::saturating) {
        saturating_axial(gap, axial_field, c);
        c.dalpha_axial *= fade;
        c.alpha_axial *= fade;
    }
    return c;
}

// From the pair's co-energy W' = 2 pi mu0 a^3 H^2 (alpha_ax cos^2 theta + alpha_tr sin^2 theta),
// theta the angle between the line of centres and H: the force along the line is dW'/d(s a) and
// the one across it (in the plane of the line and H, towards larger theta) dW'/d theta / (s a).
Vec3 close_pair_force(const ClosePairTable& table, const Vec3& d, double a, const Vec3& h) {
    const double r = norm(d), h2 = norm2(h);
    if (r == 0.0 || h2 == 0.0) return {};
    const double s = r / a;
    const Vec3 rhat = d * (1.0 / r), hhat = h * (1.0 / std::sqrt(h2));
    const double cos_t = dot(rhat, hhat), cos2 = cos_t * cos_t, sin2 = 1.0 - cos2;
    const ClosePairTable::Correction c = table.at(s - 2.0, std::sqrt(h2) * std::abs(cos_t));
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
