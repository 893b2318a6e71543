#include "observers.hpp"

#include <cmath>

#include "forces.hpp"
#include "terms/gravity_term.hpp"

namespace mrjam {

EnergyBreakdown energy(const System& s) {
    EnergyBreakdown e;
    const Particles& p = s.particles;
    for (std::size_t i = 0; i < p.size(); ++i) {
        e.translational += 0.5 * p.mass[i] * norm2(p.velocity[i]);
        e.rotational += 0.5 * p.inertia[i] * norm2(p.angular_velocity[i]);
    }
    if (const GravityTerm* g = s.terms.find<GravityTerm>()) e.gravitational = g->potential_energy(s);
    if (s.physics.contact) e.elastic = contact_elastic_energy(s);
    return e;
}

double mean_coordination(const System& s) {
    const std::size_t n = s.particles.size();
    return n ? 2.0 * static_cast<double>(s.contact_stats.contacts) / static_cast<double>(n) : 0.0;
}

double induced_magnetic_energy(const System& s) {
    if (!s.magnetic.enabled || !s.magnetic.field) return 0.0;
    double sum = 0;
    const auto& g = s.particles;
    for (std::size_t i = 0; i < g.size(); ++i)
        sum += dot(g.dipole_moment[i], s.magnetic.field->flux_density(g.position[i], s.time));
    return -0.5 * sum;
}

nlohmann::json state_summary(const System& s) {
    const EnergyBreakdown e = energy(s);
    nlohmann::json j;
    j["grains"] = s.particles.size();
    double total_mass = 0;
    for (double m : s.particles.mass) total_mass += m;
    j["total_mass_kg"] = total_mass;
    j["steps"] = s.step;
    j["simulated_time_s"] = s.time;
    j["timestep_s"] = s.dt;
    j["kinetic_energy_J"] = e.translational;
    j["rotational_energy_J"] = e.rotational;
    j["elastic_energy_J"] = e.elastic;
    j["contacts"] = s.contact_stats.contacts;
    j["mean_coordination"] = mean_coordination(s);
    j["max_overlap_ratio"] = s.contact_stats.max_overlap_ratio;
    j["neighbour_builds"] = s.contacts.builds();
    j["neighbour_pairs"] = s.contacts.pair_count();
    for (const auto& term : s.terms) term->summarise(s, j);
    for (const Raft& r : s.rafts)
        j["rafts"].push_back({{"name", r.name},
                              {"grains", r.members},
                              {"force_N", {r.force.x, r.force.y, r.force.z}},
                              {"velocity_m_s", {r.velocity.x, r.velocity.y, r.velocity.z}}});
    for (const Wall& w : s.walls)
        j["walls"].push_back({{"name", w.name},
                              {"force_N", {w.force.x, w.force.y, w.force.z}},
                              {"point_m", {w.point.x, w.point.y, w.point.z}}});
    return j;
}

}  // namespace mrjam
