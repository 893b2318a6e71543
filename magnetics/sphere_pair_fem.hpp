#pragma once
// The force between two equal iron spheres in a uniform field along their line of centres,
// solved by finite elements (gmsh + GetDP, axisymmetric) with the iron's saturation: the
// physics the engine's linear close-pair correction leaves out. Near contact a linear model's
// gap field grows without bound as the gap closes; real iron saturates there first, so the
// attraction of touching grains grows as about H0^(3/2) at low field instead of H0^2 times a
// gap-dependent factor (Ginder and Davis 1994's local saturation).
//
// The half-space above the pair's mid-plane is solved (by symmetry phi = 0 on the plane), the
// upper sphere's centre at z = a + gap/2, the truncation boundary a quarter circle where
// phi = -H0 z. The force on the upper sphere is the Maxwell stress on the mid-plane:
//     F_z = -(mu0 / 2) integral over the plane of (H_z^2 - H_r^2 - H0^2) dA,
// which converges (the pair's dipole field falls as r^-3); the part beyond the truncation
// radius is added from the pair's far dipole field.
// Checked against the exact linear solution (lib/engine/magnetic/sphere_pair_exact) with
// linear iron: within 0.2 % at gaps 0.001-0.1 radii (tests/test_sphere_pair_fem.cpp).
#include <filesystem>

namespace mrjam::magnetics {

struct SpherePairFemRequest {
    double relative_permeability = 1000;      // initial (low-field) permeability of the iron
    bool saturating = true;                   // Frohlich-Kennelly saturation; false: linear iron
    double saturation_magnetisation = 1.7e6;  // M_s, A/m
    double applied_field = 1e5;               // H0 along the line of centres, A/m
    double gap = 0.1;                         // surface gap over the radius
    double outer_radius = 1000;               // truncation radius over the radius
    double refinement = 1;                    // element sizes are divided by this (convergence studies)
};

struct SpherePairFemResult {
    // Axial force on the upper sphere of radius a = 1 m over mu0 H0^2 a^2 (negative: attraction).
    // The engine's linear pair writes the same number as 2 pi d(alpha)/ds.
    double force_coefficient = 0;
    // The pair's total moment over 4 pi a^3 H0, read from its dipole field on the mid-plane far
    // from it (40-100 radii, where the octupole is below 0.1 %).
    double polarisability = 0;
    double max_gap_flux_density = 0;  // largest |B| sampled on the mid-plane, tesla
    int unknowns = 0;
    int newton_steps = 0;
    double seconds = 0;
};

// Meshes and solves one pair in `work_dir` (created if needed). Throws SolverError or
// std::runtime_error with the reason if gmsh or GetDP fails.
SpherePairFemResult solve_sphere_pair_fem(const SpherePairFemRequest&, const std::filesystem::path& work_dir);

}  // namespace mrjam::magnetics
