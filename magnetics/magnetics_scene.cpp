#include "magnetics/magnetics_scene.hpp"

#include <cmath>

#include "scene/scene_node.hpp"
#include "scene/scene_parts.hpp"
#include "scene/tier.hpp"

namespace mrjam::magnetics {

std::vector<std::string> magnetics_tier_names() { return tier_names(); }

FieldModel tier_field_model(const std::string& tier) {
    return PerTier<FieldModel>{FieldModel::planar_2d, FieldModel::full_3d, FieldModel::full_3d}[tier_from_name(tier)];
}

// Measured in docs/magnetics.md: the active-fluid mean moves by 0.1% from (0.24, 0.6) mm to
// (0.12, 0.3) mm elements, so the standard tier uses the coarse pair and answers in seconds.
MeshSettings tier_mesh(const std::string& tier) {
    PerTier<MeshSettings> table;       // standard: the defaults, 3D
    table.quick.fluid_size = 0.05e-3;  // 2D: cheap
    table.quick.device_size = 0.1e-3;
    table.quick.far_size = 2e-3;
    table.paper.fluid_size = 0.1e-3;
    table.paper.device_size = 0.25e-3;
    return table[tier_from_name(tier)];
}

namespace {

void read_magnet(SceneNode node, MagnetMaterial& m) {
    // The strongest permanent magnets (NdFeB) hold about 1.5 T; 2 T leaves room, and refuses mT written as T.
    m.remanence = node.quantity("remanence", units::magnetic_flux_density, m.remanence, Bounds::closed(0.0, 2.0));
    m.recoil_permeability = node.number("recoil_permeability", m.recoil_permeability, Bounds::closed(1.0, 1e6));
    node.finish();
}

// Maxwell Garnett (Clausius-Mossotti) for spheres of permeability mu_p at volume fraction phi in
// a non-magnetic carrier: mu = (1 + 2 phi beta) / (1 - phi beta), beta = (mu_p - 1)/(mu_p + 2).
// It ignores chaining, so it is a lower bound for a fluid in a field (documented).
double maxwell_garnett(double phi, double mu_particle) {
    const double beta = (mu_particle - 1.0) / (mu_particle + 2.0);
    return (1.0 + 2.0 * phi * beta) / (1.0 - phi * beta);
}

void read_materials(SceneNode node, MaterialParameters& m) {
    if (auto iron = node.optional_object("iron")) {
        m.iron_relative_permeability =
            iron->number("relative_permeability", m.iron_relative_permeability, Bounds::closed(1.0, 1e7));
        m.iron_nonlinear = iron->choice("model", {"linear", "saturating"}, "linear") == "saturating";
        m.iron_saturation =
            // Iron saturates at 2.15 T, the best cobalt-iron at 2.4 T.
            iron->quantity("saturation", units::magnetic_flux_density, m.iron_saturation,
                           Bounds::open_closed(0.0, 3.0));
        iron->finish();
    }
    if (auto fluid = node.optional_object("fluid")) {
        const std::string rule = fluid->choice("mixing_rule", {"none", "maxwell_garnett"}, "none");
        if (rule == "none") {
            m.fluid_relative_permeability =
                fluid->number("relative_permeability", m.fluid_relative_permeability, Bounds::closed(1.0, 1e6));
        } else {
            if (fluid->has("relative_permeability"))
                fluid->fail("relative_permeability",
                            "is derived from the mixing rule; drop it or set mixing_rule to \"none\"");
            const double phi = fluid->number("volume_fraction", std::nullopt, Bounds::open(0.0, 0.74));
            const double mu_p = fluid->number("particle_permeability", 1000.0, Bounds::closed(1.0, 1e7));
            m.fluid_relative_permeability = maxwell_garnett(phi, mu_p);
            fluid->resolved_child("relative_permeability_derived") = m.fluid_relative_permeability;
        }
        fluid->finish();
    }
    node.finish();
}

}  // namespace

namespace {

// Absent blocks are read as empty ones so that every default is echoed into the report.
nlohmann::json with_default_blocks(const nlohmann::json& scene) {
    if (!scene.is_object()) throw SceneError("", "a magnetics scene is a JSON object");
    nlohmann::json filled = scene;
    const nlohmann::json skeleton = {
        {"valve", nlohmann::json::object()},
        {"magnets", {{"ndfeb", nlohmann::json::object()}, {"alnico", nlohmann::json::object()}}},
        {"bracket", nlohmann::json::object()},
        {"materials", {{"iron", nlohmann::json::object()}, {"fluid", nlohmann::json::object()}}},
        {"mesh", nlohmann::json::object()},
        {"field_map", nlohmann::json::object()},
        {"output", nlohmann::json::object()}};
    for (const auto& [key, blocks] : skeleton.items()) {
        if (!filled.contains(key)) filled[key] = nlohmann::json::object();
        if (!filled[key].is_object()) continue;  // the reader refuses it with the path
        for (const auto& [sub, empty] : blocks.items())
            if (!filled[key].contains(sub)) filled[key][sub] = empty;
    }
    return filled;
}

}  // namespace

namespace {

void read_magnets(SceneNode magnets, const nlohmann::json& scene, const std::string& state, MagnetParameters& mg) {
    const auto L = units::length;
    mg.width = magnets.quantity("width", L, mg.width, Bounds::any());
    mg.depth = magnets.quantity("depth", L, mg.depth, Bounds::any());
    mg.length = magnets.quantity("length", L, mg.length, Bounds::any());
    mg.spacing = magnets.quantity("spacing", L, mg.spacing, Bounds::any());
    if (auto n = magnets.optional_object("ndfeb")) read_magnet(*n, mg.ndfeb);
    // Partial switching defaults the alnico to the source's 1.25 T (with_default_blocks
    // guarantees the block exists, so only the key's presence matters).
    if (state == "partial" && !scene["magnets"]["alnico"].contains("remanence")) mg.alnico.remanence = 1.25;
    if (auto a = magnets.optional_object("alnico")) read_magnet(*a, mg.alnico);
    magnets.finish();
}

void read_bracket(SceneNode b, BracketParameters& br) {
    const auto L = units::length;
    br.thickness = b.quantity("thickness", L, br.thickness, Bounds::any());
    br.width = b.quantity("width", L, br.width, Bounds::any());
    br.tube_clearance = b.quantity("tube_clearance", L, br.tube_clearance, Bounds::any());
    br.tip_reach = b.quantity("tip_reach", L, br.tip_reach, Bounds::any());
    br.chamfer = b.quantity("chamfer", L, br.chamfer, Bounds::any());
    // A key of another variant's shape would change nothing: refused rather than ignored.
    if (b.has("cutout_radius") && br.variant != BracketVariant::curved)
        b.fail("cutout_radius", "shapes the curved variant's cutout only; set \"variant\": \"curved\" or drop it");
    if (b.has("insert_width") && br.variant != BracketVariant::insert)
        b.fail("insert_width", "sizes the insert variant's inserts only; set \"variant\": \"insert\" or drop it");
    br.cutout_radius = b.quantity("cutout_radius", L, br.cutout_radius, Bounds::any());
    br.insert_width = b.quantity("insert_width", L, br.insert_width, Bounds::any());
    b.finish();
}

// Geometry checks that need the whole description: the first problem, with the count of the rest.
void check_geometry(const EpmModel& m) {
    const auto problems = m.problems();
    if (!problems.empty()) {
        const std::string first = problems.front();
        const auto colon = first.find(": ");
        throw SceneError(
            first.substr(0, colon),
            first.substr(colon + 2) + (problems.size() > 1 ? " (and " + std::to_string(problems.size() - 1) +
                                                                 " more problem(s); fix this one first)"
                                                           : ""));
    }
}

// The mesh block over the tier's sizes, refused where the air box or the solve would not be
// resolved or would not fit.
MeshSettings read_mesh(SceneNode& root, const EpmModel& m, const std::string& tier, FieldModel field_model) {
    const auto L = units::length;
    MeshSettings mesh = tier_mesh(tier);
    // The circuit model meshes nothing: the tier's sizes are not checked against a mesh it never
    // makes (the quick tier's 2D sizes, read as a 3D mesh, were refused as too large), and a mesh
    // size given would be ignored, so it is refused.
    if (field_model == FieldModel::circuit) {
        if (auto node = root.optional_object("mesh")) {
            for (const char* key : {"fluid_size", "device_size", "far_size", "air_box"})
                if (node->has(key))
                    node->fail(key,
                               "the circuit model (model \"circuit\") makes no mesh: remove it, or give model "
                               "\"2d\" or \"3d\"");
            node->finish();
        }
        return mesh;
    }
    if (auto node = root.optional_object("mesh")) {
        mesh.fluid_size = node->quantity("fluid_size", L, mesh.fluid_size, Bounds::positive());
        mesh.device_size = node->quantity("device_size", L, mesh.device_size, Bounds::positive());
        mesh.far_size = node->quantity("far_size", L, mesh.far_size, Bounds::positive());
        mesh.air_box = node->quantity("air_box", L, mesh.air_box, Bounds::positive());
        node->finish();
    }
    const EpmLayout layout = epm_layout(m);
    const Vec3 extent = layout.device_hi - layout.device_lo;
    if (mesh.air_box < 2.0 * std::max({extent.x, extent.y, extent.z}))
        throw SceneError("/mesh/air_box", "must be at least twice the device's largest extent (" +
                                              format_number(2e3 * std::max({extent.x, extent.y, extent.z})) +
                                              " mm) so the phi = 0 boundary does not squeeze the field");
    if (mesh.fluid_size > 0.5 * m.valve.constriction_diameter)
        throw SceneError("/mesh/fluid_size",
                         "is coarser than half the throat diameter; the fluid would not be resolved");
    // The air box must be resolved: one far element across it (a far_size of 1 m) moved the
    // active fluid's mean |B| by 26 % without a word.
    if (mesh.far_size > mesh.air_box / 5)
        throw SceneError("/mesh/far_size", "is more than a fifth of the air box (" + format_number(mesh.air_box * 1e3) +
                                               " mm): the field far from the device would not be resolved; give at "
                                               "most " +
                                               format_number(mesh.air_box / 5 * 1e3) + " mm");
    {
        // The unknowns grow as the inverse cube (2D: square) of the element size. Scaled from the
        // finest 3D mesh measured (docs/magnetics.md: 1.15 million unknowns at 0.075 / 0.19 mm,
        // 4 GB, 452 s) or the quick tier's 2D one (37,021 at 0.05 / 0.1 mm), plus about ten per
        // element of the air box (two in 2D): far beyond it, the solve would run out of memory or
        // time rather than answer (a 2D far_size of 0.01 mm took 13.6 GB), so it is refused
        // before meshing.
        const bool planar = field_model == FieldModel::planar_2d;
        const double dim = planar ? 2 : 3;
        const double fluid = planar ? 37021 * std::pow(0.05e-3 / mesh.fluid_size, dim)
                                    : 1.15e6 * std::pow(0.075e-3 / mesh.fluid_size, dim);
        const double device = planar ? 37021 * std::pow(0.1e-3 / mesh.device_size, dim)
                                     : 1.15e6 * std::pow(0.19e-3 / mesh.device_size, dim);
        const double far = (planar ? 2.0 : 10.0) * std::pow(mesh.air_box / mesh.far_size, dim);
        const double unknowns = std::max(fluid, device) + far;
        constexpr double kMostUnknowns = 4e6;  // about 14 GB at the measured 3.5 kB per 3D unknown
        if (unknowns > kMostUnknowns) {
            const std::string key = far >= std::max(fluid, device) ? "far_size"
                                    : fluid >= device              ? "fluid_size"
                                                                   : "device_size";
            throw SceneError("/mesh/" + key,
                             "would make a " + std::string(planar ? "2D" : "3D") + " mesh of about " +
                                 format_number(unknowns / 1e6, 2) + " million unknowns, past the " +
                                 format_number(kMostUnknowns / 1e6) +
                                 " million this tool solves (1.15 million at 0.075 / 0.19 mm in 3D took 4 GB and "
                                 "452 s): coarsen it" +
                                 (tier == "quick" && !planar ? std::string(" (the quick tier's sizes are for its 2D "
                                                                           "model; give /mesh sizes for 3D)")
                                                             : std::string()));
        }
    }
    return mesh;
}

}  // namespace

MagneticsScene read_magnetics_scene(const nlohmann::json& user_scene, const std::string& tier) {
    MagneticsScene out;
    out.tier = tier;
    const nlohmann::json scene = with_default_blocks(user_scene);
    SceneNode root(scene, out.resolved, "");
    root.text("description", "");
    EpmModel& m = out.request.model;
    const auto L = units::length;

    m.bracket.variant = variant_from_name(root.choice("variant", variant_names(), "rectangular"));
    out.state = root.choice("state", {"on", "off", "partial"}, "on");
    // The valve alone is checked first (its own paths); the EPM's checks follow.
    if (auto valve = root.optional_object("valve")) m.valve = read_valve(*valve);
    if (auto magnets = root.optional_object("magnets")) read_magnets(*magnets, scene, out.state, m.magnets);
    m.magnets.alnico_polarity = out.state == "on" ? 1.0 : -1.0;
    if (out.state == "partial" && m.magnets.alnico.remanence >= m.magnets.ndfeb.remanence)
        root.fail("state",
                  "partial switching means the alnico is reversed but weaker than the NdFeB: set "
                  "magnets/alnico/remanence below magnets/ndfeb/remanence (the source used 1.25 T vs 1.35 T)");
    if (auto b = root.optional_object("bracket")) read_bracket(*b, m.bracket);
    if (auto mat = root.optional_object("materials")) read_materials(*mat, m.materials);

    check_geometry(m);

    const std::string model = root.choice("model", {"circuit", "2d", "3d"}, field_model_name(tier_field_model(tier)));
    out.request.field_model = model == "circuit" ? FieldModel::circuit
                              : model == "2d"    ? FieldModel::planar_2d
                                                 : FieldModel::full_3d;
    const MeshSettings mesh = read_mesh(root, m, tier, out.request.field_model);
    out.request.mesh = mesh;
    if (auto fm = root.optional_object("field_map")) {
        out.request.map_spacing = fm->quantity("spacing", L, out.request.map_spacing, Bounds::positive());
        fm->finish();
    }
    if (out.request.map_spacing > 0.5 * m.valve.tube_inner_diameter)
        throw SceneError("/field_map/spacing", "is coarser than the bore radius; use at most a tenth of the bore");
    if (auto o = root.optional_object("output")) {
        // The output block's keys as in every mode; those of a stepped run have no meaning here.
        for (const char* key : {"checkpoint", "snapshots", "progress_interval"})
            if (o->has(key))
                o->fail(key,
                        "a field solve is one mesh and one GetDP run, not a stepped run: it has no "
                        "checkpoints, snapshots or progress interval (each stage is printed as it ends); "
                        "remove it");
        out.output_directory = o->text("directory", "out/magnetics");
        out.keep_solver_files = o->boolean("keep_solver_files", false);
        o->finish();
    } else {
        out.output_directory = "out/magnetics";
    }
    root.finish();
    return out;
}

SourceFigure source_figure(const MagneticsScene& s) {
    const auto v = s.request.model.bracket.variant;
    if (s.state == "on") {
        if (v == BracketVariant::rectangular) return {0.2294, "active", "rectangular ON, mean in the active area"};
        if (v == BracketVariant::curved) return {0.2228, "active", "curved ON, mean in the active area"};
        if (v == BracketVariant::unchamfered) return {0.2245, "active", "unchamfered ON, mean in the active area"};
        if (v == BracketVariant::insert) return {0.5578, "active", "inserts ON, mean in the active area"};
    }
    if (v == BracketVariant::rectangular && s.state == "off")
        return {0.066e-3, "inactive", "rectangular OFF, inactive area"};
    if (v == BracketVariant::rectangular && s.state == "partial")
        return {4.3e-3, "active", "rectangular OFF with alnico at 1.25 T, active area"};
    return {};
}

}  // namespace mrjam::magnetics
