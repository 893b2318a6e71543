#include "asteroid/coalesce_scene.hpp"

#include <algorithm>
#include <cmath>

#include "asteroid/cloud.hpp"
#include "asteroid/grain_material.hpp"
#include "gravity/self_gravity.hpp"

namespace mrjam {

CloudLayout lay_out_cloud(const CoalesceSpec& s) {
    CloudLayout l;
    // The seed's surface and the nearest lattice grain keep half a spacing apart.
    const double clearance = s.seed_diameter > 0 ? 0.5 * s.seed_diameter + 0.5 * s.lattice_spacing : 0.0;
    l.sites = lattice_cloud(s.count, s.lattice_spacing, s.diameter, clearance);
    for (const Vec3& x : l.sites) l.cloud_radius = std::max(l.cloud_radius, norm(x) + 0.5 * s.diameter);
    l.escape_radius = s.escape_radius * l.cloud_radius;
    return l;
}

namespace {

nlohmann::json material_json(const char* name, const RubbleMaterial& m, double magnetisation) {
    nlohmann::json j = grain_material_json(name, m);
    j["surface_energy"] = m.surface_energy;
    j["relative_permeability"] = 1.0;  // rubble: permanent moments only, none induced
    if (magnetisation > 0) {
        j["remanent_magnetisation"] = magnetisation;
        j["remanence_direction"] = "random";
    }
    return j;
}

// The impact speed the contact time is judged at: the escape speed of the cloud's mass packed at
// half density (the body it may become), or the initial motion if faster.
double characteristic_speed(const CoalesceSpec& s, const CloudLayout& l) {
    const double grain_mass = s.material.density * M_PI / 6.0 * std::pow(s.diameter, 3);
    const double seed_mass = s.material.density * M_PI / 6.0 * std::pow(s.seed_diameter, 3);
    const double mass = grain_mass * static_cast<double>(l.sites.size()) + seed_mass;
    const double body_radius = std::cbrt(3.0 * mass / (s.material.density * 0.5) / (4.0 * M_PI));
    const double escape = std::sqrt(2.0 * kNewtonG * mass / body_radius);
    return std::max({escape, 3.0 * s.thermal_speed + std::fabs(s.spin) * l.cloud_radius, 1e-6});
}

}  // namespace

nlohmann::json coalesce_engine_scene(const CoalesceSpec& s, const CloudLayout& l, const char* mode) {
    const double half = 1.25 * l.escape_radius;  // a grain past the escape sphere is removed at the next look
    const bool magnetic = s.material.magnetisation > 0 || (s.seed_diameter > 0 && s.seed_magnetisation > 0);
    nlohmann::json positions = nlohmann::json::array();
    for (const Vec3& x : l.sites) positions.push_back({x.x, x.y, x.z});
    nlohmann::json j = {{"mode", mode},
                        {"seed", s.seed},
                        {"domain", {{"lo", {-half, -half, -half}}, {"hi", {half, half, half}}}},
                        {"materials", {material_json("rubble", s.material, s.material.magnetisation)}},
                        {"contact",
                         {{"model", "hertz_mindlin"},
                          {"rolling", s.material.engine_rolling()},
                          {"cohesion", s.material.surface_energy > 0 ? "dmt" : "none"}}},
                        {"self_gravity",
                         {{"method", s.direct_gravity ? "direct" : "tree"},
                          {"opening_angle", s.opening_angle},
                          {"update_interval", s.gravity_interval}}},
                        {"grains",
                         {{{"material", "rubble"},
                           {"size", {{"distribution", "single"}, {"diameter", s.diameter}}},
                           {"placement", {{"method", "list"}, {"positions", positions}}}}}},
                        {"run",
                         {{"duration", s.duration},
                          {"timestep_safety", s.timestep_safety},
                          {"characteristic_speed", characteristic_speed(s, l)}}},
                        {"output", engine_output_json(s.output)}};
    if (s.seed_diameter > 0) {
        j["materials"].push_back(material_json("seed", s.material, s.seed_magnetisation));
        j["grains"].push_back({{"material", "seed"},
                               {"size", {{"distribution", "single"}, {"diameter", s.seed_diameter}}},
                               {"placement", {{"method", "list"}, {"positions", {{0.0, 0.0, 0.0}}}}}});
    }
    if (magnetic)
        j["magnetic"] = {{"field", {{"type", "uniform"}, {"flux_density", {0.0, 0.0, 0.0}}}},
                         {"mutual", "fixed"},
                         {"cutoff", {{"diameters", s.magnetic_cutoff}}},
                         {"update_interval", s.magnetic_interval}};
    return j;
}

}  // namespace mrjam
