#pragma once
// Reorders grains so that neighbours in space are neighbours in memory (Morton order of a grid
// about one mean diameter wide). The pair loop then finds a grain's partners in cache instead
// of at random addresses. Done once after insertion, before any contact history exists.
#include "core/domain.hpp"
#include "particles.hpp"

namespace mrjam {

void sort_spatially(Particles& particles, const Domain& domain);

}  // namespace mrjam
