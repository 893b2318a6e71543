#pragma once
// A body's rotation: its spin rate about z (L_z / I_zz about its centre of mass, the grains'
// own spins included) and a rigid spin-up of it by delta-omega about z through its centre.
#include <cstddef>
#include <vector>

#include "system.hpp"

namespace mrjam {

// The grains of the heaviest contact cluster, and every cluster's mass, heaviest first.
struct BodyMembers {
    std::vector<std::size_t> grains;
    std::vector<double> cluster_masses;            // every cluster's, heaviest first
    std::vector<std::size_t> other_cluster_sizes;  // grains in each cluster but the heaviest
};
BodyMembers heaviest_cluster(const System& s);

struct BodySpin {
    double rate = 0;  // rad/s, L_z / I_zz
    double i_zz = 0;  // kg m^2 about the centre of mass
};
BodySpin body_spin(const Particles& p, const std::vector<std::size_t>& members);

// Adds delta_omega z x (r - r_com) to each member's velocity and delta_omega z to its own spin;
// returns the angular momentum added (I delta_omega z with the body's full inertia tensor; no net
// momentum is added, so it is the same about any point).
Vec3 spin_up_body(Particles& p, const std::vector<std::size_t>& members, double delta_omega);

}  // namespace mrjam
