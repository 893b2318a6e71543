#pragma once
// The flow rate a flow field carries through the valve's section at z, by the midpoint rule on
// n rings of the passage (the valve flows' tests check continuity with it).
#include <cmath>

#include "fluid/flow_field.hpp"
#include "geometry/valve.hpp"

namespace mrjam_test {

inline double section_flow_rate(const mrjam::FlowField& f, const mrjam::ValveGeometry& v, double z, int n) {
    const double R = v.passage_radius(z);
    double q = 0;
    for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * R / n;
        q += f.velocity({r, 0, z}, 0).z * 2 * M_PI * r * R / n;
    }
    return q;
}

}  // namespace mrjam_test
