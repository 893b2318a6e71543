#pragma once
// What a scene's pair lists will take, bounded before they are built: a shear cell of sub-micron
// grains with the source's 8 um magnetic reach grew to 24 GB, because the grain-count limit
// (geometry/size_distribution.cpp) counts about 2 kB a grain and not the pairs a long cutoff lists.
#include "core/physical_memory.hpp"
#include "system.hpp"

namespace mrjam {

struct PairMemoryEstimate {
    double contact_pairs = 0, magnetic_pairs = 0;
    double bytes = 0;  // grains, both lists and the copies a rebuild holds
};

// An upper bound: each grain's neighbours within its list's cutoff (mean grain, skin included) at
// a dense packing (volume fraction 0.64), at most every other grain.
PairMemoryEstimate estimate_pair_memory(const System& s);

// Refuses (SceneError at /magnetic/cutoff when the magnetic list dominates, else /grains) a scene
// whose estimate exceeds 80 % of the physical memory.
void check_pair_memory(const System& s);

}  // namespace mrjam
