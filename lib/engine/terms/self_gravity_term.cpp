#include "terms/self_gravity_term.hpp"

#include <nlohmann/json.hpp>

#include "core/binary_io.hpp"
#include "grain_removal.hpp"
#include "system.hpp"

namespace mrjam {

// The held values are accelerations, not forces: a grain's mass does not change between
// evaluations, and a held acceleration stays right for a grain whose index moved.
void SelfGravityTerm::add(System& s) {
    Particles& p = s.particles;
    if (hold_.reuse_now(held_acceleration_.size(), p.size())) {
        hold_.reused_once();
    } else {
        if (settings_.method == GravityMethod::tree) {
            tree_.build(p);
            tree_.accelerations(p, settings_.constant, held_acceleration_, s.threads);
        } else {
            direct_gravity(p, settings_.constant, held_acceleration_, s.threads);
        }
        ++evaluations_;
        hold_.evaluated();
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 f = held_acceleration_[i] * p.mass[i];
        p.force[i] += f;
        if (p.raft[i] >= 0) s.rafts[p.raft[i]].force += f;
    }
}

void SelfGravityTerm::save(const System&, std::ostream& out) const {
    hold_.save(out);
    binary::put(out, evaluations_);
    binary::put_vector(out, held_acceleration_);
}

void SelfGravityTerm::load(System&, std::istream& in) {
    hold_.load(in);
    evaluations_ = binary::get<long>(in);
    binary::get_vector(in, held_acceleration_);
}

void SelfGravityTerm::grains_removed(System&, const std::vector<std::int64_t>& index, std::size_t kept) {
    if (!held_acceleration_.empty()) compact_by_index(held_acceleration_, index, kept);
}

double SelfGravityTerm::potential_energy(const System& s) const {
    return gravitational_energy(s.particles, settings_.constant);
}

void SelfGravityTerm::summarise(const System&, nlohmann::json& summary) const {
    nlohmann::json j = {{"method", settings_.method == GravityMethod::tree ? "tree" : "direct"},
                        {"constant_m3_kg_s2", settings_.constant},
                        {"update_interval_steps", hold_.interval},
                        {"evaluations", evaluations_},
                        {"steps_with_held_forces", hold_.reused}};
    if (settings_.method == GravityMethod::tree) {
        j["opening_angle"] = settings_.tree.opening_angle;
        j["leaf_size"] = settings_.tree.leaf_size;
        j["quadrupole"] = settings_.tree.quadrupole;
    }
    summary["self_gravity"] = j;
}

}  // namespace mrjam
