#pragma once
// Everything the engine integrates: grains, walls, the fluid, the physics a scene switched on.
#include <memory>
#include <string>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "contact/material.hpp"
#include "core/domain.hpp"
#include "fluid/flow_field.hpp"
#include "magnetic/magnetic_model.hpp"
#include "neighbor/neighbor_list.hpp"
#include "particles.hpp"
#include "walls.hpp"

namespace mrjam {

// Which physics terms are built. Only what the scene names is on.
struct PhysicsSettings {
    bool contact = true;
    RollingModel rolling = RollingModel::none;
    CohesionModel cohesion = CohesionModel::none;
    bool drag = false;
    // Pairwise contact damping f_i = -c (v_i - v_j) between touching grains (N s/m; 0: off): a
    // dissipation that, unlike drag against a background flow, does not impose the affine
    // velocity profile (Lees-Edwards-free DEM rheology uses it; the shear mode offers it).
    double pair_damping = 0;
    double viscosity = 0;      // Pa s
    double fluid_density = 0;  // kg/m3, for buoyancy under gravity
    // Steps between carrier-flow lookups at the grains (scene: fluid/lookup_interval): the fluid's
    // velocity and hindered-drag factor at each grain are looked up every `flow_lookup_interval`
    // steps and held in between; the drag itself uses the grain's velocity of every step. A grain
    // moves a few nanometres a step against flow features microns wide, while the lookup (grid
    // search, interpolation) was a tenth of the 10 um valve's step (docs/notes/jam_measurements.md, "Held
    // carrier-flow lookups", measures both). 1: every step.
    int flow_lookup_interval = 1;
    bool gravity = false;
    Vec3 gravity_acceleration{};
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

// The carrier flow at each grain from the last lookup, reused while it is younger than
// PhysicsSettings::flow_lookup_interval steps (that lookup's step included). Empty when none is held.
struct HeldFlow {
    std::vector<FlowField::Drag> at;
    int age = 0;
    long held_steps = 0;  // force evaluations that reused held lookups
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
    MagneticModel magnetic;  // off unless the scene has a "magnetic" block
    HeldFlow held_flow;

    double time = 0;
    long step = 0;
    double dt = 0;
    int threads = 1;

    // Largest overlap accepted, as a fraction of the smaller radius, before the run is stopped.
    double max_overlap_fraction = 0.1;
};

}  // namespace mrjam
