#pragma once
// Read-only measurements of the state. They never change it.
#include <nlohmann/json.hpp>

#include "system.hpp"

namespace mrjam {

struct EnergyBreakdown {
    double translational = 0;
    double rotational = 0;
    double elastic = 0;        // Hertz contacts
    double gravitational = 0;  // -m g . x (with buoyancy), 0 without gravity
    double total() const { return translational + rotational + elastic + gravitational; }
};

EnergyBreakdown energy(const System& system);

// Mean number of contacts per grain (2 x contacts / grains, wall contacts counted once).
double mean_coordination(const System& system);

// The induced dipoles' energy in the applied field, -1/2 sum m_i . B0(x_i) (J): for linear
// induced moments the field does twice the stored energy's work in magnetising them, hence the
// half (Jackson 4.7). It falls as chains form and grow, so a steady value means a settled
// structure. 0 with the magnet off or without magnetic grains.
double induced_magnetic_energy(const System& system);

// Snapshot of the state for a report: counts, energies, contacts, raft and wall forces.
nlohmann::json state_summary(const System& system);

}  // namespace mrjam
