#pragma once
// The engine scene of a coalescence run, written as a `mrjam run` scene: the lattice cloud as a
// list placement, the seed grain, self-gravity, permanent dipoles, the escape sphere's box.
#include <nlohmann/json.hpp>
#include <vector>

#include "asteroid/coalesce_spec.hpp"
#include "core/vec3.hpp"

namespace mrjam {

struct CloudLayout {
    std::vector<Vec3> sites;   // cloud grain centres
    double cloud_radius = 0;   // m, farthest grain surface from the origin
    double escape_radius = 0;  // m
};

CloudLayout lay_out_cloud(const CoalesceSpec& s);
// `mode` labels the scene ("asteroid coalesce", "asteroid spinup").
nlohmann::json coalesce_engine_scene(const CoalesceSpec& s, const CloudLayout& layout, const char* mode);

}  // namespace mrjam
