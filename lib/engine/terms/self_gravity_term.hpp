#pragma once
// The grains' mutual gravity as a force term (lib/engine/gravity/): a Barnes-Hut tree or direct
// summation, evaluated every `update_interval` steps and held in between. The tree costs far
// more per step than the contacts, while the field of a body changes on its dynamical time,
// orders of magnitude above the contact step.
#include <vector>

#include "force_term.hpp"
#include "gravity/self_gravity.hpp"

namespace mrjam {

enum class GravityMethod { tree, direct };

struct SelfGravitySettings {
    GravityMethod method = GravityMethod::tree;
    double constant = kNewtonG;  // G; a scene may scale it (stated similarity rules)
    GravityTree::Settings tree;
    int update_interval = 1;
};

class SelfGravityTerm final : public ForceTerm {
public:
    explicit SelfGravityTerm(const SelfGravitySettings& settings) : settings_(settings), tree_(settings.tree) {
        hold_.interval = settings.update_interval;
    }

    std::string name() const override { return "self_gravity"; }
    std::unique_ptr<ForceTerm> clone() const override { return std::make_unique<SelfGravityTerm>(*this); }
    void add(System& s) override;
    void save(const System& s, std::ostream& out) const override;
    void load(System& s, std::istream& in) override;
    void grains_removed(System& s, const std::vector<std::int64_t>& index, std::size_t kept) override;
    void summarise(const System& s, nlohmann::json& summary) const override;

    const SelfGravitySettings& settings() const { return settings_; }
    // The grains' gravitational potential energy now (direct summation: O(N^2), for reports).
    double potential_energy(const System& s) const;
    // Evaluations so far (steps that built the tree or summed directly).
    long evaluations() const { return evaluations_; }

private:
    SelfGravitySettings settings_;
    GravityTree tree_;
    HoldSchedule hold_;
    std::vector<Vec3> held_acceleration_;
    long evaluations_ = 0;
};

}  // namespace mrjam
