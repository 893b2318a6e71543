#pragma once
// Connected groups of touching grains (union-find over the contact list): the arch that holds a
// jammed throat is one large cluster (Fig. 3.11b of the source).
#include <cstdint>
#include <vector>

#include "system.hpp"

namespace mrjam {

struct ContactClusters {
    std::vector<std::uint32_t> label;  // per grain: cluster index, 0 = the largest cluster
    std::vector<std::size_t> size;     // per cluster, largest first
};

ContactClusters contact_clusters(const System& system);

}  // namespace mrjam
