#include "grain_removal.hpp"

#include <stdexcept>

namespace mrjam {

std::vector<std::int64_t> surviving_index(const std::vector<char>& remove, std::size_t& kept) {
    std::vector<std::int64_t> index(remove.size(), -1);
    kept = 0;
    for (std::size_t i = 0; i < remove.size(); ++i)
        if (!remove[i]) index[i] = static_cast<std::int64_t>(kept++);
    return index;
}

std::size_t remove_grains(System& s, const std::vector<char>& remove) {
    std::size_t kept = 0;
    const std::vector<std::int64_t> index = surviving_index(remove, kept);
    return remove_grains(s, index, kept);
}

std::size_t remove_grains(System& s, const std::vector<std::int64_t>& index, std::size_t kept) {
    const std::size_t n = s.particles.size();
    if (index.size() != n) throw std::logic_error("remove_grains: one flag or index per grain expected");
    if (kept == n) return 0;
    for (std::size_t i = 0; i < n; ++i)
        if (index[i] < 0 && s.particles.raft[i] >= 0) --s.rafts[static_cast<std::size_t>(s.particles.raft[i])].members;
    s.particles.for_each_array([&](auto& a) { compact_by_index(a, index, kept); });
    for (auto& w : s.walls) {
        compact_by_index(w.history, index, kept);
        w.near.valid = false;  // every grain is tested until the next neighbour rebuild
    }
    s.contacts.remove_grains(index, kept);
    for (auto& term : s.terms) term->grains_removed(s, index, kept);
    return n - kept;
}

}  // namespace mrjam
