#include "asteroid/rubble_ledger.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "grain_removal.hpp"
#include "gravity/self_gravity.hpp"
#include "observers.hpp"

namespace mrjam {

namespace {

struct Momenta {
    Vec3 linear, angular;  // the latter about the origin, spins included
};

Momenta momenta(const Particles& p) {
    Momenta m;
    for (std::size_t i = 0; i < p.size(); ++i) {
        m.linear += p.velocity[i] * p.mass[i];
        m.angular += cross(p.position[i], p.velocity[i]) * p.mass[i] + p.angular_velocity[i] * p.inertia[i];
    }
    return m;
}

Vec3 vec3_of(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }
nlohmann::json json_of(const Vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

void RubbleLedger::open(const System& s, double escape_radius, double cloud_radius) {
    const Particles& p = s.particles;
    escape_radius_ = escape_radius;
    initial_mass_ = 0;
    momentum_scale_ = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        initial_mass_ += p.mass[i];
        momentum_scale_ += p.mass[i] * norm(p.velocity[i]) * (1.0 + norm(p.position[i]) / cloud_radius);
    }
    const Momenta m = momenta(p);
    initial_linear_ = m.linear;
    initial_angular_ = m.angular;
}

std::size_t RubbleLedger::remove_escaped(System& s) {
    const double r2 = escape_radius_ * escape_radius_;
    Particles& p = s.particles;
    std::vector<char> out(p.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (norm2(p.position[i]) > r2) {
            out[i] = 1;
            any = true;
            removed_linear_ += p.velocity[i] * p.mass[i];
            removed_angular_ += cross(p.position[i], p.velocity[i]) * p.mass[i] + p.angular_velocity[i] * p.inertia[i];
            escaped_mass_ += p.mass[i];
        }
    if (!any) return 0;
    const std::size_t n = remove_grains(s, out);
    escaped_ += n;
    return n;
}

nlohmann::json RubbleLedger::conservation(const System& s) const {
    const Momenta m = momenta(s.particles);
    const Vec3 dp = m.linear + removed_linear_ - initial_linear_;
    const Vec3 dl = m.angular + removed_angular_ - initial_angular_;
    const EnergyBreakdown e = energy(s);
    // What the motion carries now, the scale an unbalanced force or torque is measured against:
    // sum m |v| and sum m |r x v| + I |omega| (a cloud that starts cold has no momenta to compare with).
    const Particles& p = s.particles;
    double bulk = 0, turning = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        bulk += p.mass[i] * norm(p.velocity[i]);
        turning += p.mass[i] * norm(cross(p.position[i], p.velocity[i])) + p.inertia[i] * norm(p.angular_velocity[i]);
    }
    const double l_scale = std::max(norm(initial_angular_), turning);
    return {{"momentum_drift", norm(dp) / std::max(bulk, momentum_scale_)},
            {"angular_momentum_drift", l_scale > 0 ? norm(dl) / l_scale : 0.0},
            {"kinetic_J", e.translational + e.rotational},
            {"gravitational_J", gravitational_energy(s.particles, kNewtonG)}};
}

nlohmann::json RubbleLedger::to_json() const {
    return {{"escape_radius_m", escape_radius_},
            {"initial_mass_kg", initial_mass_},
            {"momentum_scale", momentum_scale_},
            {"initial_momentum", json_of(initial_linear_)},
            {"initial_angular_momentum", json_of(initial_angular_)},
            {"escaped_momentum", json_of(removed_linear_)},
            {"escaped_angular_momentum", json_of(removed_angular_)},
            {"escaped_grains", escaped_},
            {"escaped_mass_kg", escaped_mass_}};
}

RubbleLedger RubbleLedger::from_json(const nlohmann::json& j) {
    RubbleLedger l;
    l.escape_radius_ = j.at("escape_radius_m").get<double>();
    l.initial_mass_ = j.at("initial_mass_kg").get<double>();
    l.momentum_scale_ = j.at("momentum_scale").get<double>();
    l.initial_linear_ = vec3_of(j.at("initial_momentum"));
    l.initial_angular_ = vec3_of(j.at("initial_angular_momentum"));
    l.removed_linear_ = vec3_of(j.at("escaped_momentum"));
    l.removed_angular_ = vec3_of(j.at("escaped_angular_momentum"));
    l.escaped_ = j.at("escaped_grains").get<std::size_t>();
    l.escaped_mass_ = j.at("escaped_mass_kg").get<double>();
    return l;
}

}  // namespace mrjam
