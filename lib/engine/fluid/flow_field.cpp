#include "fluid/flow_field.hpp"

#include <algorithm>
#include <stdexcept>

namespace mrjam {

AxialFlow::AxialFlow(int axis, Vec3 centre, std::vector<Station> stations, bool parabolic)
    : axis_(axis), centre_(centre), stations_(std::move(stations)), parabolic_(parabolic) {
    if (stations_.empty()) throw std::invalid_argument("axial flow needs at least one station");
    std::sort(stations_.begin(), stations_.end(),
              [](const Station& a, const Station& b) { return a.position < b.position; });
}

Vec3 AxialFlow::velocity(const Vec3& x, double) const {
    const double s = x[axis_];
    double u = stations_.front().centreline_speed, radius = stations_.front().radius;
    if (s >= stations_.back().position) {
        u = stations_.back().centreline_speed;
        radius = stations_.back().radius;
    } else if (s > stations_.front().position) {
        auto hi = std::upper_bound(stations_.begin(), stations_.end(), s,
                                   [](double v, const Station& st) { return v < st.position; });
        auto lo = hi - 1;
        const double f = (s - lo->position) / (hi->position - lo->position);
        u = lo->centreline_speed + f * (hi->centreline_speed - lo->centreline_speed);
        radius = lo->radius + f * (hi->radius - lo->radius);
    }
    double r2 = 0;
    for (int k = 0; k < 3; ++k)
        if (k != axis_) r2 += (x[k] - centre_[k]) * (x[k] - centre_[k]);
    const double rr = r2 / (radius * radius);
    if (rr >= 1) return {};
    Vec3 v{};
    v[axis_] = parabolic_ ? u * (1 - rr) : u;
    return v;
}

}  // namespace mrjam
