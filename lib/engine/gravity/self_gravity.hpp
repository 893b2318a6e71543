#pragma once
// Newtonian self-gravity of the grains in open space: a Barnes-Hut octree with monopole and
// quadrupole moments (as in the gravity trees of pkdgrav and Sanchez & Scheeres' rubble-pile
// code), and direct summation as its reference. Isolated boundaries: no periodic images.
//
// Two grains closer than R_i + R_j attract as if touching (the separation is clamped at contact):
// their overlap is the contact law's business, and the force stays finite when centres meet.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

struct Particles;

inline constexpr double kNewtonG = 6.67430e-11;  // m^3 / (kg s^2), CODATA 2018

// The acceleration of grain i from grain j (d = x_j - x_i), separation clamped at contact.
inline Vec3 pair_gravity(const Vec3& d, double mass_j, double contact, double G) {
    const double r2 = dot(d, d);
    if (r2 == 0) return {};
    const double r = std::sqrt(r2), clamped = std::max(r, contact);
    return d * (G * mass_j / (r * clamped * clamped));
}

// Every grain's acceleration by direct summation over all pairs, O(N^2).
void direct_gravity(const Particles& p, double G, std::vector<Vec3>& acceleration, int threads);

// The grains' gravitational potential energy, -G sum_{i<j} m_i m_j / max(r_ij, R_i + R_j), O(N^2).
double gravitational_energy(const Particles& p, double G);

class GravityTree {
public:
    struct Settings {
        double opening_angle = 0.5;  // theta: a node of side s is used whole beyond s / theta
        int leaf_size = 8;           // most grains in a leaf
        bool quadrupole = true;      // false: monopoles only (the accuracy test's control)
    };

    GravityTree() = default;
    explicit GravityTree(const Settings& settings) : settings_(settings) {}

    // Builds the tree over the grains' current positions and computes the nodes' moments.
    void build(const Particles& p);
    // Every grain's acceleration from the tree built last (same grains, same positions).
    void accelerations(const Particles& p, double G, std::vector<Vec3>& acceleration, int threads) const;
    std::size_t nodes() const { return nodes_.size(); }
    const Settings& settings() const { return settings_; }

private:
    struct Node {
        Vec3 centre;  // of the cube
        double side = 0;
        Vec3 com;
        double mass = 0;
        double q[6] = {0, 0, 0, 0, 0, 0};  // traceless quadrupole sum m (3 s s - s^2 I): xx yy zz xy xz yz
        double reach = 0;                  // side / theta + |com - centre|: used whole beyond it
        std::size_t begin = 0, end = 0;    // range of order_
        int first_child = -1;              // children are nodes_[first_child .. first_child + children)
        int children = 0;
    };
    int make_node(const Particles& p, std::size_t begin, std::size_t end, const Vec3& centre, double side, int depth);
    void split(const Particles& p, int node, int depth);
    void compute_moments(const Particles& p, int node);
    Vec3 acceleration_of(const Particles& p, std::size_t i, double G) const;

    Settings settings_;
    std::vector<Node> nodes_;
    std::vector<std::size_t> order_;  // grain indices, each node's a contiguous range
};

}  // namespace mrjam
