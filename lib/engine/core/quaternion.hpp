#pragma once
// Unit quaternion for the orientation of a grain that carries a body-fixed (permanent) dipole.
#include <cmath>

#include "core/vec3.hpp"

namespace mrjam {

struct Quaternion {
    double w = 1, x = 0, y = 0, z = 0;

    // Rotates a body-frame vector into the lab frame: v' = q v q*.
    Vec3 rotate(const Vec3& v) const {
        const Vec3 u{x, y, z};
        const Vec3 t = cross(u, v) * 2.0;
        return v + t * w + cross(u, t);
    }

    // Advances the orientation by an angular velocity (lab frame) over dt: q <- exp(dt/2 omega) q,
    // exact for constant omega over the step, so the quaternion stays of unit length.
    void advance(const Vec3& omega, double dt) {
        const double angle = norm(omega) * dt;
        if (angle == 0) return;
        const Vec3 axis = omega * (1.0 / norm(omega));
        const double s = std::sin(0.5 * angle), c = std::cos(0.5 * angle);
        const Quaternion r{c, axis.x * s, axis.y * s, axis.z * s};
        *this = Quaternion{r.w * w - r.x * x - r.y * y - r.z * z, r.w * x + r.x * w + r.y * z - r.z * y,
                           r.w * y - r.x * z + r.y * w + r.z * x, r.w * z + r.x * y - r.y * x + r.z * w};
        const double n = std::sqrt(w * w + x * x + y * y + z * z);  // rounding only
        w /= n;
        x /= n;
        y /= n;
        z /= n;
    }
};

}  // namespace mrjam
