#pragma once
// The two-body correction for close magnetic pairs. Point dipoles (the mutual dipole method the
// engine and the source use) miss the field crowding into the gap of two nearly touching grains:
// for iron (mu_r 1000) the exact attraction of an axial pair is 2.8 times the dipoles' at a gap of
// 0.1 radii and 14 times at 0.01 (`mrjam-bench sphere-pair`). The correction adds, for each pair
// closer than `range`, the exact two-sphere force minus the converged two-dipole force, both for
// the pair alone in the field it sits in (the applied field plus every other neighbour's
// dipoles: the many-body part stays with the dipoles), as in the two-body corrections of
// electrorheological simulation.
//
// Approximations, stated: the material is linear (the iron's saturation near the gap, which
// caps the real force, is not modelled, so this is an upper bound on the close-range attraction);
// an unequal pair is treated as two equal spheres of their mean radius; gaps below `min_gap` (and
// overlaps) take the value at `min_gap`; the correction tapers linearly to zero over the last
// half of `range`.
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct MagneticModel;
struct Particles;

struct ClosePairSettings {
    bool enabled = false;
    double min_gap = 0.03;  // surface gap in mean radii below which the correction stops growing
    double range = 1.0;     // surface gap in mean radii beyond which there is none
};

// The exact-minus-dipole responses of an equal pair, tabulated in log(gap) for one permeability.
class ClosePairTable {
public:
    ClosePairTable() = default;
    ClosePairTable(double relative_permeability, const ClosePairSettings& settings);

    struct Correction {
        double dalpha_axial = 0, dalpha_transverse = 0;  // d(alpha)/ds, exact minus dipoles
        double alpha_axial = 0, alpha_transverse = 0;    // alpha, exact minus dipoles
    };
    // At a surface gap in radii (clamped below min_gap, zero at and beyond range).
    Correction at(double gap) const;
    double relative_permeability() const { return mu_; }
    bool empty() const { return log_gap_.empty(); }

private:
    double mu_ = 0, min_gap_ = 0, range_ = 0;
    std::vector<double> log_gap_;
    std::vector<Correction> rows_;
};

// The correction's force on grain i of a pair (minus it on j), d = x_i - x_j, radius a the pair's
// mean, h the field the pair sits in (A/m). Exposed for the tests.
Vec3 close_pair_force(const ClosePairTable& table, const Vec3& d, double a, const Vec3& h);

// Adds the corrections for every listed magnetic pair within range to `force`, using the current
// moments, model.neighbour_field (as the last pair pass left them) and, in a non-uniform field,
// model.applied_flux_density (as add_magnetic_forces looked it up for this evaluation).
void add_close_pair_forces(const MagneticModel& model, const Particles& p, double time, int threads,
                           std::vector<Vec3>& force);

}  // namespace mrjam
