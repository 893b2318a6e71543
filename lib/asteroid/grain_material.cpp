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
    m.rolling_model = node.choice("rolling_model", {"sds", "epsd"}, std::string(defaults.rolling_model));
    m.rolling_friction = node.number("rolling_friction", 0, Bounds::closed(0, 10));
    if (m.rolling_model == "sds") {
        m.rolling_stiffness = node.quantity("rolling_stiffness", units::stiffness, 0.0, Bounds::non_negative());
        m.rolling_viscous = node.quantity("rolling_viscous", units::damping, 0.0, Bounds::non_negative());
        if ((m.rolling_friction > 0) != (m.rolling_stiffness > 0))
            node.fail("rolling_stiffness",
                      "SDS rolling resistance needs both rolling_friction and rolling_stiffness (or neither)");
    } else {
        // EPSD's spring follows the normal stiffness and its damping is a ratio: the SDS keys
        // would be ignored, so they are refused.
        for (const char* sds_key : {"rolling_stiffness", "rolling_viscous"})
            if (node.has(sds_key))
                node.fail(sds_key,
                          "is an SDS key; EPSD rolling resistance takes rolling_friction and "
                          "rolling_damping (a damping ratio), or set rolling_model to \"sds\"");
        m.rolling_damping = node.number("rolling_damping", 0.0, Bounds::closed(0, 10));
    }
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
            {"rolling_viscous", m.rolling_viscous},
            {"rolling_damping", m.rolling_damping}};
}

}  // namespace mrjam
