#include "asteroid/coalesce_spec.hpp"

#include <cmath>

#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

namespace {

constexpr double kBoltzmann = 1.380649e-23;                  // J/K
constexpr double kSourceTemperaturePerDiameterCubed = 8e20;  // K/m3, section 4.2

RubbleMaterial read_material(SceneNode node) {
    RubbleMaterial m;
    static_cast<GrainMaterial&>(m) = read_grain_material(node, {0.3, 0.1, 0.4, "sds"});
    m.surface_energy = node.quantity("surface_energy", units::surface_energy, 0.0, Bounds::closed(0, 1e3));
    // Iron's saturation bounds any remanence (1.7 MA/m).
    m.magnetisation = node.quantity("magnetisation", units::magnetic_field, 0.0, Bounds::closed(0, 1.7e6));
    node.finish();
    return m;
}

void read_cloud(SceneNode node, CoalesceSpec& s, const std::string& fidelity) {
    const long tier_count = fidelity == "quick" ? 4000 : 32662;
    s.count = node.integer("count", tier_count, 2, 2'000'000);
    s.lattice_spacing = node.quantity("lattice_spacing", units::length, std::nullopt, Bounds::positive());
    if (s.lattice_spacing < s.diameter)
        node.fail("lattice_spacing", "is closer than a grain diameter (" + std::to_string(s.diameter) +
                                         " m): the lattice's grains would overlap");
    s.thermal_from_temperature = !node.has("thermal_speed");
    if (s.thermal_from_temperature) {
        s.thermal_speed = thermal_speed_from_temperature(s.material.density);
        node.resolved_child("thermal_speed") = s.thermal_speed;  // the report names the rule
    } else {
        s.thermal_speed = node.quantity("thermal_speed", units::velocity, std::nullopt, Bounds::closed(0, 1e3));
    }
    s.spin = node.quantity("spin", units::frequency, 0.0, Bounds::closed(-1, 1));
    if (auto seed = node.optional_object("seed_grain")) {
        s.seed_diameter = seed->quantity("diameter", units::length, std::nullopt, Bounds::positive());
        s.seed_magnetisation =
            seed->quantity("magnetisation", units::magnetic_field, s.material.magnetisation, Bounds::closed(0, 1.7e6));
        seed->finish();
    }
    s.escape_radius = node.number("escape_radius", 3.0, Bounds::closed(0, 100));
    if (s.escape_radius <= 1.2)
        node.fail("escape_radius",
                  "is inside the cloud (it is in cloud radii: grains beyond it are removed); "
                  "give more than 1.2");
    s.allow_unbound = node.boolean("allow_unbound", false);
    node.finish();
}

// The tiers differ in how long forces are held (quick: gravity 100 steps, dipoles 4; standard
// and paper: 20 and 1); both holds are short against the cloud's free-fall time (thousands of
// seconds against steps of hundredths of a second): docs/asteroid.md gives their measured cost.
void read_forces_and_output(SceneNode& root, CoalesceSpec& s, const std::string& fidelity) {
    const bool quick = fidelity == "quick";
    json none = json::object();
    auto optional = [&](const char* key) {
        if (auto node = root.optional_object(key)) return *node;
        return SceneNode(none, root.resolved_child(key), std::string("/") + key);
    };
    SceneNode g = optional("self_gravity");
    s.direct_gravity = g.choice("method", {"tree", "direct"}, "tree") == "direct";
    s.opening_angle = g.number("opening_angle", 0.5, Bounds::open_closed(0, 1));
    s.gravity_interval = static_cast<int>(g.integer("update_interval", quick ? 100 : 20, 1, 100000));
    g.finish();
    SceneNode m = optional("magnetic");
    s.magnetic_cutoff = m.number("cutoff_diameters", 3.0, Bounds::closed(2, 20));
    s.magnetic_interval = static_cast<int>(m.integer("update_interval", quick ? 4 : 1, 1, 100));
    m.finish();
    s.output = read_output_block(optional("output"), s.output.directory);
}

}  // namespace

void read_run_block(SceneNode& root, CoalesceSpec& s, std::optional<double> duration) {
    json none = json::object();
    std::optional<SceneNode> given = root.optional_object("run");
    SceneNode run = given ? *given : SceneNode(none, root.resolved_child("run"), "/run");
    s.duration = duration ? *duration : run.quantity("duration", units::time, std::nullopt, Bounds::positive());
    s.sample_every = run.quantity("sample_every", units::time, s.duration / 60, Bounds::positive());
    if (s.sample_every > s.duration) run.fail("sample_every", "is longer than the run's duration");
    s.timestep_safety = run.number("timestep_safety", 0.1, Bounds::open_closed(0, 0.2));
    run.finish();
}

double thermal_speed_from_temperature(double density) {
    // m = rho pi d^3 / 6, so k_B (8e20 d^3) / m has no d left in it.
    return std::sqrt(kBoltzmann * kSourceTemperaturePerDiameterCubed * 6.0 / (M_PI * density));
}

void read_rubble_blocks(SceneNode& root, CoalesceSpec& s, const std::string& fidelity) {
    s.description = root.text("description", "");
    s.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0));
    SceneNode grains = root.object("grains");
    s.diameter = grains.quantity("diameter", units::length, std::nullopt, Bounds::positive());
    s.material = read_material(grains.object("material"));
    grains.finish();
    read_cloud(root.object("cloud"), s, fidelity);
    read_forces_and_output(root, s, fidelity);
}

CoalesceSpec read_coalesce_spec(const nlohmann::json& scene, const std::string& fidelity) {
    if (!scene.is_object()) throw SceneError("", "a coalesce scene is a JSON object");
    CoalesceSpec s;
    s.resolved = nlohmann::json::object();
    SceneNode root(scene, s.resolved, "");
    s.output.directory = "out/asteroid_coalesce";
    read_rubble_blocks(root, s, fidelity);
    read_run_block(root, s, std::nullopt);
    root.finish();
    return s;
}

}  // namespace mrjam
