#pragma once
// What a coalescing cloud has become at one moment (section 4.2 of the source, Tables 4.2 and
// Figs. 4.4-4.6): the largest body (the heaviest cluster of touching grains), its mass share, the
// semi-axes of the uniform ellipsoid with its second moments, its bulk density and porosity (over
// the body and by shell), its net magnetic moment, and how many of the grains left outside it sit
// in chains or clumps.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/vec3.hpp"
#include "system.hpp"

namespace mrjam {

struct BodyDiagnostics {
    double time = 0;                    // s
    std::size_t grains = 0;             // present (escaped ones removed)
    std::size_t body_grains = 0;        // in the heaviest cluster
    double body_mass_fraction = 0;      // of the cloud's initial mass
    Vec3 centre;                        // the body's centre of mass
    double semi_axes[3] = {0, 0, 0};    // m, largest first: sqrt(5 lambda) of the mass covariance
    double bulk_density = 0;            // kg/m3: body mass over the ellipsoid's volume
    double porosity = 0;                // 1 - grain volume / ellipsoid volume
    std::vector<double> shell_packing;  // grain volume fraction in 4 shells of a quarter R_eq each
    double net_dipole = 0;              // A m^2, |sum of the body's moments|
    double dipole_alignment = 0;        // net dipole / sum of |moments| (0 random, 1 all aligned)
    double outside_grouped = 0;         // share of grains outside the body in clusters of 2 or more
    double outside_clumped = 0;         // ... in clusters of more than 10
};

// `initial_mass` is the whole cloud's at the start (escaped grains keep counting against it).
BodyDiagnostics diagnose_body(const System& s, double initial_mass);

// The equivalent-ellipsoid semi-axes of a set of grains (largest first) and their centre of mass:
// a uniform solid ellipsoid of semi-axes a, b, c has the mass covariance diag(a^2, b^2, c^2) / 5;
// each grain adds its own sphere's R^2 / 5 on the diagonal.
void equivalent_ellipsoid(const Particles& p, const std::vector<std::size_t>& members, Vec3& centre,
                          double semi_axes[3]);

nlohmann::json to_json(const BodyDiagnostics& d);

}  // namespace mrjam
