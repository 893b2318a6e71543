// Scene physics blocks: materials, contact model, magnetic block (scene/scene_physics.hpp).
#include "scene/scene_physics.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>

#include "scene/material_ranges.hpp"
#include "scene/scene_parts.hpp"

namespace mrjam {

Material read_material(SceneNode node) {
    Material m;
    m.name = node.text("name", std::nullopt);
    if (m.name.empty()) node.fail("name", "give the material a name (grains and walls refer to it)");
    m.density = node.quantity("density", units::density, std::nullopt, density_range());
    m.youngs_modulus = node.quantity("youngs_modulus", units::pressure, std::nullopt, youngs_modulus_range());
    m.poisson_ratio = node.number("poisson_ratio", 0.3, Bounds::closed(-0.99, 0.5));
    m.restitution = node.number("restitution", 0.5, Bounds::open_closed(0.0, 1.0));
    m.friction = node.number("friction", 0.5, Bounds::non_negative());
    m.rolling_friction = node.number("rolling_friction", 0.0, Bounds::non_negative());
    m.rolling_damping = node.number("rolling_damping", 0.0, Bounds::non_negative());
    m.rolling_stiffness = node.quantity("rolling_stiffness", units::stiffness, 0.0, Bounds::non_negative());
    m.rolling_viscous = node.quantity("rolling_viscous", units::damping, 0.0, Bounds::non_negative());
    m.cohesion_energy_density = node.quantity("cohesion_energy_density", units::pressure, 0.0, Bounds::non_negative());
    m.surface_energy = node.quantity("surface_energy", units::surface_energy, 0.0, Bounds::non_negative());
    m.relative_permeability = node.number("relative_permeability", 1000.0, Bounds::closed(1.0, 1e7));
    m.saturation_magnetisation =
        node.quantity("saturation_magnetisation", units::magnetic_field, 1.7e6, Bounds::positive());
    m.remanent_magnetisation =
        node.quantity("remanent_magnetisation", units::magnetic_field, 0.0, Bounds::non_negative());
    if (node.has("remanence_direction") && node.raw("remanence_direction").is_array()) {
        const Vec3 d = node.vector("remanence_direction", units::dimensionless, std::nullopt);
        if (norm(d) == 0) node.fail("remanence_direction", "must be a non-zero vector, or \"random\"");
        m.remanence_direction = d / norm(d);
        m.random_remanence_direction = false;
    } else {
        node.choice("remanence_direction", {"random"}, "random");
    }
    node.finish();
    return m;
}

// One pair's friction and cohesion in place of the mixing rule's means: {"materials": [a, b],
// "friction", "rolling_friction", "cohesion_energy_density"} (each defaulting to the mean it
// replaces).
void read_material_pair(SceneNode node, const std::vector<std::string>& names, PairTable& pairs) {
    const json& list = node.raw("materials");
    if (!list.is_array() || list.size() != 2 || !list[0].is_string() || !list[1].is_string())
        node.fail("materials", "must be two material names, e.g. [\"iron\", \"glass\"]");
    std::uint16_t index[2];
    for (int k = 0; k < 2; ++k) {
        const auto it = std::find(names.begin(), names.end(), list[k].get<std::string>());
        if (it == names.end())
            node.fail("materials",
                      "names no material called \"" + list[k].get<std::string>() + "\"; define it in /materials");
        index[k] = static_cast<std::uint16_t>(it - names.begin());
    }
    PairCoefficients c = pairs(index[0], index[1]);
    c.friction = node.number("friction", c.friction, Bounds::non_negative());
    c.rolling_friction = node.number("rolling_friction", c.rolling_friction, Bounds::non_negative());
    c.cohesion_energy_density =
        node.quantity("cohesion_energy_density", units::pressure, c.cohesion_energy_density, Bounds::non_negative());
    node.finish();
    pairs.set_pair(index[0], index[1], c);
}

void read_contact(SceneNode node, PhysicsSettings& ph, double& pair_damping) {
    ph.contact = node.choice("model", {"hertz_mindlin", "none"}, "hertz_mindlin") == "hertz_mindlin";
    const std::string rolling = node.choice("rolling", {"none", "epsd", "sds"}, "none");
    ph.rolling = rolling == "epsd" ? RollingModel::epsd : rolling == "sds" ? RollingModel::sds : RollingModel::none;
    const std::string cohesion = node.choice("cohesion", {"none", "sjkr", "dmt"}, "none");
    ph.cohesion = cohesion == "sjkr"  ? CohesionModel::sjkr
                  : cohesion == "dmt" ? CohesionModel::dmt
                                      : CohesionModel::none;
    pair_damping = node.quantity("pair_damping", units::damping, 0.0, Bounds::non_negative());
    if (pair_damping > 0 && !ph.contact)
        node.fail("pair_damping", "acts between touching grains: it needs the hertz_mindlin contact model");
    node.finish();
}

// Induced coefficient (eq. 2.4), saturation cap and permanent moment of a grain.
void set_magnetic_constants(const Material& m, Particles& p, std::size_t i, Rng& rng) {
    const double r = p.radius[i];
    const double volume = 4.0 / 3.0 * M_PI * r * r * r;
    const double mu = m.relative_permeability;
    p.induced_coefficient[i] = 4.0 * M_PI * r * r * r * (mu - 1.0) / (mu + 2.0);
    p.saturation_moment[i] = m.saturation_magnetisation * volume;
    p.orientation[i] = Quaternion{};
    if (m.remanent_magnetisation > 0) {
        Vec3 dir = m.remanence_direction;
        if (m.random_remanence_direction) {  // uniform on the sphere
            const double z = rng.uniform(-1.0, 1.0), phi = rng.uniform(0.0, 2.0 * M_PI);
            const double rho = std::sqrt(1.0 - z * z);
            dir = {rho * std::cos(phi), rho * std::sin(phi), z};
        }
        p.permanent_moment[i] = dir * (m.remanent_magnetisation * volume);
    }
}

// The close-pair table is for one permeability: every magnetisable grain must share it, and the
// magnetic list must reach the correction's range for the smallest and largest grains.
void build_close_pair_table(System& s, double r_max) {
    const Particles& p = s.particles;
    double beta = -1, ms = -1, r_min = r_max;
    for (std::size_t i = 0; i < p.size(); ++i) {
        r_min = std::min(r_min, p.radius[i]);
        if (p.induced_coefficient[i] <= 0) continue;
        const double r3 = std::pow(p.radius[i], 3);
        const double b = p.induced_coefficient[i] / (4.0 * M_PI * r3);
        const double m = p.saturation_moment[i] / (4.0 / 3.0 * M_PI * r3);
        if (beta < 0) {
            beta = b;
            ms = m;
        } else if (std::abs(b - beta) > 1e-9 * beta) {
            throw SceneError("/magnetic/close_pairs",
                             "the correction is tabulated for one permeability, and the grains' "
                             "materials differ in relative_permeability; give them one, or drop close_pairs");
        } else if (s.magnetic.settings.close_pairs.model == ClosePairModel::saturating &&
                   std::abs(m - ms) > 1e-9 * ms) {
            throw SceneError("/magnetic/close_pairs/model",
                             "the saturating table is in H / M_s for one M_s, and the grains' materials differ in "
                             "saturation_magnetisation; give them one, or use the linear model");
        }
    }
    if (beta <= 0)
        throw SceneError("/magnetic/close_pairs",
                         "no grain is magnetisable (relative_permeability 1); drop close_pairs");
    const ClosePairSettings& cs = s.magnetic.settings.close_pairs;
    for (double r : {r_min, r_max})
        if (s.magnetic.pairs.interaction_range(r, r) < (2.0 + cs.range) * r)
            throw SceneError("/magnetic/close_pairs/range", "the magnetic cutoff does not reach a gap of " +
                                                                format_number(cs.range) +
                                                                " radii; lengthen the cutoff or shorten the range");
    const double mu = (1.0 + 2.0 * beta) / (1.0 - beta);
    if (cs.model == ClosePairModel::saturating && !(ms < 1e12))
        throw SceneError("/magnetic/close_pairs/model",
                         "the saturating model needs the grains' saturation magnetisation, and these grains have "
                         "none (saturation switched off); switch it on or use the linear model");
    if (cs.model == ClosePairModel::saturating && std::abs(mu - kSaturatingPairPermeability) > 1e-6 * mu)
        throw SceneError("/magnetic/close_pairs/model",
                         "the saturating pair table was solved for iron of relative_permeability " +
                             format_number(kSaturatingPairPermeability) + ", not " + format_number(mu) +
                             "; give the grains that permeability, use the linear model, or solve a table for it "
                             "(mrjam-bench sphere-pair-fem --permeability ... --table-out)");
    s.magnetic.close_pair_table = ClosePairTable(mu, cs, ms);
}

// The two-body correction for nearly touching grains (docs/magnetic_forces.md, "Close pairs").
void read_close_pairs(SceneNode close, ClosePairSettings& cp) {
    cp.enabled = true;
    // No default: the two models differ by an order of magnitude at contact.
    const std::string model = close.choice("model", {"saturating", "linear"}, std::nullopt);
    cp.model = model == "saturating" ? ClosePairModel::saturating : ClosePairModel::linear;
    if (cp.model == ClosePairModel::saturating) {
        if (close.has("min_gap"))
            close.fail("min_gap",
                       "is the linear model's floor; the saturating model's force is capped by the "
                       "iron's saturation and needs none: drop it");
        cp.range = close.number("range", cp.range, Bounds::closed(0.1, 1.0));
    } else {
        cp.min_gap = close.number("min_gap", cp.min_gap, Bounds::closed(0.005, 1.0));
        cp.range = close.number("range", cp.range, Bounds::closed(0.1, 4.0));
        if (!(cp.range > cp.min_gap)) close.fail("range", "must exceed min_gap (both are surface gaps in radii)");
    }
    close.finish();
}

void read_magnetic(SceneNode node, System& s, const BuildOptions& options, const FidelityTier& tier) {
    MagneticModel& mag = s.magnetic;
    mag.enabled = true;
    SceneNode field = node.object("field");
    const std::string type = field.choice("type", {"uniform", "map"}, "uniform");
    if (type == "uniform") {
        const Vec3 b = field.vector("flux_density", units::magnetic_flux_density, std::nullopt);
        check_applied_flux_density(field, "flux_density", norm(b));
        const double on = field.quantity("switch_on", units::time, 0.0, Bounds::non_negative());
        const double ramp = field.quantity("ramp", units::time, 0.0, Bounds::non_negative());
        const double off =
            field.quantity("switch_off", units::time, std::numeric_limits<double>::max(), Bounds::positive());
        if (!(off > on)) field.fail("switch_off", "must come after switch_on");
        mag.field = std::make_shared<UniformField>(b, on, ramp, off);
    } else {
        std::string file = field.text("file", std::nullopt);
        if (!file.empty() && file[0] != '/' && !options.base_directory.empty())
            file = options.base_directory + "/" + file;
        // Absolute as resolved, so a checkpoint resumed from another directory finds the same map.
        if (!file.empty()) file = std::filesystem::absolute(file).lexically_normal().string();
        field.resolved_child("file") = file;
        const double scale = field.number("scale", 1.0, Bounds::any());
        if (!std::filesystem::exists(file))
            field.fail("file", "no field map at " + file +
                                   " (the format, a text grid of B, is in docs/scene.md under "
                                   "\"Magnetic forces\"; a relative path is taken from the scene file's folder)");
        std::shared_ptr<FieldMap> map;
        try {
            map = std::make_shared<FieldMap>(FieldMap::read(file, scale));
        } catch (const std::exception& e) {
            field.fail("file", e.what());
        }
        // The scaled map's strongest node, as a uniform field is checked (a scale of 1e6 blew up).
        check_map_scale(field, "scale", map->largest_flux_density());
        mag.field = map;
    }
    field.finish();
    MagneticSettings& st = mag.settings;
    const std::string policy =
        node.choice("mutual", {"fixed", "lagged", "iterations", "converged"}, policy_name(tier.magnetic_policy));
    st.policy = policy == "fixed"        ? MutualPolicy::fixed
                : policy == "lagged"     ? MutualPolicy::lagged
                : policy == "iterations" ? MutualPolicy::iterations
                                         : MutualPolicy::converged;
    // Each policy's own settings. A new scene giving another policy's (iterations with
    // "lagged") is refused: it would be silently ignored. A checkpoint's resolved scene, written
    // before this check, records all three, so there they are read and left unused.
    const bool counted = st.policy == MutualPolicy::iterations, converged = st.policy == MutualPolicy::converged;
    for (const auto& [key, owner] :
         {std::pair{"iterations", "iterations"}, {"tolerance", "converged"}, {"max_iterations", "converged"}})
        if (policy != owner && node.has(key) && options.insert_grains)
            node.fail(key, std::string("is used only by \"mutual\": \"") + owner + "\", not \"" + policy +
                               "\"; drop it, or choose \"" + owner + "\"");
    if (counted || node.has("iterations")) st.iterations = static_cast<int>(node.integer("iterations", 1, 1, 1000));
    if (converged || node.has("tolerance")) st.tolerance = node.number("tolerance", 1e-6, Bounds::open(0.0, 1.0));
    if (converged || node.has("max_iterations"))
        st.max_iterations = static_cast<int>(node.integer("max_iterations", 500, 1, 100000));
    // The mutual update's under-relaxation (lib/engine/magnetic/magnetic_model.cpp says why 2/3):
    // unused by fixed dipoles, so refused there in a new scene like the other policies' keys.
    if (policy != "fixed" || node.has("relaxation")) {
        if (policy == "fixed" && options.insert_grains)
            node.fail("relaxation", "relaxes the mutual-dipole update; \"mutual\": \"fixed\" has none: drop it");
        st.relaxation = node.number("relaxation", 2.0 / 3.0, Bounds::open_closed(0.0, 1.0));
    }
    mag.hold.interval = static_cast<int>(node.integer("update_interval", 1, 1, 100));
    if (auto close = node.optional_object("close_pairs")) read_close_pairs(*close, st.close_pairs);
    if (auto cut = node.optional_object("cutoff")) {
        // "diameters" with "beyond_contact": the shorter of the two ranges, so fine grains reach a
        // few of their own diameters and coarse ones a length beyond contact.
        const bool capped = cut->has("diameters") && cut->has("beyond_contact") && !cut->has("length");
        const int given = cut->has("diameters") + cut->has("beyond_contact") + cut->has("length");
        if (given != 1 && !capped)
            cut->fail("diameters",
                      "give one of 'diameters', 'beyond_contact' or 'length', or 'diameters' with "
                      "'beyond_contact' (the shorter range of the two)");
        if (cut->has("beyond_contact")) {
            st.cutoff_scale = 1.0;
            st.cutoff_extra = cut->quantity("beyond_contact", units::length, std::nullopt, Bounds::non_negative());
            if (capped) st.cutoff_max_scale = cut->number("diameters", std::nullopt, Bounds::closed(1.0, 100.0));
        } else if (cut->has("diameters")) {
            st.cutoff_scale = cut->number("diameters", std::nullopt, Bounds::closed(1.0, 100.0));
        } else {
            st.cutoff_scale = 0.0;
            st.cutoff_extra = cut->quantity("length", units::length, std::nullopt, Bounds::positive());
        }
        cut->finish();
    } else {
        st.cutoff_scale = tier.magnetic_cutoff_diameters;
        node.resolved_child("cutoff") = {{"diameters", st.cutoff_scale}};
    }
    node.finish();
}

SelfGravitySettings read_self_gravity(SceneNode node, const Domain& domain) {
    // Isolated boundaries only: a periodic image of a body is another body (the source's PPPM
    // trick read low by about the cloud's share of the box for that reason).
    for (int k = 0; k < 3; ++k)
        if (domain.periodic[k])
            throw SceneError("/domain/periodic",
                             "self-gravity sums over open space; make every axis non-periodic "
                             "(or drop /self_gravity)");
    SelfGravitySettings st;
    st.method =
        node.choice("method", {"tree", "direct"}, "tree") == "tree" ? GravityMethod::tree : GravityMethod::direct;
    st.constant = node.quantity("constant", units::gravitational_constant, kNewtonG, Bounds::positive());
    st.tree.opening_angle = node.number("opening_angle", 0.5, Bounds::open_closed(0, 1));
    st.tree.leaf_size = static_cast<int>(node.integer("leaf_size", 8, 1, 64));
    st.update_interval = static_cast<int>(node.integer("update_interval", 1, 1, 100000));
    node.finish();
    return st;
}

void check_field_map_coverage(const System& s, std::vector<std::string>& warnings) {
    const auto* map = dynamic_cast<const FieldMap*>(s.magnetic.field.get());
    if (!s.magnetic.enabled || !map) return;
    const Vec3 lo = map->lower_corner(), hi = map->upper_corner();
    auto box = [&] {
        return "x " + format_number(lo.x) + ".." + format_number(hi.x) + ", y " + format_number(lo.y) + ".." +
               format_number(hi.y) + ", z " + format_number(lo.z) + ".." + format_number(hi.z) + " m";
    };
    const double tol = 1e-9 * std::max(1.0, norm(hi - lo));
    auto inside = [&](const Vec3& x) {
        return x.x >= lo.x - tol && x.y >= lo.y - tol && x.z >= lo.z - tol && x.x <= hi.x + tol && x.y <= hi.y + tol &&
               x.z <= hi.z + tol;
    };
    for (std::size_t i = 0; i < s.particles.size(); ++i) {
        const Vec3& x = s.particles.position[i];
        if (!inside(x))
            throw SceneError("/magnetic/field/file",
                             "the field map (" + box() + ") does not reach grain " + std::to_string(i) + " at (" +
                                 format_number(x.x) + ", " + format_number(x.y) + ", " + format_number(x.z) +
                                 "); solve the map over the whole domain, or move the grains into it");
    }
    if (!inside(s.domain.lo) || !inside(s.domain.hi))
        warnings.push_back("the domain reaches beyond the field map (" + box() +
                           "): a grain that leaves the map feels the field of the map's nearest edge");
}

}  // namespace mrjam
