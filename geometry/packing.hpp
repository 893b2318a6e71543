#pragma once
// Initial grain configurations: random packings at a target solid volume fraction and
// regular lattices, inside an insertion Region of a Domain (minimum image on periodic axes).
#include <functional>
#include <string>
#include <vector>

#include "core/domain.hpp"
#include "core/random.hpp"
#include "core/vec3.hpp"
#include "geometry/region.hpp"
#include "geometry/size_distribution.hpp"

namespace mrjam {

struct Sphere {
    Vec3 centre;
    double radius;
};

struct PackingOptions {
    double overlap_tolerance = 1e-3;  // max overlap / smaller radius accepted
    int max_sweeps = 20000;           // relaxation sweeps before giving up
    // Asked every 1024 insertions and every sweep; true stops the packing with SetupInterrupted
    // (core/exit_status.hpp). The scene passes Ctrl-C's flag.
    std::function<bool()> cancelled;
};

// Throws SetupInterrupted when the options' cancel check says so.
void check_cancelled(const PackingOptions& options);

struct PackingResult {
    std::vector<Sphere> spheres;          // largest first
    double achieved_volume_fraction = 0;  // solid volume / region.volume(domain)
    double max_overlap_ratio = 0;         // worst overlap / smaller radius, all pairs
    int sweeps = 0;                       // relaxation sweeps used
};

// Random packing of grains drawn from `sizes` filling `volume_fraction` of the region.
//
// Method:
//  1. Diameters: sizes.sample_for_volume(volume_fraction * region.volume(domain)), largest
//     first, so the achieved fraction differs from the target only by the last grain's rounding.
//  2. Random sequential addition, largest first: up to 100 uniform centres are tried for each
//     grain and the first without overlap is taken. A grain with no overlap-free try is put at
//     the try with the smallest worst overlap.
//  3. Collective rearrangement: repeated sweeps of geometric overlap removal. Each overlapping
//     pair (minimum image on periodic axes) is pushed apart along the line of centres, each grain
//     moving in proportion to the OTHER's volume (a fine grain moves out of a coarse one's way),
//     and moved centres are clamped back into the region at once (Gauss-Seidel: later pairs
//     see the update). Each pair is pushed slightly past contact, to a gap equal to its overlap
//     but at most 0.1 of the smaller radius; that over-relaxation cuts the sweeps needed near
//     random close packing several-fold. Sweeps repeat until the worst overlap / smaller radius
//     is below options.overlap_tolerance, checked on a fresh neighbour grid with no moves.
// Neighbour search is O(N) for any size ratio: grains are binned by radius into bands a factor
// 2 apart, each band with its own grid of cells at least one band-diameter wide; a grain looks
// only at the 27 cells around it in its own band and in coarser bands, which holds every grain
// of those bands that it can touch. Each pair is thus found once, from its finer grain.
//
// Throws std::invalid_argument for volume_fraction <= 0 or > 0.64 (random close packing of
// spheres), a largest grain that does not fit in the region or whose diameter exceeds half a
// period, or a region that neither spans nor lies within a periodic axis of the domain.
// Throws std::runtime_error if options.max_sweeps sweeps do not reach the tolerance.
PackingResult random_packing(const Region& region, const Domain& domain, const SizeDistribution& sizes,
                             double volume_fraction, Rng& rng, const PackingOptions& options = {});

// Spheres of `diameter` on the sites of a lattice whose nearest-neighbour centre distance is
// `spacing`, keeping only spheres fully inside the region. Lattices: "cubic" (simple cubic),
// "bcc", "fcc", "hcp" (close-packed layers normal to z, ABAB). On bounded axes the first layer
// touches the region's low face; on axes where the region wraps a periodic domain, whole lattice
// periods are laid along the period so images never come closer than `spacing`. Throws
// std::invalid_argument for an unknown lattice, diameter <= 0, spacing < diameter, or a period
// shorter than one lattice period.
std::vector<Sphere> lattice_packing(const Region& region, const Domain& domain, double diameter, double spacing,
                                    const std::string& lattice);

}  // namespace mrjam
