#include "geometry/packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/exit_status.hpp"

namespace mrjam {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRandomClosePacking = 0.64;
constexpr int kInsertionTries = 100;
constexpr int kMaxBands = 12;
constexpr double kGapCap = 0.1;  // radius bands a factor 2 apart: 4096:1 before bands merge

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// One axis of a cell grid.
struct GridAxis {
    double origin = 0.0;
    double inv_cell = 1.0;
    int n = 1;
    bool wrap = false;

    int index(double x) const {
        int i = static_cast<int>(std::floor((x - origin) * inv_cell));
        if (wrap) {
            i %= n;
            return i < 0 ? i + n : i;
        }
        return std::clamp(i, 0, n - 1);
    }

    // The distinct cells within one of cell i, wrapped where periodic; returns the count.
    int neighbours(int i, std::array<int, 3>& out) const {
        if (wrap && n < 3) {  // ±1 would visit a cell twice
            for (int k = 0; k < n; ++k) out[k] = k;
            return n;
        }
        int m = 0;
        for (int d = -1; d <= 1; ++d) {
            int j = i + d;
            if (wrap)
                j = (j + n) % n;
            else if (j < 0 || j >= n)
                continue;
            out[m++] = j;
        }
        return m;
    }
};

// Centre-binned cell grid for the grains of one radius band, as singly linked lists through a
// `next` array shared by all bands (each grain is in exactly one band).
class CellGrid {
public:
    explicit CellGrid(const std::array<GridAxis, 3>& axes) : axes_(axes) {
        head_.assign(static_cast<std::size_t>(axes[0].n) * axes[1].n * axes[2].n, -1);
    }

    void clear() { std::fill(head_.begin(), head_.end(), -1); }

    void insert(int i, const Vec3& x, std::vector<int>& next) {
        const std::size_t c = cell(axes_[0].index(x.x), axes_[1].index(x.y), axes_[2].index(x.z));
        next[i] = head_[c];
        head_[c] = i;
    }

    // Calls f(j) for every grain in the cells within one of x's cell; stops early when f
    // returns false. Returns false if stopped.
    template <class F>
    bool visit(const Vec3& x, const std::vector<int>& next, F&& f) const {
        std::array<int, 3> ix{}, iy{}, iz{};
        const int nx = axes_[0].neighbours(axes_[0].index(x.x), ix);
        const int ny = axes_[1].neighbours(axes_[1].index(x.y), iy);
        const int nz = axes_[2].neighbours(axes_[2].index(x.z), iz);
        for (int a = 0; a < nz; ++a)
            for (int b = 0; b < ny; ++b)
                for (int c = 0; c < nx; ++c)
                    for (int j = head_[cell(ix[c], iy[b], iz[a])]; j >= 0; j = next[j])
                        if (!f(j)) return false;
        return true;
    }

private:
    std::size_t cell(int i, int j, int k) const {
        return (static_cast<std::size_t>(k) * axes_[1].n + j) * axes_[0].n + i;
    }

    std::array<GridAxis, 3> axes_;
    std::vector<int> head_;
};

// Rejects inputs the packer cannot honour, with messages that say what to change.
void validate(const Region& region, const Domain& domain, double volume_fraction) {
    if (!(volume_fraction > 0.0) || volume_fraction > kRandomClosePacking)
        throw std::invalid_argument("volume fraction " + fmt(volume_fraction) +
                                    " is outside (0, 0.64]; 0.64 is random close packing of spheres, above it a random "
                                    "packing cannot exist (use lattice_packing for denser ordered packings)");
    for (int k = 0; k < 3; ++k) {
        if (!domain.periodic[k] || region.wraps(k, domain)) continue;
        const double tol = 1e-12 * (domain.hi[k] - domain.lo[k]);
        if (region.bbox_lo()[k] < domain.lo[k] - tol || region.bbox_hi()[k] > domain.hi[k] + tol)
            throw std::invalid_argument("on periodic axis " + std::to_string(k) +
                                        " the region must either span the whole period or lie inside the domain");
    }
}

void validate_sizes(const Region& region, const Domain& domain, double d_max) {
    if (!region.fits(0.5 * d_max, domain))
        throw std::invalid_argument("the largest grain (d = " + fmt(d_max) + ") does not fit in the region");
    for (int k = 0; k < 3; ++k)
        if (domain.periodic[k] && domain.hi[k] - domain.lo[k] < 2.0 * d_max)
            throw std::invalid_argument(
                "periodic axis " + std::to_string(k) +
                " is shorter than two largest-grain diameters; minimum image needs a longer period");
}

class Packer {
public:
    Packer(const Region& region, const Domain& domain, std::vector<double> diameters, Rng& rng)
        : region_(region), domain_(domain), rng_(rng) {
        const std::size_t n = diameters.size();
        pos_.resize(n);
        rad_.resize(n);
        vol_.resize(n);
        next_.assign(n, -1);
        for (std::size_t i = 0; i < n; ++i) {
            rad_[i] = 0.5 * diameters[i];
            vol_[i] = rad_[i] * rad_[i] * rad_[i];  // 4pi/3 cancels in the move weights
        }
        for (int k = 0; k < 3; ++k) {
            wrap_[k] = region.wraps(k, domain);
            period_[k] = domain.hi[k] - domain.lo[k];
            half_period_[k] = 0.5 * period_[k];
        }
        assign_bands();
        build_grids();
    }

    // Random sequential addition, largest first; unplaceable grains go to their least bad try.
    void insert_all(const PackingOptions& options) {
        for (int i = 0; i < size(); ++i) {
            if (i % 1024 == 0) check_cancelled(options);
            Vec3 best{};
            double best_ratio = std::numeric_limits<double>::infinity();
            for (int t = 0; t < kInsertionTries && best_ratio > 0.0; ++t) {
                const Vec3 c = region_.sample_centre(rad_[i], domain_, rng_);
                const double ratio = worst_overlap_with_placed(c, i, best_ratio);
                if (ratio < best_ratio) {
                    best_ratio = ratio;
                    best = c;
                }
            }
            pos_[i] = best;
            grids_[band_[i]].insert(i, best, next_);
        }
    }

    // Collective rearrangement until the worst overlap ratio is below tol. Returns the sweeps
    // used, or -1 if max_sweeps were not enough (final_ratio() then says how far off it was).
    int relax(double tol, int max_sweeps, const PackingOptions& options) {
        double sweep_max = std::numeric_limits<double>::infinity();
        for (int sweep = 0;; ++sweep) {
            check_cancelled(options);
            rebuild_grids();
            // A Gauss-Seidel sweep sees partly moved grains, so its own maximum is only a hint;
            // confirm on a fresh grid before declaring success.
            if (sweep == 0 || sweep_max < tol) {
                final_ratio_ = measure();
                if (final_ratio_ < tol) return sweep;
            }
            if (sweep == max_sweeps) {
                final_ratio_ = measure();
                return -1;
            }
            sweep_max = relax_sweep();
        }
    }

    double final_ratio() const { return final_ratio_; }

    std::vector<Sphere> spheres() const {
        std::vector<Sphere> out(pos_.size());
        for (std::size_t i = 0; i < pos_.size(); ++i) out[i] = {pos_[i], rad_[i]};
        return out;
    }

private:
    int size() const { return static_cast<int>(pos_.size()); }

    // Band 0 holds the largest grains; band b holds radii in (r0/2^(b+1), r0/2^b].
    void assign_bands() {
        band_.resize(pos_.size());
        nbands_ = 0;
        if (pos_.empty()) return;
        const double r0 = *std::max_element(rad_.begin(), rad_.end());
        for (std::size_t i = 0; i < rad_.size(); ++i) {
            const int b = static_cast<int>(std::floor(std::log2(r0 / rad_[i])));
            band_[i] = std::clamp(b, 0, kMaxBands - 1);
            nbands_ = std::max(nbands_, band_[i] + 1);
        }
    }

    // Cells of band b are at least the band's largest diameter wide, so every grain of that
    // band touching a grain no larger than it has its centre in the 27 cells around. They are
    // also widened to about one grain per cell, so a few coarse grains in a big region don't
    // allocate a huge empty grid.
    void build_grids() {
        std::vector<double> rmax(nbands_, 0.0);
        std::vector<int> count(nbands_, 0);
        for (std::size_t i = 0; i < rad_.size(); ++i) {
            rmax[band_[i]] = std::max(rmax[band_[i]], rad_[i]);
            ++count[band_[i]];
        }
        Vec3 origin, extent;
        for (int k = 0; k < 3; ++k) {
            origin[k] = wrap_[k] ? domain_.lo[k] : region_.bbox_lo()[k];
            extent[k] = wrap_[k] ? period_[k] : region_.bbox_hi()[k] - origin[k];
        }
        const double grid_volume = extent.x * extent.y * extent.z;
        for (int b = 0; b < nbands_; ++b) {
            const double per_grain = std::cbrt(grid_volume / std::max(count[b], 1));
            const double cell = std::max(2.0 * rmax[b] * (1.0 + 1e-9), per_grain);
            std::array<GridAxis, 3> axes;
            for (int k = 0; k < 3; ++k) {
                axes[k].wrap = wrap_[k];
                axes[k].origin = origin[k];
                axes[k].n = std::max(1, static_cast<int>(std::floor(extent[k] / cell)));
                axes[k].inv_cell = axes[k].n / extent[k];  // actual cell >= requested
            }
            grids_.emplace_back(axes);
        }
    }

    void rebuild_grids() {
        for (auto& g : grids_) g.clear();
        for (int i = 0; i < size(); ++i) grids_[band_[i]].insert(i, pos_[i], next_);
    }

    static double overlap_ratio(double overlap, double ri, double rj) { return overlap / std::min(ri, rj); }

    // Worst overlap ratio of a trial grain i at c against the grains already placed (all in
    // band_[i] or coarser, as placement goes largest first). Stops once above `bound`.
    double worst_overlap_with_placed(const Vec3& c, int i, double bound) const {
        double worst = 0.0;
        const double ri = rad_[i];
        for (int b = 0; b <= band_[i]; ++b) {
            const bool done = !grids_[b].visit(c, next_, [&](int j) {
                const double reach = ri + rad_[j];
                const Vec3 d = separation(c, pos_[j]);
                const double d2 = norm2(d);
                if (d2 >= reach * reach) return true;
                worst = std::max(worst, overlap_ratio(reach - std::sqrt(d2), ri, rad_[j]));
                return worst <= bound;
            });
            if (done) break;
        }
        return worst;
    }

    // Calls f(j) once for each pair (i, j) found from i: grains of coarser bands, and of i's
    // own band with j < i, so each pair is seen exactly once over all i.
    template <class F>
    void for_each_partner(int i, F&& f) const {
        const Vec3 x = pos_[i];
        for (int b = 0; b <= band_[i]; ++b) {
            const bool same = b == band_[i];
            grids_[b].visit(x, next_, [&](int j) {
                if (!same || j < i) f(j);
                return true;
            });
        }
    }

    double measure() const {
        double worst = 0.0;
        for (int i = 0; i < size(); ++i)
            for_each_partner(i, [&](int j) {
                const double reach = rad_[i] + rad_[j];
                const Vec3 d = separation(pos_[i], pos_[j]);
                const double d2 = norm2(d);
                if (d2 < reach * reach) worst = std::max(worst, overlap_ratio(reach - std::sqrt(d2), rad_[i], rad_[j]));
            });
        return worst;
    }

    // One Gauss-Seidel sweep of pairwise overlap removal; returns the worst ratio met.
    double relax_sweep() {
        double worst = 0.0;
        for (int i = 0; i < size(); ++i)
            for_each_partner(i, [&](int j) {
                const double reach = rad_[i] + rad_[j];
                const Vec3 d = separation(pos_[i], pos_[j]);
                const double d2 = norm2(d);
                if (d2 >= reach * reach) return;
                const double dist = std::sqrt(d2);
                worst = std::max(worst, overlap_ratio(reach - dist, rad_[i], rad_[j]));
                separate(i, j, d, dist, reach - dist);
            });
        return worst;
    }

    // Pushes i and j apart along their line of centres, each moving in proportion to the
    // other's volume, then clamps both back into the region. They are pushed past contact,
    // leaving a gap as wide as the overlap was (capped at a tenth of the smaller radius): the
    // gap absorbs part of the push-back from their other neighbours, which cuts the sweeps
    // needed near random close packing several-fold (0.62: ~3000 -> ~200). Without the cap,
    // deep initial overlaps would throw grains through their neighbours and never settle.
    void separate(int i, int j, const Vec3& d, double dist, double overlap) {
        const Vec3 n = dist > 1e-12 * (rad_[i] + rad_[j]) ? d / dist : random_direction();
        const double push = overlap + std::min(overlap, kGapCap * std::min(rad_[i], rad_[j]));
        const double wi = vol_[j] / (vol_[i] + vol_[j]);
        pos_[i] = clamp(pos_[i] - n * (push * wi), rad_[i]);
        pos_[j] = clamp(pos_[j] + n * (push * (1.0 - wi)), rad_[j]);
    }

    // Region::clamp_centre with the box case inlined: it runs for every overlapping pair.
    Vec3 clamp(Vec3 c, double r) const {
        if (region_.kind != Region::Kind::box) return region_.clamp_centre(c, r, domain_);
        for (int k = 0; k < 3; ++k) {
            if (!wrap_[k]) {
                c[k] = std::clamp(c[k], region_.lo[k] + r, region_.hi[k] - r);
            } else if (c[k] < domain_.lo[k] || c[k] >= domain_.hi[k]) {
                c[k] -= period_[k] * std::floor((c[k] - domain_.lo[k]) / period_[k]);
                if (c[k] >= domain_.hi[k]) c[k] = domain_.lo[k];
            }
        }
        return c;
    }

    // Minimum image b - a. Centres are kept in the domain on periodic axes, so one period is
    // the most that can need removing; this avoids nearbyint in the innermost loop.
    Vec3 separation(const Vec3& a, const Vec3& b) const {
        Vec3 d = b - a;
        for (int k = 0; k < 3; ++k) {
            if (!domain_.periodic[k]) continue;
            if (d[k] > half_period_[k])
                d[k] -= period_[k];
            else if (d[k] < -half_period_[k])
                d[k] += period_[k];
        }
        return d;
    }

    // Coincident centres have no line between them; any direction will do, from the seeded Rng.
    Vec3 random_direction() {
        for (;;) {
            const Vec3 v{rng_.normal(), rng_.normal(), rng_.normal()};
            const double n = norm(v);
            if (n > 1e-6) return v / n;
        }
    }

    const Region& region_;
    const Domain& domain_;
    Rng& rng_;
    std::vector<Vec3> pos_;
    std::vector<double> rad_;
    std::vector<double> vol_;
    std::vector<int> band_;
    std::vector<int> next_;
    std::vector<CellGrid> grids_;
    std::array<bool, 3> wrap_{};
    Vec3 period_, half_period_;
    int nbands_ = 0;
    double final_ratio_ = 0.0;
};

}  // namespace

void check_cancelled(const PackingOptions& options) {
    if (options.cancelled && options.cancelled())
        throw SetupInterrupted("interrupted while placing the grains (nothing was run, so there is nothing to resume)");
}

PackingResult random_packing(const Region& region, const Domain& domain, const SizeDistribution& sizes,
                             double volume_fraction, Rng& rng, const PackingOptions& options) {
    validate(region, domain, volume_fraction);
    validate_sizes(region, domain, sizes.max_diameter());
    const double region_volume = region.volume(domain);
    std::vector<double> diameters = sizes.sample_for_volume(volume_fraction * region_volume, rng);

    PackingResult result;
    if (diameters.empty()) return result;  // region smaller than about half a grain

    Packer packer(region, domain, std::move(diameters), rng);
    packer.insert_all(options);
    const int sweeps = packer.relax(options.overlap_tolerance, options.max_sweeps, options);
    if (sweeps < 0)
        throw std::runtime_error("could not reach volume fraction " + fmt(volume_fraction) +
                                 " (worst overlap / radius still " + fmt(packer.final_ratio()) + " after " +
                                 std::to_string(options.max_sweeps) +
                                 " sweeps); try a lower volume fraction (random close packing is ~0.64, less near "
                                 "walls and for narrow size spreads)");

    result.spheres = packer.spheres();
    double solid = 0.0;
    for (const auto& s : result.spheres) solid += 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
    result.achieved_volume_fraction = solid / region_volume;
    result.max_overlap_ratio = packer.final_ratio();
    result.sweeps = sweeps;
    return result;
}

namespace {

// A lattice as a rectangular repeat cell (in units of the nearest-neighbour spacing) and the
// sites inside it (fractions of the cell).
struct LatticeCell {
    Vec3 period;
    std::vector<Vec3> basis;
};

LatticeCell lattice_cell(const std::string& name) {
    if (name == "cubic" || name == "sc") return {{1, 1, 1}, {{0, 0, 0}}};
    if (name == "bcc") {
        const double a = 2.0 / std::sqrt(3.0);  // body diagonal = 2 spacings
        return {{a, a, a}, {{0, 0, 0}, {0.5, 0.5, 0.5}}};
    }
    if (name == "fcc") {
        const double a = std::sqrt(2.0);  // face diagonal = 2 spacings
        return {{a, a, a}, {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}}};
    }
    if (name == "hcp") {
        // Triangular layers (rows 1 apart in x, sqrt(3) per two rows in y) stacked ABAB in z
        // with layer gap sqrt(2/3); B sites sit over the centroids of A triangles.
        const double b = std::sqrt(3.0), c = 2.0 * std::sqrt(2.0 / 3.0);
        return {{1, b, c}, {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 1.0 / 6.0, 0.5}, {0, 2.0 / 3.0, 0.5}}};
    }
    throw std::invalid_argument("unknown lattice '" + name + "' (use cubic, bcc, fcc or hcp)");
}

}  // namespace

std::vector<Sphere> lattice_packing(const Region& region, const Domain& domain, double diameter, double spacing,
                                    const std::string& lattice) {
    if (!(diameter > 0.0) || !std::isfinite(diameter)) throw std::invalid_argument("diameter must be positive");
    if (!(spacing >= diameter * (1.0 - 1e-12)) || !std::isfinite(spacing))
        throw std::invalid_argument("spacing " + fmt(spacing) + " is below the diameter " + fmt(diameter) +
                                    "; spheres would overlap");
    const LatticeCell cell = lattice_cell(lattice);
    const double r = 0.5 * diameter;
    const Vec3 P = cell.period * spacing;

    // Per axis: lattice origin and how many repeat cells to lay.
    Vec3 origin;
    std::array<long, 3> count{};
    std::array<bool, 3> wrap{};
    for (int k = 0; k < 3; ++k) {
        wrap[k] = region.wraps(k, domain);
        if (wrap[k]) {
            const double L = domain.hi[k] - domain.lo[k];
            count[k] = static_cast<long>(std::floor(L / P[k] * (1.0 + 1e-12)));
            if (count[k] < 1)
                throw std::invalid_argument("the period on axis " + std::to_string(k) +
                                            " is shorter than one lattice period");
            origin[k] = domain.lo[k] + r;
        } else {
            origin[k] = region.bbox_lo()[k] + r;  // first layer touches the low face
            const double span = region.bbox_hi()[k] - origin[k];
            count[k] = static_cast<long>(std::ceil(span / P[k])) + 1;
        }
    }
    if (static_cast<double>(count[0]) * count[1] * count[2] * cell.basis.size() > 1e8)
        throw std::invalid_argument("more than 1e8 lattice sites; use a larger spacing");

    std::vector<Sphere> out;
    for (long iz = 0; iz < count[2]; ++iz)
        for (long iy = 0; iy < count[1]; ++iy)
            for (long ix = 0; ix < count[0]; ++ix)
                for (const Vec3& f : cell.basis) {
                    const Vec3 idx{static_cast<double>(ix), static_cast<double>(iy), static_cast<double>(iz)};
                    Vec3 c;
                    for (int k = 0; k < 3; ++k) c[k] = origin[k] + (idx[k] + f[k]) * P[k];
                    if (!region.contains_sphere(c, r, domain)) continue;
                    domain.wrap(c);  // only wrapping axes can be outside the domain here
                    out.push_back({c, r});
                }
    return out;
}

}  // namespace mrjam
