#pragma once
// The coalescence mode's initial cloud (section 4.2 of the source): grains on a simple cubic
// lattice inside a sphere, thermal (Maxwell-Boltzmann) velocities and spins, and a rigid spin of
// the whole cloud about z, v_i = v_thermal + omega x r_i; and the two ratios that say whether
// such a cloud can collapse at all.
#include <cstdint>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct Particles;

// The `count` simple-cubic lattice sites nearest the origin (ties broken by z, y, x, so the set is
// the same on every machine), leaving out sites whose grain of `diameter` would come closer than
// `clearance` to the origin (a seed grain's radius plus a gap; 0 keeps them all).
std::vector<Vec3> lattice_cloud(long count, double spacing, double diameter, double clearance);

// Gives the grains flagged in `thermal` velocities with each component normal with deviation
// `thermal_speed` and spins by equipartition (each component sigma sqrt(m / I)); removes the
// mass-weighted mean velocity, so the cloud's centre of mass is at rest; then adds the rigid spin
// omega z x (r - r_com) to every grain (the seed grain too).
void give_cloud_motion(Particles& p, const std::vector<char>& thermal, double thermal_speed, double spin,
                       std::uint64_t seed);

struct CloudEnergetics {
    double mass = 0;            // kg, every grain
    double radius = 0;          // m, farthest grain surface from the centre of mass
    double kinetic = 0;         // J, translational and rotational, in the centre-of-mass frame
    double spin_kinetic = 0;    // J, the part of the rigid spin (1/2 I_zz omega^2 of the lattice)
    double binding = 0;         // J, -U = G sum m_i m_j / r_ij (separations clamped at contact)
    double virial_ratio = 0;    // kinetic / binding: above 1 the cloud is unbound
    double orbital_rate = 0;    // rad/s, sqrt(G M / R^3): a circular orbit at the cloud's edge
    double spin_ratio = 0;      // |spin| / orbital_rate
    double free_fall_time = 0;  // s, sqrt(3 pi / (32 G rho)) for the cloud's mean density
};

CloudEnergetics cloud_energetics(const Particles& p, double spin, double G);

}  // namespace mrjam
