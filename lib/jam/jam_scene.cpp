#include "jam/jam_scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include "fluid/valve_flow.hpp"
#include "jam/coupled_flow.hpp"
#include "jam/jam_engine_scene.hpp"
#include "magnetic/external_field.hpp"
#include "magnetic/magnetic_model.hpp"
#include "scene/material_ranges.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "scene/scene_parts.hpp"
#include "scene/tier.hpp"

namespace mrjam {

std::vector<std::string> jam_tier_names() {
    std::vector<std::string> names = tier_names();
    names.emplace_back("continuum");  // no grains: a Bingham plug (lib/jam/continuum_tier.hpp)
    return names;
}

namespace {

// The source's two mass tables (section 3.4.4). As printed, the percentages sum to 122; mrjam
// reads them as relative mass (= volume, one density) shares and normalises them to 1.
struct MassTable {
    std::vector<double> diameters, mass;
};
MassTable preset_table(const std::string& name) {
    const std::vector<double> mass{44, 35, 24.2, 13.2, 5.6};
    if (name == "44um") return {{44e-6, 38.9e-6, 33.8e-6, 28.7e-6, 23.6e-6}, mass};
    return {{10e-6, 9.49e-6, 8.98e-6, 8.47e-6, 7.96e-6}, mass};
}

// Slab thickness (in largest-grain diameters) and modelled tube length per tier.
struct TierSettings {
    double slab_diameters;
    double upstream, downstream;
    long long magnetic_interval;     // steps between magnetic evaluations
    long long flow_lookup_interval;  // steps between carrier-flow lookups at the grains
    bool heavier_below_largest;      // model/heavier_below defaults to the largest diameter
};
// The quick and standard tiers hold the magnetic forces 4 steps: 1.5 times faster on the 44 um
// cases at the quick tier with the same outcomes over three seeds each (docs/notes/jam_measurements.md,
// "Held magnetic forces"), 2.1 times at the standard tier, where the pair pass (3 diameters) and
// the field map's lookups were three quarters of a step, with the same outcome
// (docs/notes/jam_speed.md). They hold the carrier-flow lookups 4 steps too: 8 % faster on the
// 10 um mix, the same outcomes on the 44 um cases over three seeds
// (docs/notes/jam_measurements.md, "Held carrier-flow lookups"). The paper tier evaluates every step.
const PerTier<TierSettings> kTable = {
    {3.0, 1.0e-3, 0.5e-3, 4, 4, true},
    {6.0, 1.5e-3, 0.75e-3, 4, 4, false},
    {0.0, 2.0e-3, 1.0e-3, 1, 1, false},  // paper: the full bore
};
// The continuum tier has no grains; its scene is read with the standard tier's model sizes.
const TierSettings& tier_settings(const std::string& tier) {
    return kTable[tier == "continuum" ? Tier::standard : tier_from_name(tier)];
}

// A number in SI or a string with units, in a table the scene reader passes through raw.
double table_quantity(const json& value, const units::Dimension& dimension, const std::string& at) {
    if (value.is_number()) return value.get<double>();
    if (!value.is_string()) throw SceneError(at, "expected a number in SI or a string with units");
    try {
        return units::parse_as(value.get<std::string>(), dimension);
    } catch (const std::exception& e) {
        throw SceneError(at, e.what());
    }
}

// The block `continuum`: the fluid's yield stress against the field, as pairs
// [[B, tau_y], ...] (numbers in SI or strings with units) or the report of a `mrjam shear` run
// (shear_report, relative to the scene). Required by the continuum tier.
void read_continuum(SceneNode& root, const std::string& tier, const std::string& base_directory, JamScene& out) {
    std::optional<SceneNode> block = root.optional_object("continuum");
    if (!block) {
        if (tier == "continuum")
            throw SceneError("/continuum",
                             "the continuum tier needs the fluid's yield stress: give "
                             "continuum/yield_stress [[\"100 mT\", \"5 kPa\"], ...] or "
                             "continuum/shear_report (a mrjam shear report of this fluid)");
        return;
    }
    SceneNode& c = *block;
    out.continuum_samples = static_cast<int>(c.integer("samples", out.continuum_samples, 2, 1000000));
    const bool has_table = c.has("yield_stress"), has_report = c.has("shear_report");
    if (has_table == has_report)
        c.fail(
            has_table ? "shear_report" : "yield_stress",
            "give the yield stress either as a table (yield_stress) or as a shear report (shear_report), one of them");
    if (has_report) {
        std::filesystem::path path(c.text("shear_report", std::nullopt));
        if (path.is_relative() && !base_directory.empty()) path = std::filesystem::path(base_directory) / path;
        std::ifstream in(path);
        if (!in) throw SceneError("/continuum/shear_report", "cannot read " + path.string());
        const json report = json::parse(in, nullptr, false);
        if (report.is_discarded()) throw SceneError("/continuum/shear_report", path.string() + " is not JSON");
        out.yield_stress = yield_stress_table_from_shear_report(report, "/continuum/shear_report");
        return;
    }
    const json& rows = c.raw("yield_stress");
    if (!rows.is_array() || rows.empty())
        throw SceneError("/continuum/yield_stress", "expected pairs [[B, tau_y], ...], e.g. [[\"100 mT\", \"5 kPa\"]]");
    std::vector<YieldStressPoint> points;
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const std::string at = "/continuum/yield_stress/" + std::to_string(k);
        if (!rows[k].is_array() || rows[k].size() != 2) throw SceneError(at, "expected a pair [B, tau_y]");
        points.push_back({table_quantity(rows[k][0], units::magnetic_flux_density, at + "/0"),
                          table_quantity(rows[k][1], units::pressure, at + "/1"), "scene"});
    }
    out.yield_stress = YieldStressTable(std::move(points), "/continuum/yield_stress");
}

// protocol/order and, closed first, how long and by what criterion the grains are magnetised at rest.
void read_protocol_order(SceneNode& protocol, JamProtocol& p) {
    const std::string order = protocol.choice("order", {"closed_first", "open_first"}, "closed_first");
    p.order = order == "closed_first" ? JamOrder::closed_first : JamOrder::open_first;
    const bool closed = p.order == JamOrder::closed_first;
    for (const char* key : {"magnetise_time", "settle_window", "settle_tolerance", "magnetise_viscosity_share"})
        if (!closed && protocol.has(key))
            protocol.fail(key,
                          "applies to protocol/order \"closed_first\" only (the magnet switched on at rest): drop it");
    if (!closed) return;
    p.magnetise_time = protocol.quantity("magnetise_time", units::time, p.magnetise_time, Bounds::positive());
    p.settle_window = protocol.quantity("settle_window", units::time, p.settle_window, Bounds::positive());
    p.settle_tolerance = protocol.number("settle_tolerance", p.settle_tolerance, Bounds::open(0.0, 1.0));
    p.magnetise_viscosity_share =
        protocol.number("magnetise_viscosity_share", p.magnetise_viscosity_share, Bounds::open_closed(0.0, 1.0));
    if (2 * p.settle_window > p.magnetise_time)
        protocol.fail("settle_window", "two windows must fit in protocol/magnetise_time (" +
                                           format_number(p.magnetise_time * 1e3) +
                                           " ms) to compare one with the next: give at most " +
                                           format_number(0.5 * p.magnetise_time * 1e3) + " ms");
}

// The model block's figures the other blocks need (the rest go straight to the engine inputs).
struct ModelBlock {
    double slab_diameters = 0;  // 0: the full bore
    double upstream = 0, downstream = 0;
    bool downstream_given = false;  // by the scene (the coupled flow may lengthen it otherwise)
};

// The model block: the modelled part of the valve (tier defaults, the scene wins) and the
// engine's speed settings.
ModelBlock read_model_block(SceneNode model, const json& scene, const TierSettings& ts, JamScene& out,
                            JamEngineInputs& engine) {
    ModelBlock b;
    b.slab_diameters = model.number("slab_thickness_diameters", ts.slab_diameters, Bounds::non_negative());
    b.upstream = model.quantity("upstream_length", units::length, ts.upstream, Bounds::positive());
    b.downstream_given =
        model.has("downstream_length") || (scene["valve"].is_object() && scene["valve"].contains("downstream_length"));
    b.downstream = model.quantity("downstream_length", units::length, ts.downstream, Bounds::positive());
    // The engine tier sets the dipoles' cutoff (quick 2, standard 3, paper 5 diameters); a scene may fix it.
    engine.cutoff_diameters = model.has("magnetic_cutoff_diameters")
                                  ? model.number("magnetic_cutoff_diameters", std::nullopt, Bounds::closed(1.0, 20.0))
                                  : 0.0;
    // Steps between magnetic evaluations (held in between; docs/magnetic_forces.md measures the cost).
    engine.magnetic_update_interval = model.integer("magnetic_update_interval", ts.magnetic_interval, 1, 100);
    // Close pairs: the two-sphere force near contact on top of the point dipoles
    // (docs/magnetic_forces.md, "Close pairs"). Off by default: the source's model is point
    // dipoles. `close_pairs: "saturating"` takes the finite-element table of saturating iron;
    // `close_pairs_min_gap` the linear pair above that floor.
    if (model.has("close_pairs") && model.has("close_pairs_min_gap"))
        model.fail("close_pairs_min_gap",
                   "is the linear model's floor; give close_pairs \"saturating\" or "
                   "close_pairs_min_gap (the linear model), not both");
    if (model.has("close_pairs")) {
        model.choice("close_pairs", {"saturating"}, std::nullopt);
        engine.close_pairs_saturating = true;
    }
    engine.close_pairs_min_gap = model.has("close_pairs_min_gap")
                                     ? model.number("close_pairs_min_gap", std::nullopt, Bounds::closed(0.005, 0.5))
                                     : 0.0;
    // Steps between carrier-flow lookups at the grains (held in between; docs/notes/jam_measurements.md
    // measures the cost).
    engine.flow_lookup_interval = model.integer("flow_lookup_interval", ts.flow_lookup_interval, 1, 100);
    // The Verlet skin (of the mean diameter): the lists are exact at any skin, so it trades list
    // builds against pairs checked, speed only (docs/notes/benchmark_log.md, "The Verlet skin",
    // measures it).
    engine.neighbour_skin = model.number("neighbour_skin", kDefaultSkinFraction, Bounds::open_closed(0.0, 2.0));
    // The slab's plane faces stand for more of the same suspension beside it, moving with it: a
    // frictionless face carries no shear across the plane, as symmetry asks of a thin slab about
    // x = 0. A frictional one holds chains pressed against it like a real wall would, and that
    // friction alone arrested the quick 30x case and the 10 um mix that the full bore and the
    // frictionless slab let flow (docs/notes/jam_measurements.md, "The slab's faces"); so
    // frictionless is the default.
    engine.frictionless_slab =
        model.choice("slab_faces", {"frictionless", "frictional"}, "frictionless") == "frictionless";
    // Mass scaling: grains finer than this get its Stokes and Rayleigh times (their mass x
    // (D / d)^2; a grain batch's mass_scaling, docs/scene.md), so the finest grains stop setting
    // the step. The quick tier gives every grain the largest one's (-1 here: set once the size
    // table is read): its step 1.9 times longer on the 44 um table with the same outcomes over
    // seeds (docs/notes/jam_speed.md, "Heavier fine grains"); the other tiers leave masses as they are.
    engine.heavier_below = model.has("heavier_below") || !ts.heavier_below_largest
                               ? model.quantity("heavier_below", units::length, 0.0, Bounds::non_negative())
                               : -1.0;
    // How the grains are fed. `periodic`: grains leaving downstream re-enter upstream, a steady
    // feed. `batch`: the grains filled at the start are all there is; those leaving downstream
    // are taken out and none come in, as in a DEM run whose grains were "initialized ... inside
    // of the constrictions" (section 3.4.4) with an open outlet: the upstream end drains.
    out.batch_supply = model.choice("supply", {"periodic", "batch"}, "periodic") == "batch";
    // The modelled tube's length may be given in either block, but not in both: one would be
    // ignored.
    for (const char* k : {"upstream_length", "downstream_length"})
        if (model.has(k) && scene["valve"].is_object() && scene["valve"].contains(k))
            throw SceneError(std::string("/model/") + k,
                             std::string("also given as valve/") + k + "; give the modelled tube's length once");
    model.finish();
    return b;
}

// The valve: the model's lengths replace the valve's own unless the valve gives them.
void read_valve_block(SceneNode& root, const json& scene, const ModelBlock& b, JamScene& out) {
    json valve_in = scene["valve"];
    if (valve_in.is_object()) {
        if (!valve_in.contains("upstream_length")) valve_in["upstream_length"] = b.upstream;
        if (!valve_in.contains("downstream_length")) valve_in["downstream_length"] = b.downstream;
    }
    json valve_echo;
    // A model length too short for the constriction is the model block's fault, so say so there.
    const bool lengths_from_model = valve_in.is_object() && !scene["valve"].contains("upstream_length");
    try {
        out.valve = read_valve(SceneNode(valve_in, valve_echo, "/valve"));
    } catch (const SceneError& e) {
        if (lengths_from_model && e.path() == "/valve/upstream_length") throw e.at("/model/upstream_length");
        throw;
    }
    root.resolved_child("valve") = valve_echo;
    root.raw("valve");
}

// A size table of the user's own: diameters and their relative mass.
MassTable read_size_table(SceneNode& grains) {
    MassTable table;
    table.diameters = grains.quantity_list("diameters", units::length, Bounds::positive());
    table.mass = grains.quantity_list("mass_fractions", units::dimensionless, Bounds::non_negative());
    if (table.diameters.empty()) grains.fail("diameters", "the size table is empty; give at least one diameter");
    if (table.mass.size() != table.diameters.size())
        grains.fail("mass_fractions", "needs one entry per diameter (" + std::to_string(table.diameters.size()) + ")");
    if (std::accumulate(table.mass.begin(), table.mass.end(), 0.0) <= 0)
        grains.fail("mass_fractions", "must not all be zero");
    // The largest class sets the slab, the cells and the skin: an empty one would set them for
    // grains that are never drawn.
    for (std::size_t k = 0; k < table.mass.size(); ++k)
        if (table.mass[k] == 0)
            throw SceneError(grains.path() + "/mass_fractions/" + std::to_string(k),
                             "is 0: a class without mass still sets the model's scales (the largest diameter); "
                             "drop it and its diameter");
    return table;
}

// The grains' size table and feed fraction, and what they must fit: the throat, the slab, the slot.
MassTable read_grains_block(SceneNode grains, const ModelBlock& b, JamScene& out) {
    if (grains.has("diameters") && grains.has("psd"))
        grains.fail("psd", "give a preset size table (psd) or your own (diameters and mass_fractions), not both");
    const MassTable table = grains.has("diameters") ? read_size_table(grains)
                                                    : preset_table(grains.choice("psd", {"44um", "10um"}, "44um"));
    out.feed_fraction = grains.number("volume_fraction", 0.345, Bounds::open(0.0, 0.64));
    grains.finish();
    out.largest_diameter = *std::max_element(table.diameters.begin(), table.diameters.end());
    const ValveGeometry& v = out.valve;
    if (out.largest_diameter >= v.constriction_diameter)
        throw SceneError("/valve/constriction_diameter", "the throat is not wider than the largest grain (" +
                                                             format_number(out.largest_diameter * 1e6) +
                                                             " um); widen it or use finer grains");
    // The slab (0: the full bore) must hold the largest grain and cut a passage through the throat.
    if (b.slab_diameters > 0 && b.slab_diameters < 1)
        throw SceneError("/model/slab_thickness_diameters",
                         "must be at least 1 (the largest grain must fit between the faces), or 0 for the full bore");
    if (!v.is_slot() && b.slab_diameters * out.largest_diameter >= v.constriction_diameter)
        throw SceneError("/model/slab_thickness_diameters",
                         "a slab " + format_number(b.slab_diameters) +
                             " largest grains thick is not narrower than the throat (" +
                             format_number(v.constriction_diameter / out.largest_diameter) +
                             " of them): give fewer, or 0 for the full bore");
    if (v.is_slot() && out.largest_diameter >= v.slot_width)
        throw SceneError("/valve/slot_width", "the slot is not wider than the largest grain (" +
                                                  format_number(out.largest_diameter * 1e6) +
                                                  " um); widen it or use finer grains");
    out.slab_half_thickness = b.slab_diameters > 0 ? 0.5 * b.slab_diameters * out.largest_diameter : 0.0;
    return table;
}

// The grains' material: the source's contact properties. Section 3.4.4 prints only E and the
// friction: restitution, Poisson's ratio, rolling resistance and cohesion default to a bare
// Hertz-Mindlin contact, and Table 2.1's MRF suite is one scene away
// (examples/valve_mix2_30x_table21.json).
json read_material_block(SceneNode mat, JamScene& out) {
    json material = {
        {"name", "iron"},
        {"density", mat.quantity("density", units::density, 7800.0, density_range())},
        {"youngs_modulus", mat.quantity("youngs_modulus", units::pressure, 1e9, youngs_modulus_range())},
        {"poisson_ratio", mat.number("poisson_ratio", 0.3, Bounds::closed(0.0, 0.5))},
        {"restitution", mat.number("restitution", 0.5, Bounds::open_closed(0.0, 1.0))},
        {"friction", mat.number("friction", 0.4, Bounds::non_negative())},
        {"rolling_friction", mat.number("rolling_friction", 0.0, Bounds::non_negative())},
        {"rolling_damping", mat.number("rolling_damping", 0.0, Bounds::non_negative())},
        {"cohesion_energy_density",
         mat.quantity("cohesion_energy_density", units::pressure, 0.0, Bounds::non_negative())},
        {"relative_permeability", mat.number("relative_permeability", 1000.0, Bounds::closed(1.0, 1e7))},
        {"saturation_magnetisation", mat.quantity("saturation_magnetisation", units::magnetic_field,
                                                  Material{}.saturation_magnetisation, Bounds::positive())}};
    if (material["rolling_damping"].get<double>() > 0 && !(material["rolling_friction"].get<double>() > 0))
        mat.fail("rolling_damping",
                 "damps the EPSD rolling spring, which only rolling_friction > 0 switches on; "
                 "give rolling_friction or drop rolling_damping");
    mat.finish();
    // A lone sphere magnetises to M = 3 beta H0, beta = (mu_r - 1)/(mu_r + 2), until M reaches M_s.
    const double mu_r = material["relative_permeability"].get<double>();
    out.lone_grain_saturation_flux_density =
        mu_r > 1 ? kMu0 * material["saturation_magnetisation"].get<double>() * (mu_r + 2) / (3 * (mu_r - 1))
                 : std::numeric_limits<double>::infinity();
    return material;
}

// How far past the orifice the stream re-opens to the bore (the converging profile's jet, and
// the coupled flow's), checked against the room the modelled tube leaves; 0 without a jet.
double read_jet_length(SceneNode& fluid, SceneNode& root, const ModelBlock& b, const std::string& profile,
                       JamScene& out) {
    const ValveGeometry& v = out.valve;
    // The converging profile's jet must re-open before the periodic seam, a couple of cells
    // short of it so that the seam joins the bore's profile to itself (fluid/valve_flow.hpp).
    const bool has_jet = profile == "converging" || (out.flow.coupled && !v.is_slot());
    if (!has_jet && fluid.has("jet_length"))
        fluid.fail("jet_length",
                   "applies to the converging profile and the coupled flow only; set fluid/profile to "
                   "\"converging\" or fluid/flow to \"coupled\", or drop it");
    // The coupled flow's slices have no inertia, so its jet must be given room: a jet shorter than
    // the taper piled the grains where it slowed (the 44 um 20x case stopped arresting, the 10 um
    // one blew up; docs/notes/jam_measurements.md). Unless the scene fixes the tube's length, the
    // coupled flow lengthens it downstream until the taper's mirror fits.
    if (out.flow.coupled && !v.is_slot() && !b.downstream_given && !fluid.has("jet_length")) {
        const double needed = v.throat_end_z() + v.taper_length + 2.0 * out.flow.cell_length;
        if (needed > out.valve.downstream_length) {
            out.valve.downstream_length = needed;
            root.resolved_child("model")["downstream_length"] = needed;
            root.resolved_child("valve")["downstream_length"] = needed;
        }
    }
    if (!has_jet) return 0;
    const double room = v.downstream_length - v.throat_end_z() - 2.0 * out.flow.cell_length;
    if (fluid.has("jet_length")) {
        const double jet_length = fluid.quantity("jet_length", units::length, std::nullopt, Bounds::positive());
        if (jet_length > room)
            fluid.fail("jet_length",
                       "the stream must re-open two resistance cells before the modelled tube ends: at most " +
                           format_number(room * 1e3) + " mm here; shorten it or lengthen model/downstream_length");
        return jet_length;
    }
    if (!(room > 0))
        fluid.fail("profile", "the converging jet has no room past the orifice exit; lengthen model/downstream_length");
    // The jet mirrors the taper by default: a stepped orifice has none to mirror.
    if (!(v.taper_length > 0))
        fluid.fail("jet_length",
                   "is the taper's length by default, and this valve has no taper "
                   "(valve/taper_length 0): give how far past the orifice the stream "
                   "re-opens to the bore, e.g. \"0.5 mm\"");
    return std::min(v.taper_length, room);  // the taper mirrored, if it fits
}

// The coupled flow's rings across the throat and the clear fluid's pressure it must exceed.
void read_coupled_rings(SceneNode& fluid, const MassTable& table, double viscosity, JamScene& out) {
    const ValveGeometry& v = out.valve;
    // Rings about a largest grain wide in the throat (at least 4, at most 32 per slice), and
    // the wall ring counted to the mix's volume-weighted mean radius from the wall.
    const double total = std::accumulate(table.mass.begin(), table.mass.end(), 0.0);
    double mean_radius = 0;
    for (std::size_t i = 0; i < table.diameters.size(); ++i)
        mean_radius += 0.5 * table.diameters[i] * table.mass[i] / total;
    out.flow.wall_gap = mean_radius;
    const int widest = static_cast<int>(std::floor(v.throat_radius() / (2.0 * mean_radius)));
    if (widest < 2)
        fluid.fail("flow",
                   "the throat is narrower than four mean grain diameters, too narrow for the coupled "
                   "flow's rings; use \"pressure\"");
    const int rings_default = std::clamp(static_cast<int>(std::floor(v.throat_radius() / out.largest_diameter)), 4, 32);
    out.flow.rings = static_cast<int>(fluid.integer("rings", std::min(rings_default, widest), 2, 256));
    if (out.flow.rings > widest)
        fluid.fail("rings", "at most " + std::to_string(widest) +
                                " here: a ring must be at least a mean grain diameter wide in the throat, "
                                "or grain centres cannot fill it");
    const double q0 = ValveFlow(v, out.flow.bore_speed).reference_flow_rate();
    const double clear =
        clear_stretch_pressure(v, -v.upstream_length, v.downstream_length, out.flow.jet_length, viscosity, q0);
    if (out.flow.supply_pressure <= clear)
        fluid.fail("supply_pressure", "must exceed the " + format_number(clear) +
                                          " Pa the clear fluid needs through the modelled stretch at the bore "
                                          "flow; raise it or lower bore_speed");
}

// The carrier fluid and its flow: viscosity, the flow model, its profile, the supply pressure,
// the resistance cells, the jet and the coupled flow's rings.
void read_fluid_block(SceneNode fluid, SceneNode& root, const ModelBlock& b, const MassTable& table, JamScene& out,
                      JamEngineInputs& engine) {
    const ValveGeometry& v = out.valve;
    engine.viscosity = fluid.quantity("viscosity", units::viscosity, 0.16, Bounds::positive());
    // Positive: the no-field flux it drives is what an arrest is measured against.
    out.flow.bore_speed = fluid.quantity("bore_speed", units::velocity, 0.273, Bounds::positive());
    // The experiment drove the fluid with a regulated supply pressure (105 kPa): pressure-driven by
    // default. A slot has the prescribed profile only.
    const std::string flow_model =
        fluid.choice("flow", {"prescribed", "pressure", "coupled"}, v.is_slot() ? "prescribed" : "pressure");
    out.flow.coupled = flow_model == "coupled";
    out.flow.pressure_driven = flow_model != "prescribed";
    // The coupled flow solves its own profile (lib/jam/coupled_flow.hpp); the engine scene keeps
    // the source's for the time step's characteristic speed only.
    if (out.flow.coupled && fluid.has("profile"))
        fluid.fail("profile", "the coupled flow computes the fluid's profile from the grains; drop fluid/profile");
    // The slot's flow is the conserving reading only (fluid/slot_valve_flow.hpp).
    engine.profile = fluid.choice("profile", valve_flow_profile_names(), v.is_slot() ? "conserving" : "source");
    if (v.is_slot() && engine.profile != "conserving")
        fluid.fail("profile", "a slot orifice has the conserving profile only; use \"conserving\"");
    out.flow.supply_pressure = fluid.quantity("supply_pressure", units::pressure, 105e3, Bounds::positive());
    out.flow.cell_length =
        fluid.quantity("resistance_cell_length", units::length, 2.0 * out.largest_diameter, Bounds::positive());
    if (out.flow.cell_length < out.largest_diameter)
        fluid.fail("resistance_cell_length", "must be at least the largest grain's diameter (" +
                                                 format_number(out.largest_diameter * 1e6) +
                                                 " um): a cell's volume fraction is counted from grain centres");
    out.flow.jet_length = read_jet_length(fluid, root, b, engine.profile, out);
    if (out.flow.coupled && !v.is_slot())
        read_coupled_rings(fluid, table, engine.viscosity, out);
    else if (fluid.has("rings"))
        fluid.fail("rings", "applies to the coupled flow only; set fluid/flow to \"coupled\" or drop it");
    // The resistance cells drive the circular orifice's profile (fluid/valve_flow.hpp); the
    // slot's profile (fluid/slot_valve_flow.hpp) has no pressure controller yet.
    if (out.flow.pressure_driven && v.is_slot())
        fluid.fail("flow",
                   "the pressure-driven and coupled flows are modelled for circular orifices only; use "
                   "\"prescribed\" with a slot");
    fluid.finish();
}

// A field map from `mrjam magnetics`, which must cover the modelled valve.
json read_field_map(SceneNode& field, const std::string& base_directory, JamScene& out) {
    const ValveGeometry& v = out.valve;
    const std::string file = field.text("file", std::nullopt);
    const double scale = field.number("scale", 1.0, Bounds::non_negative());
    std::filesystem::path path(file);
    if (path.is_relative() && !base_directory.empty()) path = std::filesystem::path(base_directory) / path;
    FieldMap map = [&] {
        try {
            return FieldMap::read(path.string());
        } catch (const std::exception& e) {
            throw SceneError("/field/file", e.what());
        }
    }();
    const Vec3 lo = map.lower_corner(), hi = map.upper_corner();
    const double tol = 1e-9, rb = v.bore_radius(), hx = out.half_width();
    if (lo.x > -hx + tol || hi.x < hx - tol || lo.y > -rb + tol || hi.y < rb - tol || lo.z > -v.upstream_length + tol ||
        hi.z < v.downstream_length - tol)
        throw SceneError("/field/file", "the field map does not cover the modelled valve (x " +
                                            format_number(-hx * 1e3) + "..." + format_number(hx * 1e3) + ", y +-" +
                                            format_number(rb * 1e3) + ", z " + format_number(-v.upstream_length * 1e3) +
                                            "..." + format_number(v.downstream_length * 1e3) +
                                            " mm); solve it with the same valve (mrjam magnetics --field-map)");
    out.peak_flux_density = scale * map.largest_flux_density();
    check_map_scale(field, "scale", out.peak_flux_density);
    out.field_map = std::make_shared<const FieldMap>(std::move(map));
    return {{"type", "map"}, {"file", std::filesystem::absolute(path).string()}, {"scale", scale}};
}

// The field: uniform across the valve (y) or a map from `mrjam magnetics`. Returns the engine's
// magnetic/field block.
json read_field_block(SceneNode field, const std::string& base_directory, JamScene& out) {
    out.field_type = field.choice("type", {"uniform", "map"}, "uniform");
    json field_json;
    if (out.field_type == "uniform") {
        const double b =
            field.quantity("flux_density", units::magnetic_flux_density, std::nullopt, Bounds::non_negative());
        const Vec3 dir = field.vector("direction", units::dimensionless, Vec3{0, 1, 0});
        if (norm(dir) == 0) field.fail("direction", "must be a non-zero vector");
        const Vec3 b0 = dir * (b / norm(dir));
        field_json = {{"type", "uniform"}, {"flux_density", json::array({b0.x, b0.y, b0.z})}};
        check_applied_flux_density(field, "flux_density", b);
        out.peak_flux_density = b;
    } else {
        field_json = read_field_map(field, base_directory, out);
    }
    field.finish();
    return field_json;
}

// The hold after an arrest: how long, and (the experiment raised the supply on a jammed valve:
// more than 405 kPa, section 3.4.2) at what supply pressure, reached over what ramp.
void read_hold(SceneNode& protocol, const JamFlow& flow, JamProtocol& p) {
    p.hold_time = protocol.quantity("hold_time", units::time, p.hold_time, Bounds::non_negative());
    const bool raised = protocol.has("hold_pressure");
    p.hold_pressure = protocol.quantity("hold_pressure", units::pressure, flow.supply_pressure, Bounds::positive());
    if (raised && !flow.pressure_driven)
        protocol.fail("hold_pressure",
                      "needs a pressure-driven flow (fluid/flow \"pressure\" or \"coupled\"); the "
                      "prescribed flow has no supply pressure");
    if (raised && !(p.hold_time > 0))
        protocol.fail("hold_pressure", "is the supply pressure during the hold: give protocol/hold_time too");
    // The experiment raised the pressure on a jammed valve to see what it holds; a lower one asks nothing of it.
    if (raised && p.hold_pressure < flow.supply_pressure)
        protocol.fail("hold_pressure",
                      "is below fluid/supply_pressure (" + format_number(flow.supply_pressure / 1e3) +
                          " kPa): the hold tests what a jam holds above the supply; give at least that");
    const bool ramped = protocol.has("hold_pressure_ramp");
    p.hold_pressure_ramp = protocol.quantity("hold_pressure_ramp", units::time, 0.0, Bounds::non_negative());
    if (ramped && !raised)
        protocol.fail("hold_pressure_ramp", "ramps the supply to protocol/hold_pressure: give that too");
    if (p.hold_pressure_ramp > p.hold_time)
        protocol.fail("hold_pressure_ramp", "must not exceed protocol/hold_time: the hold should reach its pressure");
}

// The protocol: its order, the periods, the arrest and release tests, the hold.
void read_protocol_block(SceneNode protocol, const JamFlow& flow, JamProtocol& p) {
    read_protocol_order(protocol, p);
    p.flow_time = protocol.quantity("flow_time", units::time, p.flow_time, Bounds::positive());
    p.max_time = protocol.quantity("max_time", units::time, p.max_time, Bounds::positive());
    p.arrest_window = protocol.quantity("arrest_window", units::time, p.arrest_window, Bounds::positive());
    p.arrest_fraction = protocol.number("arrest_fraction", p.arrest_fraction, Bounds::any());
    if (!(p.arrest_fraction > 0 && p.arrest_fraction < 1))
        protocol.fail("arrest_fraction",
                      "must lie in (0, 1): arrest is flux below this share of the no-field flux "
                      "(zero would never be reached by a noisy count)");
    read_hold(protocol, flow, p);
    p.release_time = protocol.quantity("release_time", units::time, p.release_time, Bounds::non_negative());
    // The release is judged over one arrest window with the field off: a shorter release period
    // would end before the test is made and report every arrest as irreversible.
    if (p.release_time < p.arrest_window)
        protocol.fail("release_time", "must be at least protocol/arrest_window (" +
                                          format_number(p.arrest_window * 1e3) +
                                          " ms): the release is judged over one window with the field off");
    p.release_fraction = protocol.number("release_fraction", p.release_fraction, Bounds::open(0.0, 1.0));
    p.observe_every = protocol.integer("observe_every_steps", p.observe_every, 1, 100000);
    if (p.arrest_window >= p.max_time) protocol.fail("arrest_window", "must be shorter than max_time");
    p.steady_window = protocol.quantity("steady_window", units::time, p.steady_window, Bounds::non_negative());
    p.steady_tolerance = protocol.number("steady_tolerance", p.steady_tolerance, Bounds::open(0.0, 1.0));
    if (p.steady_window > 0.5 * p.max_time)
        protocol.fail("steady_window",
                      "two windows must fit in max_time: give at most half of it, or 0 to run to max_time");
    if (p.order == JamOrder::closed_first && !flow.pressure_driven)
        protocol.fail("order",
                      "closed_first applies the supply pressure to a fluid at rest: it needs fluid/flow \"pressure\" "
                      "or \"coupled\" (the prescribed flow has no pressure); or give \"open_first\"");
    protocol.finish();
}

// Where the run writes: its directory (checkpoints), snapshots and checkpoints by step count.
void read_jam_output(SceneNode output, JamEngineInputs& engine) {
    // Each seed's checkpoint goes where the campaign and `--resume` look for it.
    engine.output = read_output_block(output, "out/jam",
                                      "the jam run keeps each seed's checkpoint as checkpoint.mrjam in "
                                      "output/directory, where --resume finds it: drop path");
}

}  // namespace

JamScene read_jam_scene(const json& user, const std::string& tier, const std::string& base_directory) {
    JamScene out;
    out.tier = tier;
    if (!user.is_object()) throw SceneError("", "a jam scene is a JSON object");
    json scene = user;
    // Every block but the field has defaults; the field changes the answer most, so it is never
    // assumed (a scene without a magnet writes {"type": "uniform", "flux_density": "0 mT"}).
    if (!scene.contains("field"))
        throw SceneError("/field",
                         "required: the applied field, e.g. {\"type\": \"uniform\", \"flux_density\": "
                         "\"230 mT\"}, a map from mrjam magnetics, or \"0 mT\" for none");
    for (const char* key : {"valve", "grains", "material", "fluid", "protocol", "model", "output"})
        if (!scene.contains(key)) scene[key] = json::object();
    SceneNode root(scene, out.resolved, "");
    root.text("description", "");
    JamEngineInputs engine;
    engine.seed = root.integer("seed", 1, 0);
    // Blocks in the order they depend on each other: the model sizes the valve, the valve and
    // the model bound the grains, the grains size the flow's cells, the flow bounds the protocol.
    const ModelBlock model = read_model_block(root.object("model"), scene, tier_settings(tier), out, engine);
    read_valve_block(root, scene, model, out);
    const MassTable table = read_grains_block(root.object("grains"), model, out);
    engine.diameters = table.diameters;
    engine.mass = table.mass;
    if (engine.heavier_below < 0)
        out.resolved["model"]["heavier_below"] = engine.heavier_below =
            *std::max_element(table.diameters.begin(), table.diameters.end());
    engine.material = read_material_block(root.object("material"), out);
    read_fluid_block(root.object("fluid"), root, model, table, out, engine);
    engine.field = read_field_block(root.object("field"), base_directory, out);
    read_protocol_block(root.object("protocol"), out.flow, out.protocol);
    read_continuum(root, tier, base_directory, out);
    read_jam_output(root.object("output"), engine);
    root.finish();
    out.engine_scene = jam_engine_scene(out, engine);
    return out;
}

}  // namespace mrjam
