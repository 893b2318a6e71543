#pragma once
// Insertion regions: where new grains may be put. A box, or a cylinder with its axis along x,
// y or z (a valve tube, a die, a column).
//
// Periodic axes: when a region spans the whole period of a periodic axis of the Domain, that
// axis is treated as unbounded (a grain may straddle the boundary; its image is inside), so a
// periodic box filled by a full-domain region has no artificial walls. A region that does not
// span the period is clipped on that axis like any other.
#include "core/domain.hpp"
#include "core/random.hpp"
#include "core/vec3.hpp"

namespace mrjam {

struct Region {
    enum class Kind { box, cylinder };

    Kind kind = Kind::box;
    // Box: the two corners.
    Vec3 lo{0, 0, 0};
    Vec3 hi{1, 1, 1};
    // Cylinder: centre of the base disc, axis index (0 = x, 1 = y, 2 = z), radius, length along
    // +axis from the base.
    Vec3 base{0, 0, 0};
    int axis = 2;
    double radius = 0.0;
    double length = 0.0;

    // Throw std::invalid_argument for an empty/inverted box, a bad axis, non-positive sizes.
    static Region box(const Vec3& lo, const Vec3& hi);
    static Region cylinder(const Vec3& base_centre, int axis, double radius, double length);

    // Geometric volume of the region.
    double volume() const;
    // Volume inside the domain: on periodic axes the region spans, one period.
    double volume(const Domain& domain) const;

    // Axis-aligned bounding box.
    Vec3 bbox_lo() const;
    Vec3 bbox_hi() const;

    // True when axis k of the domain is periodic and the region covers the whole period, so
    // the axis imposes no bound on centres.
    bool wraps(int k, const Domain& domain) const;

    // Sphere of radius r at c lies fully inside (to rounding, 1e-12 of the region size). On
    // wrapping axes there is no bound.
    bool contains_sphere(const Vec3& c, double r, const Domain& domain) const;

    // True if a sphere of radius r fits somewhere in the region.
    bool fits(double r, const Domain& domain) const;

    // A centre uniform among those keeping a sphere of radius r inside; on wrapping axes,
    // uniform over the period. Throws std::invalid_argument if the sphere cannot fit.
    Vec3 sample_centre(double r, Rng& rng) const;  // no periodic axes
    Vec3 sample_centre(double r, const Domain& domain, Rng& rng) const;

    // The allowed centre nearest to c (c itself if allowed), wrapped into the domain on
    // wrapping axes. Assumes fits(r, domain).
    Vec3 clamp_centre(const Vec3& c, double r, const Domain& domain) const;
};

}  // namespace mrjam
