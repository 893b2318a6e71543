#pragma once
// The outlet of a finite batch of grains (model/supply "batch"): the jam scene's tube is periodic
// along z, and a grain that reaches the outlet is taken out instead of re-entering upstream. The
// outlet sits far enough before the downstream end that no grain left in the tube reaches across
// the periodic seam to the batch's upstream end, by contact or by its dipole.
#include <cstddef>

#include "jam/throat_flux.hpp"
#include "system.hpp"

namespace mrjam {

class BatchOutlet {
public:
    // `z_end`: the modelled tube's downstream end. The outlet is the longest pair reach of the
    // contact and magnetic lists (cutoff plus skin, for two of the largest grains) and one largest
    // diameter (what a grain can travel between observations, with room to spare) before it.
    // It must lie at least a largest diameter past `z_throat_exit`, or it would take grains out of
    // the throat's own flow (SceneError naming model/downstream_length otherwise).
    BatchOutlet(const System& s, double z_end, double z_throat_exit, double largest_diameter);
    double z() const { return z_; }
    // Takes out the grains at or past the outlet (also one that went back upstream past the
    // tube's start and was wrapped onto the outlet's side), keeps the flux counter in step, and
    // returns how many went.
    std::size_t drain(System& s, ThroatFlux& flux) const;

private:
    double z_;
};

}  // namespace mrjam
