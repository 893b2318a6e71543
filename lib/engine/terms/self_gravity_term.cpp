#include "terms/self_gravity_term.hpp"

#include <nlohmann/json.hpp>

#include "core/binary_io.hpp"
#include "grain_removal.hpp"
#include "system.hpp"

namespace mrjam {

namespace {

// The tree's forces are not pairwise (a node pulls a grain with the node's moments, the grain
// pulls the node's grains one by one), so they sum to a net force an isolated system does not
// have, and its momentum would drift by the tree's error every evaluation. The mass-weighted mean
// acceleration, of the order of that error, is taken off every grain.
void remove_net_force(const Particles& p, std::vector<Vec3>& acceleration) {
    Vec3 net{};
    double mass = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        net += acceleration[i] * p.mass[i];
        mass += p.mass[i];
    }
    if (mass <= 0) return;
    net = net / mass;
    for (Vec3& a : acceleration) a -= net;
}

}  // namespace

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
            remove_net_force(p, held_acceleration_);
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
