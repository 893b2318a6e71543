// Template body of gradient_b2_statistics (included from epm_field.hpp).
#include <cmath>

namespace mrjam::magnetics {

template <class Inside>
std::pair<double, double> gradient_b2_statistics(const FieldGrid& g, Inside inside) {
    const auto at = [&](int i, int j, int k) {
        const Vec3& b = g.values[(static_cast<std::size_t>(k) * g.count[1] + j) * g.count[0] + i];
        return dot(b, b);
    };
    const auto derivative = [&](int i, int j, int k, int axis) {
        int idx[3] = {i, j, k};
        const int n = g.count[axis];
        if (n < 2) return 0.0;
        const double h = axis == 0 ? g.spacing.x : axis == 1 ? g.spacing.y : g.spacing.z;
        int lo[3] = {i, j, k}, hi[3] = {i, j, k};
        lo[axis] = std::max(idx[axis] - 1, 0);
        hi[axis] = std::min(idx[axis] + 1, n - 1);
        return (at(hi[0], hi[1], hi[2]) - at(lo[0], lo[1], lo[2])) / ((hi[axis] - lo[axis]) * h);
    };
    double sum = 0, max = 0;
    std::size_t count = 0;
    for (int k = 0; k < g.count[2]; ++k)
        for (int j = 0; j < g.count[1]; ++j)
            for (int i = 0; i < g.count[0]; ++i) {
                const Vec3 x{g.origin.x + i * g.spacing.x, g.origin.y + j * g.spacing.y, g.origin.z + k * g.spacing.z};
                if (!inside(x)) continue;
                const double gx = derivative(i, j, k, 0), gy = derivative(i, j, k, 1), gz = derivative(i, j, k, 2);
                const double norm = std::sqrt(gx * gx + gy * gy + gz * gz);
                sum += norm;
                max = std::max(max, norm);
                ++count;
            }
    return {count ? sum / count : 0.0, max};
}

}  // namespace mrjam::magnetics
