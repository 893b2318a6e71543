#pragma once
// Taking grains out of a running system (an outflow boundary: grains that leave a finite batch
// are gone). Everything indexed by grain is compacted in step, so the run goes on as if the
// removed grains had never been there: surviving contacts keep their tangential history, the
// neighbour lists stay valid without a rebuild, and the remaining grains keep their order.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "system.hpp"

namespace mrjam {

// Grain i's index after removing those marked in `remove` (-1 for a removed one). The order is
// kept: new indices rise with the old.
std::vector<std::int64_t> surviving_index(const std::vector<char>& remove, std::size_t& kept);

// Removes the grains marked in `remove` (one flag per grain) from the particles, the walls'
// per-grain contact histories and the contact neighbour list, and has each force term compact
// its own per-grain state (ForceTerm::grains_removed: the magnetic pair list and field, held
// forces and flow lookups). Returns how many went.
std::size_t remove_grains(System& s, const std::vector<char>& remove);
// The same with the surviving index already formed (a caller that also compacts arrays of its own).
std::size_t remove_grains(System& s, const std::vector<std::int64_t>& new_index, std::size_t kept);

// The same compaction for any other per-grain array a caller keeps alongside the system.
template <class T>
void compact_by_index(std::vector<T>& a, const std::vector<std::int64_t>& new_index, std::size_t kept) {
    if (a.size() != new_index.size()) return;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (new_index[i] >= 0) a[static_cast<std::size_t>(new_index[i])] = a[i];
    a.resize(kept);
}

}  // namespace mrjam
