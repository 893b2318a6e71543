#pragma once
// Particle state in structure-of-arrays form, SI units, double precision.
// Each field is its own contiguous array so a pass touches only what it needs.
#include <cstdint>
#include <vector>

#include "core/quaternion.hpp"
#include "core/vec3.hpp"

namespace mrjam {

struct Particles {
    std::vector<Vec3> position;
    std::vector<Vec3> velocity;
    std::vector<Vec3> angular_velocity;
    std::vector<Vec3> force;
    std::vector<Vec3> torque;
    std::vector<double> radius;
    std::vector<double> mass;
    std::vector<double> inertia;      // moment of inertia of a solid sphere, 2/5 m R^2
    std::vector<Vec3> dipole_moment;  // A m^2, lab frame, as used for the current forces
    // Magnetic constants of each grain (zero for a non-magnetic grain):
    std::vector<double> induced_coefficient;  // 4 pi R^3 (mu_r - 1)/(mu_r + 2): m = C H (eq. 2.4)
    std::vector<double> saturation_moment;    // M_s V: cap on the induced moment's magnitude
    std::vector<Vec3> permanent_moment;       // body frame, A m^2 (a magnetised grain)
    std::vector<Quaternion> orientation;      // body to lab
    std::vector<std::uint16_t> material;      // index into the scene's material table
    std::vector<std::uint32_t> groups;        // bit k set: particle belongs to group k
    std::vector<std::uint64_t> id;            // stable id, survives reordering and restarts
    std::vector<std::int16_t> raft;           // -1: free; else index of the raft that moves it rigidly

    std::size_t size() const { return position.size(); }

    // Calls f on every per-grain array, so resizing, reordering and checkpointing cannot miss
    // one when a field is added.
    template <class F>
    void for_each_array(F&& f) {
        f(position);
        f(velocity);
        f(angular_velocity);
        f(force);
        f(torque);
        f(radius);
        f(mass);
        f(inertia);
        f(dipole_moment);
        f(induced_coefficient);
        f(saturation_moment);
        f(permanent_moment);
        f(orientation);
        f(material);
        f(groups);
        f(id);
        f(raft);
    }
    template <class F>
    void for_each_array(F&& f) const {
        const_cast<Particles*>(this)->for_each_array([&](const auto& a) { f(a); });
    }

    void resize(std::size_t n) {
        raft.resize(n, -1);  // new grains start free; the generic resize below leaves it as is
        for_each_array([n](auto& a) { a.resize(n); });
    }

    // Appends a sphere at rest; mass and inertia follow from radius and density.
    std::size_t add(const Vec3& x, double r, double density, std::uint16_t mat) {
        const std::size_t i = size();
        resize(i + 1);
        position[i] = x;
        radius[i] = r;
        mass[i] = density * 4.0 / 3.0 * 3.14159265358979323846 * r * r * r;
        inertia[i] = 0.4 * mass[i] * r * r;
        material[i] = mat;
        id[i] = i;
        raft[i] = -1;
        return i;
    }

    // EPSD's rolling inertia of grain i about its contact point, I + m R^2 (Ai et al. eq. 16).
    double rolling_inertia(std::size_t i) const { return inertia[i] + mass[i] * radius[i] * radius[i]; }
};

}  // namespace mrjam
