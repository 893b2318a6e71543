#include "asteroid/scaling_spec.hpp"

#include <cmath>

#include "core/format.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {

namespace {

constexpr int kMostRadii = 10000;  // points on the radius grid

void read_material(SceneNode m, ScalingSpec& s) {
    // No default density: a rubble pile of 3000 kg/m3 and iron of 7750 move every crossover.
    s.density = m.quantity("density", units::density, std::nullopt, Bounds::closed(1, 3e4));
    s.grain.relative_permeability = m.number("relative_permeability", 1000, Bounds::closed(1, 1e6));
    s.grain.saturation_magnetisation =
        m.quantity("saturation_magnetisation", units::magnetic_field, 1.7e6, Bounds::closed(1, 1e7));
    m.finish();
}

void read_radii(SceneNode r, ScalingSpec& s) {
    s.radius_min = r.quantity("min", units::length, 1e-6, Bounds::closed(1e-12, 1e7));
    s.radius_max = r.quantity("max", units::length, 1e3, Bounds::closed(1e-12, 1e7));
    if (!(s.radius_max > s.radius_min)) r.fail("max", "must exceed min (" + format_number(s.radius_min) + " m)");
    s.points_per_decade = static_cast<int>(r.integer("points_per_decade", 10, 1, 1000));
    const double decades = std::log10(s.radius_max / s.radius_min);
    if (decades * s.points_per_decade + 1 > kMostRadii)
        r.fail("points_per_decade", "gives more than " + std::to_string(kMostRadii) + " radii over " +
                                        format_number(decades, 3) + " decades; lower it");
    r.finish();
}

void read_magnetism(SceneNode m, ScalingSpec& s) {
    if (!m.has("flux_densities") && !m.has("magnetisations"))
        m.fail("flux_densities",
               "give flux_densities (applied fields on soft grains) or magnetisations "
               "(permanently magnetised grains), or both");
    if (m.has("flux_densities"))
        s.flux_densities = m.quantity_list("flux_densities", units::magnetic_flux_density, Bounds::open(0, 100));
    if (m.has("magnetisations")) {
        s.magnetisations = m.quantity_list("magnetisations", units::magnetic_field, Bounds::positive());
        for (std::size_t k = 0; k < s.magnetisations.size(); ++k)
            if (s.magnetisations[k] > s.grain.saturation_magnetisation)
                throw SceneError(m.path_of("magnetisations") + "/" + std::to_string(k),
                                 "a remanent magnetisation of " + format_number(s.magnetisations[k]) +
                                     " A/m exceeds the material's saturation (" +
                                     format_number(s.grain.saturation_magnetisation) + " A/m)");
    }
    // The exact linear pair grows without bound as the gap closes: a gap must be stated. 0.005
    // radii is where the solver's series still converges in a fraction of a second.
    s.exact_gap = m.number("exact_pair_gap", 0.01, Bounds::closed(0.005, 1.0));
    const std::string model =
        m.choice("dominance_model", {"fixed_dipoles", "mutual_dipoles", "exact_pair"}, "mutual_dipoles");
    s.dominance_model = model == "fixed_dipoles" ? InducedPairModel::fixed_dipoles
                        : model == "exact_pair"  ? InducedPairModel::exact_pair
                                                 : InducedPairModel::mutual_dipoles;
    m.finish();
}

}  // namespace

std::vector<double> ScalingSpec::radii() const {
    const double decades = std::log10(radius_max / radius_min);
    const int n = std::max(2, static_cast<int>(std::ceil(decades * points_per_decade - 1e-9)) + 1);
    std::vector<double> r(n);
    for (int k = 0; k < n; ++k) r[k] = radius_min * std::pow(radius_max / radius_min, static_cast<double>(k) / (n - 1));
    return r;
}

ScalingSpec read_scaling_spec(const nlohmann::json& scene) {
    if (!scene.is_object()) throw SceneError("", "a scaling scene is a JSON object");
    ScalingSpec s;
    s.resolved = nlohmann::json::object();
    SceneNode root(scene, s.resolved, "");
    s.description = root.text("description", "");
    read_material(root.object("material"), s);
    if (auto r = root.optional_object("radius"))
        read_radii(*r, s);
    else {
        nlohmann::json none = nlohmann::json::object();
        read_radii(SceneNode(none, root.resolved_child("radius"), "/radius"), s);
    }
    read_magnetism(root.object("magnetism"), s);
    s.surface_gravities = root.quantity_list("surface_gravities", units::acceleration, Bounds::positive());
    s.cleanliness = root.quantity_list("cleanliness", units::dimensionless, Bounds::open_closed(0, 10));
    s.self_gravity = root.choice("self_gravity", {"two_spheres", "printed"}, "two_spheres") == "printed"
                         ? SelfGravityFormula::printed
                         : SelfGravityFormula::two_spheres;
    root.finish();
    return s;
}

}  // namespace mrjam
