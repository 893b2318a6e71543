#include "asteroid/spinup_spec.hpp"

#include <cmath>

#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

int SpinupSpec::steps() const { return static_cast<int>(std::floor(final_spin / increment + 1e-9)); }
double SpinupSpec::target(int k) const { return k * increment; }
double SpinupSpec::interval(int k) const { return target(k) <= early_until + 1e-12 ? early_interval : late_interval; }

namespace {

void read_protocol(SceneNode node, SpinupSpec& s, const std::string& fidelity) {
    s.settle_time = node.quantity("settle_time", units::time, std::nullopt, Bounds::positive());
    s.increment = node.quantity("increment", units::frequency, 100e-6, Bounds::open_closed(0, 1));
    s.early_interval = node.quantity("early_interval", units::time, 500.0, Bounds::positive());
    s.early_until = node.quantity("early_until", units::frequency, 400e-6, Bounds::closed(0, 1));
    s.late_interval =
        node.quantity("late_interval", units::time, fidelity == "quick" ? 1500.0 : 3000.0, Bounds::positive());
    s.final_spin = node.quantity("final_spin", units::frequency, 1000e-6, Bounds::open_closed(0, 1));
    if (s.final_spin < s.increment) node.fail("final_spin", "is below one increment: no step would be taken");
    if (s.steps() > 1000) node.fail("final_spin", "asks for more than 1000 steps; raise the increment");
    s.deformation_threshold = node.number("deformation_threshold", 0.02, Bounds::open(0, 1));
    s.shedding_threshold = node.number("shedding_threshold", 0.01, Bounds::open(0, 1));
    s.fission_threshold = node.number("fission_threshold", 0.1, Bounds::open(0, 0.5));
    node.finish();
}

}  // namespace

SpinupSpec read_spinup_spec(const nlohmann::json& scene, const std::string& fidelity) {
    if (!scene.is_object()) throw SceneError("", "a spinup scene is a JSON object");
    SpinupSpec s;
    CoalesceSpec& b = s.body;
    b.resolved = nlohmann::json::object();
    SceneNode root(scene, b.resolved, "");
    b.output.directory = "out/asteroid_spinup";
    read_rubble_blocks(root, b, fidelity);
    read_protocol(root.object("spin_up"), s, fidelity);
    double total = s.settle_time;
    for (int k = 1; k <= s.steps(); ++k) total += s.interval(k);
    read_run_block(root, b, total);
    root.finish();
    return s;
}

}  // namespace mrjam
