#include "asteroid/avalanche_spec.hpp"

#include <cmath>

#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

namespace {

void read_material(SceneNode node, AvalancheSpec& s) {
    s.material = read_grain_material(node, {0.278, 0.2, 0.6, "epsd"});
    s.cohesion_energy_density = node.quantity("cohesion_energy_density", units::pressure, 0.0, Bounds::closed(0, 1e9));
    s.relative_permeability = node.number("relative_permeability", 1000.0, Bounds::closed(1, 1e7));
    s.saturation_magnetisation =
        node.quantity("saturation_magnetisation", units::magnetic_field, 1.7e6, Bounds::positive());
    node.finish();
}

// The cell in diameters. The source's was 300 x 80 x 400 diameters for its 5 mm grains, holding
// about 500,000 grains: packed, they fill the cell's floor 18 diameters deep, or 36 behind a gate
// at half the length (the gate's place is not printed). So the tiers default to a wide, low
// column (height / width about 0.24) behind a gate at half the length: such a column fails by
// its face sliding, which is what an angle of repose measures, where a tall one collapses and
// spreads below it (a column of aspect 2.4 here: 16 degrees, against 22 for 0.24 at 0 mT;
// docs/asteroid.md). Quick: about 4,600 grains; standard and paper: about 20,600.
void read_cell(SceneNode node, AvalancheSpec& s, const std::string& fidelity) {
    const bool quick = fidelity == "quick";
    s.length = node.number("length", quick ? 100 : 150, Bounds::closed(10, 5000));
    s.width = node.number("width", quick ? 8 : 16, Bounds::closed(2, 1000));
    // The periodic width must hold the dipoles' reach (3 diameters and the skin) twice over.
    if (s.field > 0 && s.width < 7)
        node.fail("width", "is narrower than twice the dipoles' cutoff of 3 diameters; give at least 7");
    s.height = node.number("height", quick ? 30 : 45, Bounds::closed(5, 5000));
    s.gate = node.number("gate", quick ? 50 : 75, Bounds::open(0, s.length));
    if (s.gate < 2) node.fail("gate", "leaves no room behind it for a grain; give at least 2 diameters");
    s.fill_height = node.number("fill_height", quick ? 12 : 18, Bounds::closed(2, s.height));
    s.fill_fraction = node.number("fill_fraction", 0.5, Bounds::closed(0.05, 0.6));
    const double grains = s.gate * s.width * s.fill_height * s.fill_fraction / (M_PI / 6.0);
    if (grains > 2e6) node.fail("gate", "asks for " + std::to_string(long(grains)) + " grains; at most 2,000,000");
    node.finish();
}

void read_protocol(SceneNode node, AvalancheSpec& s) {
    s.settle_time = node.quantity("settle_time", units::time, std::nullopt, Bounds::positive());
    s.magnetise_time = node.quantity("magnetise_time", units::time, std::nullopt, Bounds::non_negative());
    s.runout_time = node.quantity("runout_time", units::time, std::nullopt, Bounds::positive());
    // At rest: an rms speed under 2 % of sqrt(g d), the speed of a grain dropped by its own size.
    s.rest_speed =
        node.quantity("rest_speed", units::velocity, 0.02 * std::sqrt(s.gravity * s.diameter), Bounds::positive());
    s.timestep_safety = node.number("timestep_safety", 0.1, Bounds::open_closed(0, 0.2));
    node.finish();
}

}  // namespace

AvalancheSpec read_avalanche_spec(const nlohmann::json& scene, const std::string& fidelity) {
    if (!scene.is_object()) throw SceneError("", "an avalanche scene is a JSON object");
    AvalancheSpec s;
    s.resolved = nlohmann::json::object();
    SceneNode root(scene, s.resolved, "");
    s.description = root.text("description", "");
    s.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0));
    SceneNode grains = root.object("grains");
    s.diameter = grains.quantity("diameter", units::length, std::nullopt, Bounds::positive());
    read_material(grains.object("material"), s);
    grains.finish();
    s.gravity = root.quantity("gravity", units::acceleration, std::nullopt, Bounds::positive());
    s.field = root.quantity("field", units::magnetic_flux_density, std::nullopt, Bounds::closed(0, 10));
    // Mutual by default, as the source's LAMMPS module: the neighbours' fields in each moment
    // (lagged, under-relaxed: plain Jacobi diverged in the settled packing, docs/asteroid.md).
    s.mutual_dipoles = root.choice("dipoles", {"fixed", "mutual"}, "mutual") == "mutual";
    json none = json::object();
    auto optional = [&](const char* key) {
        if (auto node = root.optional_object(key)) return *node;
        return SceneNode(none, root.resolved_child(key), std::string("/") + key);
    };
    read_cell(optional("cell"), s, fidelity);
    read_protocol(root.object("protocol"), s);
    SceneNode out = optional("output");
    s.output = read_output_block(out, "out/asteroid_avalanche");
    root.finish();
    return s;
}

}  // namespace mrjam
