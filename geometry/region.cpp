#include "geometry/region.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mrjam {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The two axes perpendicular to a cylinder axis.
int other_axis(int axis, int which) { return (axis + 1 + which) % 3; }

double wrap_coordinate(double x, double lo, double hi) {
    const double L = hi - lo;
    x -= L * std::floor((x - lo) / L);
    return x >= hi ? lo : x;  // rounding can land exactly on hi
}

}  // namespace

Region Region::box(const Vec3& lo, const Vec3& hi) {
    for (int k = 0; k < 3; ++k)
        if (!(hi[k] > lo[k]) || !std::isfinite(lo[k]) || !std::isfinite(hi[k]))
            throw std::invalid_argument("hi must exceed lo on every axis (axis " + std::to_string(k) + ")");
    Region r;
    r.kind = Kind::box;
    r.lo = lo;
    r.hi = hi;
    return r;
}

Region Region::cylinder(const Vec3& base_centre, int axis, double radius, double length) {
    if (axis < 0 || axis > 2) throw std::invalid_argument("axis must be 0 (x), 1 (y) or 2 (z)");
    if (!(radius > 0.0) || !(length > 0.0) || !std::isfinite(radius) || !std::isfinite(length))
        throw std::invalid_argument("radius and length must be positive");
    Region r;
    r.kind = Kind::cylinder;
    r.base = base_centre;
    r.axis = axis;
    r.radius = radius;
    r.length = length;
    return r;
}

double Region::volume() const {
    if (kind == Kind::box) {
        const Vec3 e = hi - lo;
        return e.x * e.y * e.z;
    }
    return kPi * radius * radius * length;
}

double Region::volume(const Domain& domain) const {
    const Vec3 L = domain.length();
    if (kind == Kind::box) {
        double v = 1.0;
        for (int k = 0; k < 3; ++k) v *= wraps(k, domain) ? L[k] : hi[k] - lo[k];
        return v;
    }
    return kPi * radius * radius * (wraps(axis, domain) ? L[axis] : length);
}

Vec3 Region::bbox_lo() const {
    if (kind == Kind::box) return lo;
    Vec3 b = base;
    b[other_axis(axis, 0)] -= radius;
    b[other_axis(axis, 1)] -= radius;
    return b;
}

Vec3 Region::bbox_hi() const {
    if (kind == Kind::box) return hi;
    Vec3 b = base;
    b[axis] += length;
    b[other_axis(axis, 0)] += radius;
    b[other_axis(axis, 1)] += radius;
    return b;
}

bool Region::wraps(int k, const Domain& domain) const {
    if (!domain.periodic[k]) return false;
    // A round cross-section never tiles a period, so only a cylinder's own axis can wrap.
    if (kind == Kind::cylinder && k != axis) return false;
    const double tol = 1e-12 * (domain.hi[k] - domain.lo[k]);
    return bbox_lo()[k] <= domain.lo[k] + tol && bbox_hi()[k] >= domain.hi[k] - tol;
}

bool Region::contains_sphere(const Vec3& c, double r, const Domain& domain) const {
    const Vec3 blo = bbox_lo(), bhi = bbox_hi();
    const Vec3 ext = bhi - blo;
    const double eps = 1e-12 * std::max({ext.x, ext.y, ext.z});
    if (kind == Kind::box) {
        for (int k = 0; k < 3; ++k) {
            if (wraps(k, domain)) continue;
            if (c[k] - r < lo[k] - eps || c[k] + r > hi[k] + eps) return false;
        }
        return true;
    }
    if (!wraps(axis, domain)) {
        const double s = c[axis] - base[axis];
        if (s - r < -eps || s + r > length + eps) return false;
    }
    const double du = c[other_axis(axis, 0)] - base[other_axis(axis, 0)];
    const double dv = c[other_axis(axis, 1)] - base[other_axis(axis, 1)];
    return std::sqrt(du * du + dv * dv) + r <= radius + eps;
}

bool Region::fits(double r, const Domain& domain) const {
    if (kind == Kind::box) {
        for (int k = 0; k < 3; ++k)
            if (!wraps(k, domain) && hi[k] - lo[k] < 2.0 * r) return false;
        return true;
    }
    return radius >= r && (wraps(axis, domain) || length >= 2.0 * r);
}

Vec3 Region::sample_centre(double r, Rng& rng) const { return sample_centre(r, Domain{}, rng); }

Vec3 Region::sample_centre(double r, const Domain& domain, Rng& rng) const {
    if (!fits(r, domain))
        throw std::invalid_argument("Region::sample_centre: a sphere of radius " + std::to_string(r) +
                                    " does not fit in the region");
    Vec3 c;
    if (kind == Kind::box) {
        for (int k = 0; k < 3; ++k)
            c[k] = wraps(k, domain) ? rng.uniform(domain.lo[k], domain.hi[k]) : rng.uniform(lo[k] + r, hi[k] - r);
        return c;
    }
    // Uniform in the disc of radius R - r: the radius goes as sqrt(u) for uniform area density.
    const double rho = (radius - r) * std::sqrt(rng.uniform());
    const double theta = 2.0 * kPi * rng.uniform();
    c[other_axis(axis, 0)] = base[other_axis(axis, 0)] + rho * std::cos(theta);
    c[other_axis(axis, 1)] = base[other_axis(axis, 1)] + rho * std::sin(theta);
    c[axis] = wraps(axis, domain) ? rng.uniform(domain.lo[axis], domain.hi[axis])
                                  : rng.uniform(base[axis] + r, base[axis] + length - r);
    return c;
}

Vec3 Region::clamp_centre(const Vec3& c, double r, const Domain& domain) const {
    Vec3 out = c;
    if (kind == Kind::box) {
        for (int k = 0; k < 3; ++k)
            out[k] = wraps(k, domain) ? wrap_coordinate(c[k], domain.lo[k], domain.hi[k])
                                      : std::clamp(c[k], lo[k] + r, hi[k] - r);
        return out;
    }
    out[axis] = wraps(axis, domain) ? wrap_coordinate(c[axis], domain.lo[axis], domain.hi[axis])
                                    : std::clamp(c[axis], base[axis] + r, base[axis] + length - r);
    const int u = other_axis(axis, 0), v = other_axis(axis, 1);
    const double du = c[u] - base[u], dv = c[v] - base[v];
    const double rho = std::sqrt(du * du + dv * dv);
    const double rmax = radius - r;
    if (rho > rmax) {  // project radially onto the allowed disc
        const double s = rho > 0.0 ? rmax / rho : 0.0;
        out[u] = base[u] + du * s;
        out[v] = base[v] + dv * s;
    }
    return out;
}

}  // namespace mrjam
