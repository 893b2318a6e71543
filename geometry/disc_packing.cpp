#include "geometry/disc_packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>

namespace mrjam {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kInsertionTries = 100;

std::string fmt(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// Two in-plane axes of a box, each either wrapping (periodic) or closed.
struct Plane {
    int axis[2];
    double lo[2], len[2];
    bool wrap[2];

    // Minimum-image in-plane separation b - a.
    void separation(const double a[2], const double b[2], double d[2]) const {
        for (int k = 0; k < 2; ++k) {
            d[k] = b[k] - a[k];
            if (wrap[k]) d[k] -= len[k] * std::nearbyint(d[k] / len[k]);
        }
    }
    // Back into the box: wrapped on periodic axes, inside by the radius on closed ones.
    void confine(double x[2], double r) const {
        for (int k = 0; k < 2; ++k) {
            if (wrap[k])
                x[k] -= len[k] * std::floor((x[k] - lo[k]) / len[k]);
            else
                x[k] = std::clamp(x[k], lo[k] + r, lo[k] + len[k] - r);
        }
    }
};

// Cell grid over the plane with cells at least one largest diameter wide: every pair that can
// touch lies in neighbouring cells.
class Grid {
public:
    Grid(const Plane& p, double d_max, std::size_t n) : plane_(p), next_(n, -1) {
        for (int k = 0; k < 2; ++k) {
            count_[k] = std::max(1, static_cast<int>(std::floor(p.len[k] / d_max)));
            cell_[k] = p.len[k] / count_[k];
        }
        head_.assign(static_cast<std::size_t>(count_[0]) * count_[1], -1);
    }
    void clear() { std::fill(head_.begin(), head_.end(), -1); }
    void insert(int i, const double x[2]) {
        const std::size_t c = index(cell_of(x[0], 0), cell_of(x[1], 1));
        next_[i] = head_[c];
        head_[c] = i;
    }
    // Calls f(j) for every disc in the cells around x (each cell once).
    template <class F>
    void visit(const double x[2], F&& f) const {
        int cells[2][3], n[2];
        for (int k = 0; k < 2; ++k) {
            const int c = cell_of(x[k], k);
            n[k] = 0;
            if (plane_.wrap[k] && count_[k] < 3) {
                for (int m = 0; m < count_[k]; ++m) cells[k][n[k]++] = m;
                continue;
            }
            for (int d = -1; d <= 1; ++d) {
                int m = c + d;
                if (plane_.wrap[k])
                    m = (m + count_[k]) % count_[k];
                else if (m < 0 || m >= count_[k])
                    continue;
                cells[k][n[k]++] = m;
            }
        }
        for (int a = 0; a < n[0]; ++a)
            for (int b = 0; b < n[1]; ++b)
                for (int j = head_[index(cells[0][a], cells[1][b])]; j >= 0; j = next_[j]) f(j);
    }

private:
    int cell_of(double x, int k) const {
        return std::clamp(static_cast<int>(std::floor((x - plane_.lo[k]) / cell_[k])), 0, count_[k] - 1);
    }
    std::size_t index(int a, int b) const { return static_cast<std::size_t>(b) * count_[0] + a; }

    const Plane& plane_;
    int count_[2];
    double cell_[2];
    std::vector<int> head_, next_;
};

}  // namespace

DiscPackingResult random_disc_packing(const Domain& domain, int normal, const SizeDistribution& sizes,
                                      double area_fraction, Rng& rng, const PackingOptions& options) {
    if (!(area_fraction > 0.0) || area_fraction > kRandomClosePackingDiscs)
        throw std::invalid_argument("area fraction " + fmt(area_fraction) +
                                    " is outside (0, 0.84]; 0.84 is random close packing of discs, above it a random "
                                    "packing of discs cannot exist");
    if (normal < 0 || normal > 2 || domain.periodic[normal])
        throw std::invalid_argument("the monolayer's normal axis must be one of x, y, z and not periodic");
    Plane plane;
    for (int k = 0; k < 2; ++k) {
        plane.axis[k] = (normal + 1 + k) % 3;
        plane.lo[k] = domain.lo[plane.axis[k]];
        plane.len[k] = domain.hi[plane.axis[k]] - domain.lo[plane.axis[k]];
        plane.wrap[k] = domain.periodic[plane.axis[k]];
    }
    const double d_max = sizes.max_diameter();
    for (int k = 0; k < 2; ++k)
        if ((plane.wrap[k] && plane.len[k] < 2 * d_max) || (!plane.wrap[k] && plane.len[k] <= d_max))
            throw std::invalid_argument(
                "the box is " + fmt(plane.len[k]) + " m along " + std::string(1, char('x' + plane.axis[k])) +
                ", too short for the largest grain (" + fmt(d_max) + " m; a periodic side needs two diameters)");
    if (domain.hi[normal] - domain.lo[normal] < d_max)
        throw std::invalid_argument("the layer is thinner than the largest grain");

    // Diameters until the disc area is closest to the target, largest first.
    const double target = area_fraction * plane.len[0] * plane.len[1];
    std::vector<double> diameters;
    double area = 0;
    for (;;) {
        const double d = sizes.sample(rng), a = 0.25 * kPi * d * d;
        if (area + a < target) {
            diameters.push_back(d);
            area += a;
            continue;
        }
        if (area + a - target < target - area) {
            diameters.push_back(d);
            area += a;
        }
        break;
    }
    std::sort(diameters.begin(), diameters.end(), std::greater<>());
    const std::size_t n = diameters.size();
    std::vector<double> r(n), w(n);  // radius, area weight (pi cancels)
    std::vector<std::array<double, 2>> x(n);
    for (std::size_t i = 0; i < n; ++i) {
        r[i] = 0.5 * diameters[i];
        w[i] = r[i] * r[i];
    }

    Grid grid(plane, d_max, n);
    auto worst_overlap_at = [&](std::size_t i, const double xi[2], std::size_t placed) {
        double worst = 0;
        grid.visit(xi, [&](int j) {
            if (static_cast<std::size_t>(j) >= placed || static_cast<std::size_t>(j) == i) return;
            double d[2];
            plane.separation(xi, x[j].data(), d);
            const double overlap = r[i] + r[j] - std::hypot(d[0], d[1]);
            if (overlap > 0) worst = std::max(worst, overlap / std::min(r[i], r[j]));
        });
        return worst;
    };
    // Random sequential addition.
    for (std::size_t i = 0; i < n; ++i) {
        if (i % 1024 == 0) check_cancelled(options);
        double best[2] = {0, 0}, best_worst = INFINITY;
        for (int t = 0; t < kInsertionTries; ++t) {
            double c[2];
            for (int k = 0; k < 2; ++k)
                c[k] = plane.wrap[k] ? rng.uniform(plane.lo[k], plane.lo[k] + plane.len[k])
                                     : rng.uniform(plane.lo[k] + r[i], plane.lo[k] + plane.len[k] - r[i]);
            const double worst = worst_overlap_at(i, c, i);
            if (worst < best_worst) {
                best_worst = worst;
                best[0] = c[0];
                best[1] = c[1];
            }
            if (worst == 0) break;
        }
        x[i] = {best[0], best[1]};
        grid.insert(static_cast<int>(i), x[i].data());
    }
    // Collective rearrangement (Gauss-Seidel sweeps over overlapping pairs).
    DiscPackingResult out;
    for (;;) {
        check_cancelled(options);
        grid.clear();
        for (std::size_t i = 0; i < n; ++i) grid.insert(static_cast<int>(i), x[i].data());
        double worst = 0;
        for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, worst_overlap_at(i, x[i].data(), n));
        out.max_overlap_ratio = worst;
        if (worst < options.overlap_tolerance) break;
        if (out.sweeps >= options.max_sweeps)
            throw std::runtime_error("overlaps still " + fmt(worst) + " of a radius after " +
                                     std::to_string(out.sweeps) + " sweeps; lower the area fraction");
        ++out.sweeps;
        for (std::size_t i = 0; i < n; ++i) {
            grid.visit(x[i].data(), [&](int jj) {
                const std::size_t j = static_cast<std::size_t>(jj);
                if (j <= i) return;
                double d[2];
                plane.separation(x[i].data(), x[j].data(), d);
                const double dist = std::hypot(d[0], d[1]);
                const double overlap = r[i] + r[j] - dist;
                if (overlap <= 0) return;
                // Push past contact by the overlap, at most 0.1 of the smaller radius (over-relaxation).
                const double push = overlap + std::min(overlap, 0.1 * std::min(r[i], r[j]));
                double e[2] = {1, 0};
                if (dist > 0) {
                    e[0] = d[0] / dist;
                    e[1] = d[1] / dist;
                }
                const double wi = w[j] / (w[i] + w[j]);
                for (int k = 0; k < 2; ++k) {
                    x[i][k] -= e[k] * push * wi;
                    x[j][k] += e[k] * push * (1 - wi);
                }
                plane.confine(x[i].data(), r[i]);
                plane.confine(x[j].data(), r[j]);
            });
        }
    }
    const double mid = 0.5 * (domain.lo[normal] + domain.hi[normal]);
    out.discs.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 c{};
        c[normal] = mid;
        c[plane.axis[0]] = x[i][0];
        c[plane.axis[1]] = x[i][1];
        out.discs[i] = Sphere{c, r[i]};
    }
    out.achieved_area_fraction = area / (plane.len[0] * plane.len[1]);
    return out;
}

}  // namespace mrjam
