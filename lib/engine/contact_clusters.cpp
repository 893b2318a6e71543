#include "contact_clusters.hpp"

#include <algorithm>
#include <numeric>

namespace mrjam {

namespace {
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];  // path halving
        i = parent[i];
    }
    return i;
}
}  // namespace

ContactClusters contact_clusters(const System& s) {
    const std::size_t n = s.particles.size();
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    const NeighborList& list = s.contacts;
    for (std::size_t i = 0; i + 1 < list.offsets.size() && i < n; ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            if (!list.touching[k]) continue;
            const std::uint32_t a = root(parent, static_cast<std::uint32_t>(i)), b = root(parent, list.partners[k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<std::size_t> count(n, 0);
    for (std::size_t i = 0; i < n; ++i) ++count[root(parent, static_cast<std::uint32_t>(i))];
    std::vector<std::uint32_t> roots;
    for (std::size_t i = 0; i < n; ++i)
        if (count[i] > 0) roots.push_back(static_cast<std::uint32_t>(i));
    std::stable_sort(roots.begin(), roots.end(), [&](auto a, auto b) { return count[a] > count[b]; });
    std::vector<std::uint32_t> rank(n, 0);
    ContactClusters out;
    for (std::size_t r = 0; r < roots.size(); ++r) {
        rank[roots[r]] = static_cast<std::uint32_t>(r);
        out.size.push_back(count[roots[r]]);
    }
    out.label.resize(n);
    for (std::size_t i = 0; i < n; ++i) out.label[i] = rank[root(parent, static_cast<std::uint32_t>(i))];
    return out;
}

}  // namespace mrjam
