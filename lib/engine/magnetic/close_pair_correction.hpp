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
// Two models of the pair:
//  * linear: the exact two-sphere force of linear iron (lib/engine/magnetic/sphere_pair_exact).
//    Its gap field grows without bound as the gap closes, so the force does too: gaps below
//    `min_gap` (and overlaps) take the value at `min_gap`, a floor the model cannot choose.
//  * saturating: the force with the iron saturating in the gap (Frohlich-Kennelly, M_s), from the
//    axisymmetric finite-element table bundled in saturating_pair_table.inc (written by
//    `mrjam-bench sphere-pair-fem`, magnetics/sphere_pair_fem). Saturation caps the force at
//    contact by itself: no floor. The table is for an axial pair, tabulated in gap (0.001-1
//    radii) and in H/M_s (0.001-1); a pair at angle theta to the field takes the axial part at
//    the field's axial component |H cos theta| (the gap saturates under the flux along the line
//    of centres) and the linear transverse part; gaps below 0.001 radii take the value there
//    (the force is flat in the gap by then), fields above M_s keep the saturated force.
//
// Approximations of both, stated: an unequal pair is treated as two equal spheres of their mean
// radius; the correction tapers linearly to zero over the last half of `range`.
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct MagneticModel;
struct Particles;

enum class ClosePairModel { linear, saturating };

// The model's name as scene files write it.
const char* close_pair_model_name(ClosePairModel model);

struct ClosePairSettings {
    bool enabled = false;
    ClosePairModel model = ClosePairModel::linear;
    double min_gap = 0.03;  // linear model: surface gap in mean radii below which the correction stops growing
    double range = 1.0;     // surface gap in mean radii beyond which there is none
};

// The exact-minus-dipole responses of an equal pair, tabulated in log(gap) for one permeability
// (and, saturating, in log(H / M_s) for the axial part).
class ClosePairTable {
public:
    ClosePairTable() = default;
    // `saturation_magnetisation` (A/m) is the grains' M_s, needed by the saturating model only,
    // whose table is for relative permeability kSaturatingPairPermeability alone (throws otherwise).
    ClosePairTable(double relative_permeability, const ClosePairSettings& settings,
                   double saturation_magnetisation = 0);

    struct Correction {
        double dalpha_axial = 0, dalpha_transverse = 0;  // d(alpha)/ds, exact minus dipoles
        double alpha_axial = 0, alpha_transverse = 0;    // alpha, exact minus dipoles
    };
    // At a surface gap in radii (clamped below the table's smallest gap, zero at and beyond
    // range) and, saturating, the field's component along the line of centres (A/m); both
    // coefficients are per the square of that component.
    Correction at(double gap, double axial_field = 0) const;
    double relative_permeability() const { return mu_; }
    ClosePairModel model() const { return model_; }
    // The gap below which the correction stays at its value there: the linear floor, or the
    // saturating table's smallest gap.
    double min_gap() const { return min_gap_; }
    bool empty() const { return log_gap_.empty(); }

private:
    // The saturating axial correction on its (gap, H / M_s) grid; the linear rows keep the transverse part.
    void build_saturating_grid();
    void saturating_axial(double gap, double axial_field, Correction& c) const;

    double mu_ = 0, min_gap_ = 0, range_ = 0, saturation_ = 0;
    ClosePairModel model_ = ClosePairModel::linear;
    std::vector<double> log_gap_;
    std::vector<Correction> rows_;
    struct SaturatingNode {
        double log_force = 0;       // log of the attraction's coefficient, -F / (mu0 H0^2 a^2)
        double polarisability = 0;  // the pair's moment over 4 pi a^3 H0
    };
    std::vector<double> sat_log_gap_, sat_log_field_;  // grid axes, field over M_s
    std::vector<SaturatingNode> sat_nodes_;            // [field][gap]
};

// The relative permeability the bundled saturating table was solved for.
extern const double kSaturatingPairPermeability;

// An axial pair of point dipoles, mutual and each capped at M_s (the engine's induced moments for
// the pair alone in field H0 = h_over_ms M_s), at centre distance s radii: the force over
// mu0 H0^2 a^2 (negative: attraction) and the total moment over 4 pi a^3 H0.
struct DipolePairCoefficients {
    double force = 0, polarisability = 0;
};
DipolePairCoefficients capped_dipole_pair(double relative_permeability, double separation, double h_over_ms);

// The correction's force on grain i of a pair (minus it on j), d = x_i - x_j, radius a the pair's
// mean, h the field the pair sits in (A/m). Exposed for the tests.
Vec3 close_pair_force(const ClosePairTable& table, const Vec3& d, double a, const Vec3& h);

// Adds the corrections for every listed magnetic pair within range to `force`, using the current
// moments, model.neighbour_field (as the last pair pass left them) and, in a non-uniform field,
// model.applied_flux_density (as add_magnetic_forces looked it up for this evaluation).
void add_close_pair_forces(const MagneticModel& model, const Particles& p, double time, int threads,
                           std::vector<Vec3>& force);

}  // namespace mrjam
