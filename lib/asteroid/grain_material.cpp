#include "asteroid/grain_material.hpp"

#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

GrainMaterial read_grain_material(SceneNode& node, const GrainMaterialDefaults& defaults) {
    GrainMaterial m;
    m.density = node.quantity("density", units::density, std::nullopt, Bounds::closed(1, 1e5));
    m.youngs_modulus = node.quantity("youngs_modulus", units::pressure, std::nullopt, Bounds::closed(1e3, 1e13));
    m.poisson_ratio = node.number("poisson_ratio", defaults.poisson_ratio, Bounds::closed(-0.99, 0.5));
    m.restitution = node.number("restitution", defaults.restitution, Bounds::open_closed(0, 1));
    m.friction = node.number("friction", defaults.friction, Bounds::closed(0, 10));
    m.rolling_friction = node.number("rolling_friction", 0, Bounds::closed(0, 10));
    m.rolling_stiffness = node.quantity("rolling_stiffness", units::stiffness, 0.0, Bounds::non_negative());
    m.rolling_viscous = node.quantity("rolling_viscous", units::damping, 0.0, Bounds::non_negative());
    if ((m.rolling_friction > 0) != (m.rolling_stiffness > 0))
        node.fail("rolling_stiffness",
                  "SDS rolling resistance needs both rolling_friction and rolling_stiffness (or neither)");
    return m;
}

nlohmann::json grain_material_json(const char* name, const GrainMaterial& m) {
    return {{"name", name},
            {"density", m.density},
            {"youngs_modulus", m.youngs_modulus},
            {"poisson_ratio", m.poisson_ratio},
            {"restitution", m.restitution},
            {"friction", m.friction},
            {"rolling_friction", m.rolling_friction},
            {"rolling_stiffness", m.rolling_stiffness},
            {"rolling_viscous", m.rolling_viscous}};
}

}  // namespace mrjam
