#pragma once
// The simulation box: bounds and which axes are periodic. Non-periodic axes are closed by
// walls the scene declares; the box bounds there only size the cell grid.
#include <array>
#include <cmath>

#include "vec3.hpp"

namespace mrjam {

struct Domain {
    Vec3 lo{0, 0, 0};
    Vec3 hi{1, 1, 1};
    std::array<bool, 3> periodic{false, false, false};

    Vec3 length() const { return hi - lo; }

    // Minimum-image separation b - a on periodic axes (valid while cutoffs stay below L/2,
    // which the neighbour search checks).
    Vec3 separation(const Vec3& a, const Vec3& b) const {
        Vec3 d = b - a;
        for (int k = 0; k < 3; ++k) {
            if (!periodic[k]) continue;
            const double L = hi[k] - lo[k];
            d[k] -= L * std::nearbyint(d[k] / L);
        }
        return d;
    }

    // Maps a position back into [lo, hi) on periodic axes.
    void wrap(Vec3& x) const {
        for (int k = 0; k < 3; ++k) {
            if (!periodic[k]) continue;
            const double L = hi[k] - lo[k];
            if (x[k] < lo[k] || x[k] >= hi[k]) {
                x[k] -= L * std::floor((x[k] - lo[k]) / L);
                if (x[k] >= hi[k]) x[k] = lo[k];  // guard against rounding to exactly hi
            }
        }
    }
};

}  // namespace mrjam
