#include "magnetics/element_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mrjam::magnetics {

void ElementField::append(const ElementField& other) {
    if (!other.points.empty() && !points.empty() && other.vertices != vertices)
        throw std::invalid_argument("cannot mix element kinds in one field");
    if (points.empty()) vertices = other.vertices;
    points.insert(points.end(), other.points.begin(), other.points.end());
    values.insert(values.end(), other.values.begin(), other.values.end());
}

ElementSampler::ElementSampler(ElementField field) : field_(std::move(field)) {
    const std::size_t ne = field_.elements();
    if (ne == 0) throw std::invalid_argument("no elements to sample from");
    Vec3 lo = field_.points[0], hi = field_.points[0];
    for (const auto& p : field_.points) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const int dims = field_.vertices == 4 ? 3 : 2;
    // About two elements per bucket on average.
    const double extent[3] = {hi.x - lo.x, hi.y - lo.y, dims == 3 ? hi.z - lo.z : 0.0};
    double volume = 1;
    for (int a = 0; a < dims; ++a) volume *= std::max(extent[a], 1e-30);
    const double side = std::pow(volume / std::max<double>(1.0, 0.5 * static_cast<double>(ne)), 1.0 / dims);
    for (int a = 0; a < 3; ++a) n_[a] = a < dims ? std::clamp(static_cast<int>(extent[a] / side) + 1, 1, 1024) : 1;
    lo_ = lo;
    cell_ = {extent[0] / n_[0] + 1e-30, extent[1] / n_[1] + 1e-30, dims == 3 ? extent[2] / n_[2] + 1e-30 : 1.0};

    auto range = [&](std::size_t e, int axis, int& first, int& last) {
        double a = 1e300, b = -1e300;
        for (int v = 0; v < field_.vertices; ++v) {
            const Vec3& p = field_.points[e * field_.vertices + v];
            const double c = axis == 0 ? p.x : axis == 1 ? p.y : p.z;
            a = std::min(a, c);
            b = std::max(b, c);
        }
        const double o = axis == 0 ? lo_.x : axis == 1 ? lo_.y : lo_.z;
        const double h = axis == 0 ? cell_.x : axis == 1 ? cell_.y : cell_.z;
        first = std::clamp(static_cast<int>((a - o) / h), 0, n_[axis] - 1);
        last = std::clamp(static_cast<int>((b - o) / h), 0, n_[axis] - 1);
    };
    std::vector<std::size_t> count(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2] + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            start_.assign(count.size(), 0);
            for (std::size_t b = 0; b + 1 < count.size(); ++b) start_[b + 1] = start_[b] + count[b];
            members_.resize(start_.back());
            std::fill(count.begin(), count.end(), 0);
        }
        for (std::size_t e = 0; e < ne; ++e) {
            int r[3][2];
            for (int a = 0; a < 3; ++a) range(e, a, r[a][0], r[a][1]);
            for (int k = r[2][0]; k <= r[2][1]; ++k)
                for (int j = r[1][0]; j <= r[1][1]; ++j)
                    for (int i = r[0][0]; i <= r[0][1]; ++i) {
                        const std::size_t b = bucket_of(i, j, k);
                        if (pass == 1) members_[start_[b] + count[b]] = e;
                        ++count[b];
                    }
        }
    }
}

bool ElementSampler::weights(std::size_t e, const Vec3& x, double w[4]) const {
    const Vec3* p = &field_.points[e * field_.vertices];
    constexpr double tolerance = 1e-9;
    if (field_.vertices == 4) {
        const Vec3 a = p[1] - p[0], b = p[2] - p[0], c = p[3] - p[0], d = x - p[0];
        const double det = dot(a, cross(b, c));
        if (det == 0) return false;
        w[1] = dot(d, cross(b, c)) / det;
        w[2] = dot(a, cross(d, c)) / det;
        w[3] = dot(a, cross(b, d)) / det;
        w[0] = 1.0 - w[1] - w[2] - w[3];
        return std::min({w[0], w[1], w[2], w[3]}) >= -tolerance;
    }
    const double ax = p[1].x - p[0].x, ay = p[1].y - p[0].y, bx = p[2].x - p[0].x, by = p[2].y - p[0].y;
    const double dx = x.x - p[0].x, dy = x.y - p[0].y;
    const double det = ax * by - ay * bx;
    if (det == 0) return false;
    w[1] = (dx * by - dy * bx) / det;
    w[2] = (ax * dy - ay * dx) / det;
    w[0] = 1.0 - w[1] - w[2];
    w[3] = 0;
    return std::min({w[0], w[1], w[2]}) >= -tolerance;
}

std::optional<Vec3> ElementSampler::sample(const Vec3& x) const {
    const double c[3] = {(x.x - lo_.x) / cell_.x, (x.y - lo_.y) / cell_.y,
                         field_.vertices == 4 ? (x.z - lo_.z) / cell_.z : 0.0};
    int idx[3];
    for (int a = 0; a < 3; ++a) {
        if (c[a] < -1e-9 * n_[a] || c[a] > n_[a] * (1 + 1e-9)) return std::nullopt;
        idx[a] = std::clamp(static_cast<int>(c[a]), 0, n_[a] - 1);
    }
    const std::size_t b = bucket_of(idx[0], idx[1], idx[2]);
    double w[4];
    for (std::size_t m = start_[b]; m < start_[b + 1]; ++m) {
        const std::size_t e = members_[m];
        if (!weights(e, x, w)) continue;
        Vec3 v{0, 0, 0};
        for (int k = 0; k < field_.vertices; ++k) v += field_.values[e * field_.vertices + k] * w[k];
        return v;
    }
    return std::nullopt;
}

}  // namespace mrjam::magnetics
