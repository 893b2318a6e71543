#include "spatial_sort.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace mrjam {
namespace {

// Spreads the low 21 bits of v so two zero bits separate each (for 3D Morton codes).
std::uint64_t spread_bits(std::uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

template <class T>
void permute(std::vector<T>& v, const std::vector<std::size_t>& order) {
    std::vector<T> out(v.size());
    for (std::size_t k = 0; k < order.size(); ++k) out[k] = v[order[k]];
    v.swap(out);
}

}  // namespace

void sort_spatially(Particles& p, const Domain& domain) {
    const std::size_t n = p.size();
    if (n < 2) return;
    const double mean_d = 2.0 * std::accumulate(p.radius.begin(), p.radius.end(), 0.0) / n;
    std::vector<std::uint64_t> key(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t code = 0;
        for (int k = 0; k < 3; ++k) {
            const double c = std::floor((p.position[i][k] - domain.lo[k]) / mean_d);
            code |= spread_bits(static_cast<std::uint64_t>(std::clamp(c, 0.0, 2097151.0))) << k;
        }
        key[i] = code;
    }
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
    p.for_each_array([&](auto& a) { permute(a, order); });
    for (std::size_t i = 0; i < n; ++i) p.id[i] = i;  // ids follow the new order from the start
}

}  // namespace mrjam
