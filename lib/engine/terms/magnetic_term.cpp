#include "terms/magnetic_term.hpp"

#include <nlohmann/json.hpp>

#include "core/binary_io.hpp"
#include "grain_removal.hpp"
#include "system.hpp"

namespace mrjam {

void MagneticTerm::add(System& s) { add_magnetic_forces(s.magnetic, s.particles, s.time, s.threads); }

void MagneticTerm::save(const System& s, std::ostream& out) const {
    const MagneticModel& m = s.magnetic;
    m.pairs.save(out);
    // The counts behind the reported mean iterations per step: a run resumed after the magnet
    // was switched off (no passes since) reports what the whole run did.
    binary::put(out, m.field_passes);
    binary::put(out, m.force_passes);
    binary::put(out, m.skipped_passes);
    m.hold.save(out);
    binary::put_vector(out, m.held_force);
    binary::put_vector(out, m.held_torque);
}

void MagneticTerm::load(System& s, std::istream& in) {
    MagneticModel& m = s.magnetic;
    m.pairs.load(in);
    m.field_passes = binary::get<long>(in);
    m.force_passes = binary::get<long>(in);
    m.skipped_passes = binary::get<long>(in);
    m.hold.load(in);
    binary::get_vector(in, m.held_force);
    binary::get_vector(in, m.held_torque);
}

void MagneticTerm::grains_removed(System& s, const std::vector<std::int64_t>& index, std::size_t kept) {
    MagneticModel& m = s.magnetic;
    m.pairs.remove_grains(index, kept);
    compact_by_index(m.neighbour_field, index, kept);
    if (!m.held_force.empty()) compact_by_index(m.held_force, index, kept);
    if (!m.held_torque.empty()) compact_by_index(m.held_torque, index, kept);
}

void MagneticTerm::summarise(const System& s, nlohmann::json& summary) const {
    const MagneticModel& m = s.magnetic;
    const std::size_t n = s.particles.size();
    double moment = 0;
    for (const Vec3& d : s.particles.dipole_moment) moment += norm(d);
    nlohmann::json j = {{"policy", policy_name(m.settings.policy)},
                        {"mean_iterations_per_step", mean_iterations(m)},
                        {"steps_with_magnet_off", m.skipped_passes},
                        {"update_interval_steps", m.hold.interval},
                        {"steps_with_held_forces", m.hold.reused},
                        {"listed_magnetic_neighbours_per_grain", n ? 2.0 * m.pairs.pair_count() / n : 0.0},
                        {"mean_moment_A_m2", n ? moment / n : 0.0},
                        {"applied_field", m.field->name()}};
    const ClosePairSettings& cp = m.settings.close_pairs;
    j["close_pairs"] = cp.enabled
                           ? nlohmann::json{{"model", close_pair_model_name(cp.model)},
                                            {"min_gap_radii", m.close_pair_table.min_gap()},
                                            {"range_radii", cp.range},
                                            {"relative_permeability", m.close_pair_table.relative_permeability()}}
                           : nlohmann::json(nullptr);
    summary["magnetic"] = j;
}

}  // namespace mrjam
