#include "terms/drag_term.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/binary_io.hpp"
#include "grain_removal.hpp"
#include "system.hpp"

namespace mrjam {

DragTerm::DragTerm(double viscosity, int lookup_interval) : viscosity_(viscosity) { hold_.interval = lookup_interval; }

void DragTerm::begin_pass(const System& s) {
    const std::size_t n = s.particles.size();
    if (!hold_.holding()) {
        lookup_ = Lookup::fresh;
        held_.clear();
    } else if (hold_.reuse_now(held_.size(), n)) {
        lookup_ = Lookup::held;
    } else {
        lookup_ = Lookup::fresh_and_hold;
        held_.resize(n);
    }
}

void DragTerm::add_per_grain(const System& s, Vec3* f, std::size_t begin, std::size_t end) {
    const Particles& p = s.particles;
    FlowField::Drag* held = held_.data();
    const double mu = viscosity();
    for (std::size_t i = begin; i < end; ++i) {
        const FlowField::Drag fluid = lookup_ == Lookup::held ? held[i] : s.flow->drag_at(p.position[i], s.time);
        if (lookup_ == Lookup::fresh_and_hold) held[i] = fluid;
        f[i] -= (p.velocity[i] - fluid.velocity) * (6.0 * M_PI * mu * p.radius[i] * fluid.factor);
    }
}

void DragTerm::end_pass() {
    if (lookup_ == Lookup::held)
        hold_.reused_once();
    else if (lookup_ == Lookup::fresh_and_hold)
        hold_.evaluated();
}

void DragTerm::save(const System&, std::ostream& out) const {
    hold_.save(out);
    binary::put_vector(out, held_);
}

void DragTerm::load(System&, std::istream& in) {
    hold_.load(in);
    binary::get_vector(in, held_);
}

void DragTerm::grains_removed(System&, const std::vector<std::int64_t>& index, std::size_t kept) {
    if (!held_.empty()) compact_by_index(held_, index, kept);
}

void DragTerm::summarise(const System&, nlohmann::json& summary) const {
    summary["carrier_flow"] = {{"lookup_interval_steps", hold_.interval}, {"steps_with_held_lookups", hold_.reused}};
}

double carrier_viscosity(const System& s) {
    const DragTerm* drag = s.terms.find<DragTerm>();
    return drag ? drag->viscosity() : 0.0;
}

}  // namespace mrjam
