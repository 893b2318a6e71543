#pragma once
// VTK snapshots of a jam run on request: one every `every` seconds of simulated time, one at
// arrest and one at the end, each with the grains' contact-cluster id (`cluster`, 0 = the
// largest) and its size (`cluster_size`) as point arrays, so ParaView colours the arch the way
// the source's Fig. 3.11 does.
#include <nlohmann/json.hpp>
#include <string>

#include "system.hpp"

namespace mrjam {

class JamSnapshots {
public:
    JamSnapshots() = default;  // none requested
    JamSnapshots(std::string directory, double every, long long seed);
    bool enabled() const { return !directory_.empty(); }

    // At an observation: writes DIR/seed<S>_step<STEP>.vtk when the next snapshot time is due.
    void observe(const System& s);
    // DIR/seed<S>_<tag>.vtk now ("arrest", "end").
    void write_tagged(const System& s, const std::string& tag);

    const std::vector<std::string>& written() const { return written_; }
    // Which snapshot is due next, for a checkpoint.
    nlohmann::json save() const;
    void restore(const nlohmann::json& state);

private:
    void write(const System& s, const std::string& file);
    std::string directory_;
    double every_ = 0;
    long long seed_ = 0;
    double next_time_ = 0;
    std::vector<std::string> written_;
};

}  // namespace mrjam
