#pragma once
// Everything the engine integrates: grains, walls, the fluid, the physics a scene switched on.
#include <memory>
#include <string>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "contact/material.hpp"
#include "core/domain.hpp"
#include "fluid/flow_field.hpp"
#include "force_term.hpp"
#include "magnetic/magnetic_model.hpp"
#include "neighbor/neighbor_list.hpp"
#include "particles.hpp"
#include "walls.hpp"

namespace mrjam {

// The contact law the force pass runs (the templated pair loop). Every other piece of physics is
// a ForceTerm in System::terms (lib/engine/force_term.hpp): only what the scene names is built.
struct PhysicsSettings {
    bool contact = true;
    RollingModel rolling = RollingModel::none;
    CohesionModel cohesion = CohesionModel::none;
};

// A group of grains moved rigidly at a prescribed velocity (a raft of a shear cell, a frozen
// layer). The force the free grains exert on it is summed each step: that is the wall stress.
struct Raft {
    std::string name;
    Vec3 velocity{};
    Vec3 force{};
    std::size_t members = 0;
};

// Contact statistics of the last force evaluation.
struct ContactStats {
    std::size_t contacts = 0;
    double max_overlap_ratio = 0;  // overlap / smaller radius
    std::size_t worst_i = 0, worst_j = 0;
    bool worst_is_wall = false;
};

struct System {
    Domain domain;
    Particles particles;
    std::vector<Material> materials;
    PairTable pairs;
    PhysicsSettings physics;
    std::shared_ptr<FlowField> flow = std::make_shared<StillFlow>();
    std::vector<Wall> walls;
    std::vector<Raft> rafts;
    NeighborList contacts;
    ContactStats contact_stats;
    MagneticModel magnetic;  // off unless the scene has a "magnetic" block (then a MagneticTerm adds its forces)
    ForceTerms terms;        // the force terms besides contact, in the order they add (lib/engine/force_term.hpp)

    double time = 0;
    long step = 0;
    double dt = 0;
    int threads = 1;

    // Largest overlap accepted, as a fraction of the smaller radius, before the run is stopped.
    double max_overlap_fraction = 0.1;
};

}  // namespace mrjam
