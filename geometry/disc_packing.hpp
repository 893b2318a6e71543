#pragma once
// Random packing of discs in a plane: the initial state of a monolayer cell (grains whose centres
// all lie in one plane of the box, normal to one axis).
#include "core/domain.hpp"
#include "core/random.hpp"
#include "geometry/packing.hpp"
#include "geometry/size_distribution.hpp"

namespace mrjam {

// Random close packing of equal discs is about 0.84 of the plane (jamming of bidisperse and
// polydisperse discs lies at 0.84-0.85); a random packing above it cannot be made.
inline constexpr double kRandomClosePackingDiscs = 0.84;

struct DiscPackingResult {
    std::vector<Sphere> discs;          // centres in the mid-plane normal to the axis, largest first
    double achieved_area_fraction = 0;  // disc area / plane area of the box
    double max_overlap_ratio = 0;       // worst overlap / smaller radius, all pairs
    int sweeps = 0;
};

// Discs drawn from `sizes` until their total area is closest to `area_fraction` of the box's
// cross-section normal to `normal_axis`, placed by random sequential addition (largest first,
// up to 100 tries each), then relaxed by sweeps of pairwise overlap removal (each pair pushed
// apart along its line of centres in proportion to the other's area, slightly past contact)
// until the worst overlap is below options.overlap_tolerance of the smaller radius. In-plane axes
// wrap where the domain is periodic (minimum image) and keep discs inside the box where closed.
// The centres sit halfway along the normal axis. Throws std::invalid_argument for an area
// fraction outside (0, 0.84], a normal axis that is periodic, or discs that do not fit;
// std::runtime_error if the sweeps do not converge.
DiscPackingResult random_disc_packing(const Domain& domain, int normal_axis, const SizeDistribution& sizes,
                                      double area_fraction, Rng& rng, const PackingOptions& options = {});

}  // namespace mrjam
