#pragma once
// Particle state in structure-of-arrays form, SI units, double precision.
// Each field is its own contiguous array so a pass touches only what it needs.
#include <cstdint>
#include <vector>

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
    std::vector<Vec3> dipole_moment;  // A m^2; filled by the magnetic terms (issue 3)
    std::vector<std::uint16_t> material;  // index into the scene's material table
    std::vector<std::uint32_t> groups;    // bit k set: particle belongs to group k
    std::vector<std::uint64_t> id;        // stable id, survives reordering and restarts
    std::vector<std::int16_t> raft;       // -1: free; else index of the raft that moves it rigidly

    std::size_t size() const { return position.size(); }

    void resize(std::size_t n) {
        position.resize(n); velocity.resize(n); angular_velocity.resize(n);
        force.resize(n); torque.resize(n); radius.resize(n); mass.resize(n); inertia.resize(n);
        dipole_moment.resize(n); material.resize(n); groups.resize(n); id.resize(n);
        raft.resize(n, -1);
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
};

}  // namespace mrjam
