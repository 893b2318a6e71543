#include "jam/jam_snapshots.hpp"

#include <cmath>
#include <filesystem>

#include "contact_clusters.hpp"
#include "io/snapshot.hpp"

namespace mrjam {

JamSnapshots::JamSnapshots(std::string directory, double every, long long seed)
    : directory_(std::move(directory)), every_(every), seed_(seed) {
    if (enabled()) std::filesystem::create_directories(directory_);
}

void JamSnapshots::observe(const System& s) {
    if (!enabled() || s.time < next_time_) return;
    write(s, "seed" + std::to_string(seed_) + "_step" + std::to_string(s.step) + ".vtk");
    // The next due time is a multiple of the interval, so observations that do not fall on one
    // do not make the series drift.
    next_time_ += every_ * (std::floor((s.time - next_time_) / every_) + 1);
    // An interval below the time's resolution would not move it on (it hung a loop here): the
    // command refuses such intervals, and this bounds the harm if one gets through.
    if (!(next_time_ > s.time)) next_time_ = std::nextafter(s.time, HUGE_VAL);
}

void JamSnapshots::write_tagged(const System& s, const std::string& tag) {
    if (enabled()) write(s, "seed" + std::to_string(seed_) + "_" + tag + ".vtk");
}

void JamSnapshots::write(const System& s, const std::string& file) {
    const ContactClusters clusters = contact_clusters(s);
    IntPointArray id{"cluster", {}}, size{"cluster_size", {}};
    id.values.reserve(clusters.label.size());
    size.values.reserve(clusters.label.size());
    for (std::uint32_t label : clusters.label) {
        id.values.push_back(static_cast<std::int32_t>(label));
        size.values.push_back(static_cast<std::int32_t>(clusters.size[label]));
    }
    const std::string path = (std::filesystem::path(directory_) / file).string();
    write_snapshot(path, SnapshotFormat::vtk_legacy, s.particles, s.domain, s.step, s.time, {id, size});
    written_.push_back(path);
}

nlohmann::json JamSnapshots::save() const { return {{"next_time_s", next_time_}, {"written", written_}}; }

void JamSnapshots::restore(const nlohmann::json& state) {
    next_time_ = state.at("next_time_s").get<double>();
    written_ = state.at("written").get<std::vector<std::string>>();
}

}  // namespace mrjam
