#pragma once
// The simulation box: bounds and which axes are periodic. Non-periodic axes are closed by
// walls the scene declares; the box bounds there only size the cell grid.
//
// Lees-Edwards (sliding periodic) boundaries: with `lees_edwards` on (x and z periodic),
// the image of the box across the shear-gradient boundary z sits displaced along the flow axis x
// by `shear_offset` and moves at `shear_velocity` = rate * Lz along x (the image above: +offset,
// +velocity). A uniform shear then has no walls and no boundary layers (Lees and Edwards 1972;
// Allen and Tildesley, sec. 11.3.2).
#include <array>
#include <cmath>

#include "vec3.hpp"

namespace mrjam {

struct Domain {
    Vec3 lo{0, 0, 0};
    Vec3 hi{1, 1, 1};
    std::array<bool, 3> periodic{false, false, false};
    bool lees_edwards = false;
    double shear_offset = 0;    // m, x shift of the image at z + Lz; kept in [-Lx/2, Lx/2) at rebuilds
    double shear_velocity = 0;  // m/s, x velocity of the image at z + Lz relative to the box
    // A monolayer: the grain centres stay in the mid-plane normal to this axis (-1: 3D). The
    // integrator removes the out-of-plane velocity and every spin component but the one about it.
    int monolayer_normal = -1;

    Vec3 length() const { return hi - lo; }

    // Minimum-image separation b - a on periodic axes (valid while cutoffs stay below L/2,
    // which the neighbour search checks). Under Lees-Edwards the z image is chosen first: it
    // decides the x shift.
    Vec3 separation(const Vec3& a, const Vec3& b) const {
        Vec3 d = b - a;
        if (lees_edwards) {
            const Vec3 L = length();
            const double wz = std::nearbyint(d.z / L.z);
            d.z -= wz * L.z;
            d.x -= wz * shear_offset;
        }
        for (int k = 0; k < 3; ++k) {
            if (!periodic[k]) continue;
            const double L = hi[k] - lo[k];
            d[k] -= L * std::nearbyint(d[k] / L);
        }
        return d;
    }

    // Maps a position back into [lo, hi) on periodic axes.
    void wrap(Vec3& x) const {
        Vec3 unused{};
        wrap(x, unused);
    }

    // The same, and under Lees-Edwards a grain that crosses the z boundary takes the image's
    // x shift and x velocity (out through the top: x - offset, v_x - shear_velocity), so its
    // velocity relative to the affine flow u_x = rate (z - z_mid) is unchanged.
    void wrap(Vec3& x, Vec3& v) const {
        if (lees_edwards) {
            const double Lz = hi.z - lo.z;
            const double periods = std::floor((x.z - lo.z) / Lz);
            if (periods != 0) {
                x.z -= periods * Lz;
                x.x -= periods * shear_offset;
                v.x -= periods * shear_velocity;
            }
        }
        for (int k = 0; k < 3; ++k) {
            if (!periodic[k]) continue;
            const double L = hi[k] - lo[k];
            if (x[k] < lo[k] || x[k] >= hi[k]) {
                x[k] -= L * std::floor((x[k] - lo[k]) / L);
                if (x[k] >= hi[k]) x[k] = lo[k];  // guard against rounding to exactly hi
            }
        }
    }

    // Keeps the Lees-Edwards offset within half a period (called only when the neighbour lists
    // are rebuilt: their stored images assume the offset moves continuously between builds).
    void wrap_shear_offset() {
        if (!lees_edwards) return;
        const double Lx = hi.x - lo.x;
        shear_offset -= Lx * std::floor(shear_offset / Lx + 0.5);
    }
};

}  // namespace mrjam
