#pragma once
// Magnetic forces between grains: induced (soft) dipoles by the mutual dipole method, permanent
// (hard) dipoles with torque, and the applied field with its gradient force.
//
// Induced moment (eq. 2.4): m = 4 pi R^3 (mu_r - 1)/(mu_r + 2) H_local, with
// H_local = B_ext/mu0 + sum over neighbours within the magnetic cutoff of their dipole fields
// (eq. 2.6). Saturation: the induced magnetisation |m|/V is capped at M_s, keeping its direction
// (the linear law holds up to saturation, then the moment stops growing; a sharp knee, simpler and
// no less defensible than the source's ad hoc cap, and exact in the linear range the tests probe).
// Pair force (eq. 4.8) with rhat from j to i, evaluated once per pair and applied to both grains;
// torque on grains with a permanent moment, m x B_local (eq. 4.9).
#include <cmath>
#include <memory>
#include <string>

#include "force_term.hpp"
#include "magnetic/close_pair_correction.hpp"
#include "magnetic/external_field.hpp"
#include "neighbor/neighbor_list.hpp"
#include "particles.hpp"

namespace mrjam {

inline constexpr double kMu0 = 1.25663706212e-6;  // vacuum permeability, T m / A
inline constexpr double kInvFourPi = 1.0 / (4.0 * M_PI);

// The Clausius-Mossotti contrast of a sphere of relative permeability mu_r in a non-magnetic
// carrier: beta = (mu_r - 1) / (mu_r + 2), 0 for a grain like the carrier, 1 for a perfect magnet.
inline double clausius_mossotti(double relative_permeability) {
    return (relative_permeability - 1) / (relative_permeability + 2);
}

// The field of dipole m at separation d from it (H, A/m), given m.d, inv_r2 = 1/|d|^2 and
// c = 1/(4 pi |d|^3): (3 d (m.d)/|d|^2 - m) c. Even in d, so the same for either end of a pair.
inline Vec3 dipole_field(const Vec3& m, const Vec3& d, double m_d, double inv_r2, double c) {
    return (d * (3.0 * m_d * inv_r2) - m) * c;
}

// Eq. 4.8: the force on dipole m_i from dipole m_j, d = x_i - x_j (rhat from j to i), given
// inv_r2 = 1/|d|^2, c = 1/(4 pi |d|^3) and the projections m_i.d, m_j.d the field pass shares.
inline Vec3 dipole_pair_force(const Vec3& mi, const Vec3& mj, const Vec3& d, double inv_r2, double c, double mi_d,
                              double mj_d) {
    return (mj * mi_d + mi * mj_d + d * (dot(mi, mj) - 5.0 * mi_d * mj_d * inv_r2)) * (3.0 * kMu0 * c * inv_r2);
}

enum class MutualPolicy {
    fixed,       // moments from the applied field only (fixed dipole method)
    lagged,      // neighbours' fields from the previous step's moments: one update per step
    iterations,  // a set number of mutual-dipole iterations per step
    converged,   // iterate until the moments change by less than the tolerance
};

// The policy's name as scene files write it.
const char* policy_name(MutualPolicy policy);

struct MagneticSettings {
    MutualPolicy policy = MutualPolicy::lagged;
    int iterations = 1;        // for `iterations`
    double tolerance = 1e-6;   // for `converged`: max |dm| / max |m|
    int max_iterations = 500;  // for `converged`
    // The mutual update's under-relaxation omega (0, 1]: the induced moments move this share of
    // the way to their Jacobi target per update (magnetic_model.cpp says why 2/3).
    double relaxation = 2.0 / 3.0;
    double cutoff_scale = 0;  // range = scale (R_i + R_j) + extra, at most max_scale (R_i + R_j)
    double cutoff_extra = 0;
    double cutoff_max_scale = 0;  // 0: no cap
    // The two-body correction for close pairs (off: point dipoles only, as the source).
    ClosePairSettings close_pairs;
};

struct MagneticModel {
    bool enabled = false;
    MagneticSettings settings;
    std::shared_ptr<ExternalField> field;
    ClosePairTable close_pair_table;    // built when settings.close_pairs is enabled
    NeighborList pairs;                 // magnetic range; rebuilt with the contact list
    std::vector<Vec3> neighbour_field;  // H at each grain from its neighbours' dipoles, A/m
    // B of a non-uniform applied field at each grain, T: looked up once per evaluation (positions
    // and time are fixed within one) for the moments, the torques and the close-pair correction.
    std::vector<Vec3> applied_flux_density;
    bool any_permanent = false;
    long field_passes = 0;  // mutual-dipole field evaluations so far
    long force_passes = 0;
    long skipped_passes = 0;  // steps with the field off and no permanent moment
    // Multiple time stepping (scene: magnetic/update_interval): the moments, pair forces, torques
    // and gradient forces are evaluated every `hold.interval` steps and held in between. The
    // contact step is set by the grains' stiffness; the dipole forces change on the much slower
    // scale of grains moving a fraction of their size, so holding them a few steps costs little
    // accuracy for a pass that is a third of a step's work (docs/magnetic_forces.md measures it).
    // held_force and held_torque are the last evaluation's (empty when none is held).
    HoldSchedule hold;
    std::vector<Vec3> held_force, held_torque;
};

// True while the magnet acts: the applied field is on, or some grain carries a permanent moment.
// Otherwise every moment is zero and there is nothing to sum (nor a pair list to keep).
bool magnet_acts(const MagneticModel& model, double time);

// Sets every grain's moment from the applied field (and its permanent moment); call after the
// grains and the model are set up and before the first forces.
void initialise_moments(MagneticModel& model, Particles& particles, double time);

// Adds magnetic forces and torques to the grains (after the contact forces), advancing the moments
// as the policy says. Deterministic for a given thread count.
void add_magnetic_forces(MagneticModel& model, Particles& particles, double time, int threads);

// Mean mutual-dipole field evaluations per force evaluation so far (0 for the fixed policy).
double mean_iterations(const MagneticModel& model);

}  // namespace mrjam
