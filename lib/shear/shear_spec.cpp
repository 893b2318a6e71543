#include "shear/shear_spec.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/format.hpp"
#include "geometry/disc_packing.hpp"
#include "geometry/size_distribution.hpp"
#include "scene/material_ranges.hpp"
#include "scene/scene_node.hpp"
#include "scene/scene_physics.hpp"

namespace mrjam {
namespace {

std::string fmt_um(double m) {
    char b[64];
    std::snprintf(b, sizeof b, "%.3g um", m * 1e6);
    return b;
}

// One table or single size; returns the distribution and the engine's "size" object.
SizeDistribution read_part(SceneNode node, nlohmann::json& engine) {
    const std::string kind = node.choice("distribution", {"single", "table"}, "table");
    if (kind == "single") {
        const double d = node.quantity("diameter", units::length, std::nullopt, Bounds::positive());
        node.finish();
        engine = {{"distribution", "single"}, {"diameter", d}};
        return SizeDistribution::single(d);
    }
    const auto diameters = node.quantity_list("diameters", units::length, Bounds::positive());
    const auto frequencies = node.quantity_list("frequencies", units::dimensionless, Bounds::non_negative());
    if (diameters.empty())
        node.fail(
            "diameters",
            "the size table is empty; list the class diameters (e.g. [\"1.46 um\", ...]) with one frequency each");
    if (diameters.size() != frequencies.size())
        node.fail("frequencies", "needs one entry per diameter (" + std::to_string(diameters.size()) + ")");
    const std::string basis = node.choice("basis", {"number", "volume"}, "number");
    node.finish();
    try {
        auto d = SizeDistribution::table(
            diameters, frequencies,
            basis == "number" ? SizeDistribution::FrequencyBasis::number : SizeDistribution::FrequencyBasis::volume);
        engine = {{"distribution", "table"}, {"diameters", diameters}, {"frequencies", frequencies}, {"basis", basis}};
        return d;
    } catch (const std::invalid_argument& e) {
        node.fail("frequencies", std::string(e.what()) + "; give at least one positive frequency");
    }
}

// A single size, a table, or a mixture of them by share of solid volume (Trendler's 33:67 is
// 33 parts of the small powder to 67 of the large, by volume of iron).
SizeDistribution read_sizes(SceneNode node, nlohmann::json& engine) {
    if (!node.has("distribution") || node.raw("distribution") != "mixture") return read_part(node, engine);
    node.choice("distribution", {"mixture"}, std::nullopt);
    std::vector<std::pair<SizeDistribution, double>> parts;
    auto items = node.objects("parts", true);
    if (items.empty()) node.fail("parts", "a mixture needs at least one part {\"share\": ..., \"size\": {...}}");
    double share_sum = 0;
    for (auto& item : items) {
        const double share = item.number("share", std::nullopt, Bounds::non_negative());
        share_sum += share;
        nlohmann::json unused;
        parts.emplace_back(read_part(item.object("size"), unused), share);
        item.finish();
    }
    // Shares as fractions or as per cent: a sum that is neither is a typing slip (30 and 67) that
    // a silent normalisation would turn into a different fluid.
    const bool fractions = std::fabs(share_sum - 1.0) <= 1e-3, percent = std::fabs(share_sum - 100.0) <= 0.1;
    if (share_sum > 0 && !fractions && !percent)
        node.fail("parts", "the shares sum to " + format_number(share_sum) +
                               "; give fractions of the solid volume that sum to 1 or per cent that sum to 100 "
                               "(Trendler's 33:67 fluid is 33 and 67)");
    node.finish();
    SizeDistribution mix = SizeDistribution::single(1);
    try {
        mix = SizeDistribution::mixture(parts);
    } catch (const std::invalid_argument& e) {
        node.fail("parts", std::string(e.what()) + "; give at least one positive share");
    }
    // The engine takes the merged classes as a number table.
    std::vector<double> d, f;
    for (const auto& c : mix.discrete_classes()) {
        d.push_back(c.diameter);
        f.push_back(c.number_fraction);
    }
    engine = {{"distribution", "table"}, {"diameters", d}, {"frequencies", f}, {"basis", "number"}};
    return mix;
}

std::vector<double> decreasing_list(SceneNode& node, const std::string& key, const units::Dimension& dim) {
    auto v = node.quantity_list(key, dim, Bounds::positive());
    if (v.empty()) node.fail(key, "needs at least one entry");
    for (std::size_t k = 1; k < v.size(); ++k)
        if (!(v[k] < v[k - 1]))
            throw SceneError(node.path_of(key) + "/" + std::to_string(k),
                             "the ladder must decrease: the first, highest rate builds the sheared structure and each "
                             "later rate relaxes it, as in the source's protocol; sort the entries from high to low");
    return v;
}

// Reads block `key` with `read`: the scene's own, or (left out) an empty one whose defaults the
// echo then records.
template <class Read>
void read_optional_block(SceneNode& root, const char* key, nlohmann::json& resolved, Read&& read) {
    nlohmann::json empty = nlohmann::json::object();
    if (auto given = root.optional_object(key))
        read(*given);
    else
        read(SceneNode(empty, resolved[key], std::string("/") + key));
}

// The cell block (every key has a default: the block may be left out).
void read_cell_block(SceneNode cell, const ShearTier& tier, ShearSpec& s) {
    // A monolayer: one layer of grains with centres in the x-z plane (shear and gradient),
    // `size` y its thickness for the stress, by default the largest diameter.
    s.monolayer = cell.boolean("monolayer", false);
    const double thickness = s.monolayer ? s.largest_diameter : tier.cell_size;
    s.cell = cell.vector("size", units::length, Vec3{tier.cell_size, thickness, tier.cell_size}, Bounds::positive());
    if (s.monolayer && s.cell.y < s.largest_diameter)
        cell.fail("size", "a monolayer's thickness (y, " + fmt_um(s.cell.y) + ") must hold the largest grain (" +
                              fmt_um(s.largest_diameter) +
                              "); it is the thickness the stress is divided by, usually the largest diameter");
    s.lees_edwards = cell.choice("boundaries", {"rafts", "lees_edwards"}, "rafts") == "lees_edwards";
    // The periodic sides (x; y in 3D; z between Lees-Edwards images) must exceed two of the
    // largest grains the size block can draw, or a grain would meet its own image: refused here,
    // by the key that fixes it, rather than by the packing that would fail on it.
    const bool periodic[3] = {true, !s.monolayer, s.lees_edwards};
    for (int k = 0; k < 3; ++k)
        if (periodic[k] && s.cell[k] <= 2 * s.largest_diameter)
            cell.fail("size", std::string("the periodic side ") + char('x' + k) + " (" + fmt_um(s.cell[k]) +
                                  ") must exceed two of the largest grains (" + fmt_um(2 * s.largest_diameter) +
                                  "); make the cell larger (the tiers use 90-125 um for Trendler's powders)");
    if (s.lees_edwards) {
        if (cell.has("raft_thickness"))
            cell.fail("raft_thickness",
                      "is used only with \"boundaries\": \"rafts\"; a Lees-Edwards cell has no rafts "
                      "(remove raft_thickness or use rafts)");
        s.raft_thickness = 0;
    } else {
        s.raft_thickness =
            cell.quantity("raft_thickness", units::length, std::min(15e-6, 0.125 * s.cell.z), Bounds::positive());
    }
    if (!(s.gap() > 0))
        cell.fail("raft_thickness", "the two rafts (" + fmt_um(s.raft_thickness) + " each) leave no gap in a cell " +
                                        fmt_um(s.cell.z) + " high; thin the rafts or raise the cell");
    cell.finish();
}

// The contact block (every key has a default: the block may be left out).
void read_contact_block(SceneNode c, ShearSpec& s) {
    s.rolling = c.choice("rolling", {"none", "epsd", "sds"}, "epsd");
    s.cohesion = c.choice("cohesion", {"none", "sjkr", "dmt"}, "sjkr");
    c.finish();
}

// The magnetic block (every key has a default: the block may be left out).
void read_magnetic_block(SceneNode m, const ShearTier& tier, ShearSpec& s) {
    s.magnetic = nlohmann::json::object();
    s.magnetic["mutual"] = m.choice("mutual", {"fixed", "lagged", "iterations", "converged"}, "lagged");
    if (m.has("cutoff"))
        s.magnetic["cutoff"] = m.raw("cutoff");
    else
        m.resolved_child("cutoff") = s.magnetic["cutoff"] = {{"beyond_contact", tier.magnetic_beyond_contact}};
    // Passed to the engine as they are (the engine's reader checks them, naming /magnetic/...):
    // the close-pair correction lets the calibration measure the same magnetic model the jam
    // predictor runs with `model/close_pairs_min_gap`.
    for (const char* k : {"iterations", "tolerance", "max_iterations", "close_pairs"})
        if (m.has(k)) s.magnetic[k] = m.raw(k);
    // "material": induced moments saturate at the material's M_s (iron 1.7e6 A/m);
    // "none": the linear law of eq. 2.4 without a cap, the source's chapter-2 model.
    s.saturation = m.choice("saturation", {"material", "none"}, "material");
    m.finish();
}

// The run block (every key has a default: the block may be left out).
void read_run_block(SceneNode r, const ShearTier& tier, ShearSpec& s) {
    s.run = nlohmann::json::object();
    s.run["timestep_safety"] = r.number("timestep_safety", tier.timestep_safety, Bounds::open_closed(0.0, 0.2));
    s.run["characteristic_speed"] = r.quantity("characteristic_speed", units::velocity, 1.0, Bounds::positive());
    // Magnetic attraction pulls small grains onto large ones at tens of m/s (drag is the only
    // brake): with the source's soft modulus (1 GPa) an impact overlaps a small grain by
    // 30-40% of its radius, resolved in ~40 steps - physics of the chosen modulus, not a
    // numerical blow-up (docs/shear.md), so the guard sits at 0.6 rather than run's 0.1.
    s.run["max_overlap_fraction"] = r.number("max_overlap_fraction", 0.6, Bounds::open(0.0, 1.0));
    if (r.has("timestep")) s.run["timestep"] = r.raw("timestep");
    r.finish();
}

// The magnetise block (every key has a default: the block may be left out).
void read_magnetise_block(SceneNode m, const ShearTier& tier, ShearSpec& s) {
    s.magnetise_check_every = m.quantity("check_every", units::time, 1e-6, Bounds::positive());
    s.magnetise_window = static_cast<int>(m.integer("window", 5, 2, 1000));
    s.magnetise_tolerance = m.number("tolerance", 0.02, Bounds::open(0.0, 1.0));
    s.magnetise_min = m.quantity("min_duration", units::time, 10e-6, Bounds::non_negative());
    // A field switched on at once pulls small grains onto large ones at tens of m/s (Stokes
    // drag is the only brake), overlapping them by 40% of their radius with the source's soft
    // modulus. Raising it over a few microseconds, as any real magnet does over far longer,
    // lets the first chains form gently; the settled structure is what is sheared.
    s.field_ramp = m.quantity("field_ramp", units::time, 5e-6, Bounds::non_negative());
    s.magnetise_max = m.quantity("max_duration", units::time, tier.magnetise_max, Bounds::positive());
    if (s.magnetise_max < s.magnetise_min) m.fail("max_duration", "must not be shorter than min_duration");
    // Sheared before the ramp ends, the cell would be measured in a field still rising.
    if (s.field_ramp > s.magnetise_min)
        m.fail(m.has("field_ramp") ? "field_ramp" : "min_duration",
               "the field ramps up over field_ramp (" + format_number(s.field_ramp * 1e6) +
                   " us) and the chains must settle in "
                   "the full field: make min_duration at least field_ramp");
    m.finish();
}

// The ladder block (every key has a default: the block may be left out).
void read_ladder_block(SceneNode l, const ShearTier& tier, ShearSpec& s) {
    if (l.has("wall_speeds") && l.has("shear_rates"))
        l.fail("shear_rates", "give either 'wall_speeds' or 'shear_rates', not both");
    if (l.has("wall_speeds")) {
        s.wall_speeds = decreasing_list(l, "wall_speeds", units::velocity);
        // The rafts move at +v and -v: the rate across the gap is 2 v / gap.
        for (double v : s.wall_speeds) s.rates.push_back(2 * v / s.gap());
    } else {
        if (l.has("shear_rates")) {
            s.rates = decreasing_list(l, "shear_rates", units::frequency);
        } else {
            // The source's ladder: wall speeds 0.128 ... 0.001 m/s across its 220 um gap
            // (sec. 2.4.2), kept as rates so a smaller cell shears at the same rates.
            for (double v : {0.128, 0.064, 0.032, 0.011, 0.008, 0.004, 0.002, 0.001}) s.rates.push_back(2 * v / 220e-6);
            l.resolved_child("shear_rates") = s.rates;
        }
        for (double g : s.rates) s.wall_speeds.push_back(0.5 * g * s.gap());
    }
    if (l.has("steps_first") || l.has("steps_per_rate")) {
        s.steps_first = l.integer("steps_first", std::nullopt, 1);
        s.steps_per_rate = l.integer("steps_per_rate", std::nullopt, 1);
    } else {
        s.strain_first = l.number("strain_first", tier.strain_first, Bounds::positive());
        s.strain_per_rate = l.number("strain_per_rate", tier.strain_per_rate, Bounds::positive());
    }
    l.finish();
}

// The measure block (every key has a default: the block may be left out).
void read_measure_block(SceneNode m, ShearSpec& s) {
    s.samples_per_rate = static_cast<int>(m.integer("samples_per_rate", 40, 4, 100000));
    s.window_fraction = m.number("window", 0.5, Bounds::open_closed(0.0, 1.0));
    // One block gives no spread to put an error bar on.
    s.blocks = static_cast<int>(m.integer("blocks", 5, 2, 1000));
    if (s.blocks > static_cast<int>(s.samples_per_rate * s.window_fraction))
        m.fail("blocks", "more blocks than samples in the window (" +
                             std::to_string(static_cast<int>(s.samples_per_rate * s.window_fraction)) +
                             "); use fewer blocks or more samples_per_rate");
    m.finish();
}

// The fit block (every key has a default: the block may be left out).
void read_fit_block(SceneNode f, ShearSpec& s) {
    s.bingham_min_rate = f.quantity("bingham_min_rate", units::frequency, 200.0, Bounds::non_negative());
    f.finish();
}

// The output block (every key has a default: the block may be left out).
void read_shear_output(SceneNode o, ShearSpec& s) {
    s.output = read_output_block(o, "out/shear",
                                 "the study keeps its checkpoint as shear_checkpoint.mrjam in output/directory (its "
                                 "field sweep's and convergence runs' beside it): drop path");
}

// How full the cell is: a monolayer by area, a 3D cell by volume.
void read_fill_fraction(SceneNode& root, ShearSpec& s) {
    if (s.monolayer) {
        if (root.has("volume_fraction"))
            root.fail("volume_fraction",
                      "a monolayer is filled by area: give \"area_fraction\" (default 0.5, at most 0.84) instead");
        s.area_fraction = root.number("area_fraction", 0.5, Bounds::open_closed(0.0, 1.0));
        if (s.area_fraction > kRandomClosePackingDiscs)
            root.fail("area_fraction",
                      "discs cannot be packed at random above 0.84 of the plane (random close packing); lower it");
    } else {
        if (root.has("area_fraction"))
            root.fail(
                "area_fraction",
                "is used only for a monolayer (\"cell\": {\"monolayer\": true}); a 3D cell takes \"volume_fraction\"");
        s.volume_fraction = root.number("volume_fraction", 0.3, Bounds::open_closed(0.0, 0.64));
    }
}

// The grains' material, and the scaling of its modulus and density that buys a longer step.
void read_material_and_scaling(SceneNode& root, const nlohmann::json& input, const ShearTier& tier, ShearSpec& s) {
    SceneNode mat = root.object("material");
    const double youngs = mat.quantity("youngs_modulus", units::pressure, std::nullopt, youngs_modulus_range());
    const double density = mat.quantity("density", units::density, std::nullopt, density_range());
    // The other material keys go to the engine's reader, which checks them (its refusals are
    // mapped back to /material/...); the echo keeps them as written.
    nlohmann::json echo = input.at("material");
    echo["youngs_modulus"] = youngs;
    echo["density"] = density;
    s.resolved["material"] = echo;
    s.material = echo;
    s.material["name"] = "grain";
    read_optional_block(root, "scaling", s.resolved, [&](SceneNode sc) {
        s.stiffness_scale = sc.number("stiffness", tier.stiffness_scale, Bounds::open_closed(0.0, 1.0));
        s.density_scale = sc.number("density", tier.density_scale, Bounds::closed(1.0, 1e4));
        // The scaled constants go to the engine, which holds them to the same ranges: say so here,
        // where the scale that took them out was given.
        if (!youngs_modulus_range().contains(youngs * s.stiffness_scale))
            sc.fail("stiffness", "scales the modulus to " + format_number(youngs * s.stiffness_scale) +
                                     " Pa, below the engine's floor (" + youngs_modulus_range().describe() +
                                     "); scale it less or start from a stiffer material");
        if (!density_range().contains(density * s.density_scale))
            sc.fail("density", "scales the density to " + format_number(density * s.density_scale) +
                                   " kg/m3, past the engine's range (" + density_range().describe() +
                                   "); scale it less");
        s.hold_magnetic_pull = sc.boolean("hold_magnetic_pull", false);
        s.heavier_below = sc.quantity("heavier_below", units::length, 0.0, Bounds::non_negative());
        sc.finish();
        s.material["youngs_modulus"] = youngs * s.stiffness_scale;
        s.material["density"] = density * s.density_scale;
    });
}

// scaling/hold_magnetic_pull: the modulus multiplied until the finest grain's contact holds the
// pull of the largest pair across it (shear/pull_holding.hpp); then the grains finer than the
// rule's diameter, or `heavier_below` if coarser, made heavier to keep the step. Needs the sizes,
// the field, the saturation and the rates.
void apply_contact_scaling(SceneNode& root, const SizeDistribution& sizes, ShearSpec& s) {
    if (!s.hold_magnetic_pull && s.heavier_below == 0) return;  // the material as given, read by the engine
    nlohmann::json scratch;
    const Material mat = read_material(SceneNode(s.material, scratch, "/material"));
    if (s.hold_magnetic_pull) {
        PullHoldingInput in;
        in.min_diameter = sizes.min_diameter();
        in.max_diameter = sizes.max_diameter();
        // The strongest field the study applies (a field sweep may go past the main one).
        in.flux_density = s.flux_density;
        for (double b : s.sweep_fields) in.flux_density = std::max(in.flux_density, b);
        in.relative_permeability = mat.relative_permeability;
        in.saturation_magnetisation =
            s.saturation == "none" ? std::numeric_limits<double>::infinity() : mat.saturation_magnetisation;
        in.youngs_modulus = mat.youngs_modulus;
        in.poisson_ratio = mat.poisson_ratio;
        s.pull_holding = pull_holding(in);
        const double youngs = mat.youngs_modulus * s.pull_holding.factor;
        if (!youngs_modulus_range().contains(youngs))
            root.fail("scaling/hold_magnetic_pull",
                      "would raise the modulus to " + format_number(youngs) + " Pa, past the engine's range (" +
                          youngs_modulus_range().describe() + "); the size ratio or the field is too large for it");
        s.material["youngs_modulus"] = youngs;
    }
    s.heavier_below = std::max(s.heavier_below, s.pull_holding.heavier_below);
    double fastest = s.sweep_fields.empty() ? 0.0 : s.sweep_rate;
    for (double r : s.rates) fastest = std::max(fastest, r);
    s.heavier_stokes_number = s.heavier_below > 0 && s.dissipation == "stokes_drag"
                                  ? stokes_number(s.heavier_below, mat.density, s.viscosity, fastest)
                                  : 0.0;
}

// The applied field: its flux density and direction.
void read_field_block(SceneNode f, ShearSpec& s) {
    s.flux_density = f.quantity("flux_density", units::magnetic_flux_density, std::nullopt, Bounds::non_negative());
    check_applied_flux_density(f, "flux_density", s.flux_density);
    const Vec3 dir = f.vector("direction", units::dimensionless, Vec3{0, 0, 1});
    if (norm(dir) == 0) f.fail("direction", "must be a non-zero vector (the source's field is along z, [0, 0, 1])");
    s.field_direction = dir / norm(dir);
    // The dipoles of a monolayer must lie in its plane, or they would pull grains out of it.
    if (s.monolayer && std::abs(s.field_direction.y) > 1e-12)
        f.fail("direction", "a monolayer lies in the x-z plane: the field must too (y component 0, e.g. [0, 0, 1])");
    f.finish();
    f.finish();
}

// The field sweep: the stress at one rate over a list of fields.
void read_field_sweep(SceneNode sw, ShearSpec& s) {
    s.sweep_fields = sw.quantity_list("flux_densities", units::magnetic_flux_density, Bounds::non_negative());
    if (s.sweep_fields.empty())
        sw.fail("flux_densities", "needs at least one flux density, e.g. [\"100 mT\", \"300 mT\"]");
    for (std::size_t k = 0; k < s.sweep_fields.size(); ++k) {
        check_applied_flux_density(sw, "flux_densities/" + std::to_string(k), s.sweep_fields[k]);
        // Each field is a study in its own folder: a repeat would be the same study.
        for (std::size_t j = 0; j < k; ++j)
            if (s.sweep_fields[j] == s.sweep_fields[k])
                sw.fail("flux_densities/" + std::to_string(k),
                        "repeats /field_sweep/flux_densities/" + std::to_string(j) + ": drop one");
    }
    s.sweep_rate = sw.quantity("shear_rate", units::frequency, 100.0, Bounds::positive());
    s.sweep_strain = sw.number("strain", s.strain_per_rate > 0 ? s.strain_per_rate : 0.1, Bounds::positive());
    sw.finish();
}

// The convergence study's cell sizes and seeds. By default three edges, the cell's and 1.25 and
// 1.5 times it (2 and 3.4 times the grains), three seeds each: enough to see whether the yield
// stress still moves with the cell beyond its seed scatter.
void read_convergence(std::optional<SceneNode> c, ShearSpec& s) {
    const std::vector<double> defaults = {s.cell.x, 1.25 * s.cell.x, 1.5 * s.cell.x};
    s.converge_cell_sizes = defaults;
    if (!c) return;
    if (c->has("cell_sizes")) {
        s.converge_cell_sizes = c->quantity_list("cell_sizes", units::length, Bounds::positive());
        if (s.converge_cell_sizes.size() < 3)
            c->fail("cell_sizes",
                    "needs at least three edges (e.g. [\"90 um\", \"112 um\", \"135 um\"]) to tell a "
                    "plateau from a trend");
        for (std::size_t k = 1; k < s.converge_cell_sizes.size(); ++k)
            if (!(s.converge_cell_sizes[k] > s.converge_cell_sizes[k - 1]))
                c->fail("cell_sizes/" + std::to_string(k), "the edges must increase");
    } else {
        c->resolved_child("cell_sizes") = defaults;
    }
    s.converge_seeds = static_cast<int>(c->integer("seeds", 3, 2, 1000));
    c->finish();
}

// The experiment to plot and compare against: a yield stress, a flow curve.
void read_experiment(SceneNode ex, ShearSpec& s) {
    s.experiment = nlohmann::json::object();
    s.experiment["label"] = ex.text("label", "experiment");
    if (ex.has("yield_stress"))
        s.experiment["yield_stress_Pa"] =
            ex.quantity("yield_stress", units::pressure, std::nullopt, Bounds::positive());
    if (ex.has("flow_curve")) {
        const auto& fc = ex.raw("flow_curve");
        if (!fc.is_array()) ex.fail("flow_curve", "must be a list of [shear rate in 1/s, stress in Pa] pairs");
        for (std::size_t k = 0; k < fc.size(); ++k)
            if (!fc[k].is_array() || fc[k].size() != 2 || !fc[k][0].is_number() || !fc[k][1].is_number())
                throw SceneError(ex.path_of("flow_curve") + "/" + std::to_string(k),
                                 "must be [shear rate in 1/s, stress in Pa]");
        s.experiment["flow_curve"] = fc;
    }
    if (ex.has("other_yield_stresses")) s.experiment["other_yield_stresses"] = ex.raw("other_yield_stresses");
    ex.finish();
}

}  // namespace

ShearSpec read_shear_spec(const nlohmann::json& input, const std::string& tier_name) {
    ShearSpec s;
    const ShearTier* tier_ptr = nullptr;
    try {
        tier_ptr = &shear_tier(tier_name);
    } catch (const std::invalid_argument& e) {
        throw SceneError("--fidelity", e.what());
    }
    const ShearTier& tier = *tier_ptr;
    s.tier = tier.name;
    s.input = input;
    s.resolved = nlohmann::json::object();
    if (!input.is_object()) throw SceneError("", "a shear scene is a JSON object (see docs/shear.md)");
    SceneNode root(input, s.resolved, "");
    root.choice("mode", {"shear"}, "shear");
    root.text("description", "");
    s.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0));

    // Sizes first: a monolayer's default thickness is the largest diameter.
    SizeDistribution sizes = read_sizes(root.object("size"), s.size_table);
    s.largest_diameter = sizes.max_diameter();
    read_optional_block(root, "cell", s.resolved, [&](SceneNode n) { read_cell_block(n, tier, s); });
    read_fill_fraction(root, s);

    read_material_and_scaling(root, input, tier, s);
    read_optional_block(root, "contact", s.resolved, [&](SceneNode n) { read_contact_block(n, s); });
    {
        SceneNode f = root.object("fluid");
        s.viscosity = f.quantity("viscosity", units::viscosity, std::nullopt, Bounds::positive());
        f.finish();
    }
    // Dissipation: Stokes drag against the affine (Couette) flow, as the source, or pairwise
    // damping between touching grains with no background flow. The default damping coefficient
    // is the Stokes coefficient 6 pi mu R of the number-mean grain, so the two are comparable.
    s.dissipation = root.choice("dissipation", {"stokes_drag", "contact_damping"}, "stokes_drag");
    if (s.dissipation == "contact_damping")
        s.contact_damping = root.quantity("contact_damping", units::damping,
                                          3.0 * M_PI * s.viscosity * sizes.mean_diameter_number(), Bounds::positive());
    else if (root.has("contact_damping"))
        root.fail("contact_damping", "is used only with \"dissipation\": \"contact_damping\"");
    read_field_block(root.object("field"), s);
    read_optional_block(root, "magnetic", s.resolved, [&](SceneNode n) { read_magnetic_block(n, tier, s); });
    read_optional_block(root, "run", s.resolved, [&](SceneNode n) { read_run_block(n, tier, s); });
    read_optional_block(root, "magnetise", s.resolved, [&](SceneNode n) { read_magnetise_block(n, tier, s); });
    read_optional_block(root, "ladder", s.resolved, [&](SceneNode n) { read_ladder_block(n, tier, s); });
    read_optional_block(root, "measure", s.resolved, [&](SceneNode n) { read_measure_block(n, s); });
    read_optional_block(root, "fit", s.resolved, [&](SceneNode n) { read_fit_block(n, s); });
    if (auto sw = root.optional_object("field_sweep")) read_field_sweep(*sw, s);
    apply_contact_scaling(root, sizes, s);
    read_convergence(root.optional_object("convergence"), s);
    if (auto ex = root.optional_object("experiment")) read_experiment(*ex, s);
    read_optional_block(root, "output", s.resolved, [&](SceneNode n) { read_shear_output(n, s); });
    root.finish();
    return s;
}

nlohmann::json engine_scene(const ShearSpec& s, double flux_density) {
    nlohmann::json scene = {
        {"mode", "shear"},
        {"seed", s.seed},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {s.cell.x, s.cell.y, s.cell.z}}, {"periodic", "xy"}}},
        {"materials", {s.material}},
        {"contact", {{"model", "hertz_mindlin"}, {"rolling", s.rolling}, {"cohesion", s.cohesion}}},
        {"fluid", {{"viscosity", s.viscosity}}},
        {"walls",
         {{{"name", "bottom"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
          {{"name", "top"}, {"type", "plane"}, {"point", {0, 0, s.cell.z}}, {"normal", {0, 0, -1}}}}},
        {"grains",
         {{{"material", "grain"},
           {"size", s.size_table},
           {"placement", {{"method", "random"}, {"volume_fraction", s.volume_fraction}}}}}},
        {"run", s.run},
        {"output", engine_output_json(s.output)}};
    scene["run"]["steps"] = 0;
    if (s.heavier_below > 0) scene["grains"][0]["mass_scaling"] = {{"below_diameter", s.heavier_below}};
    if (s.monolayer) {
        // Centres in the mid-plane y = Y/2, no y images, no y walls: the integrator holds them there.
        scene["domain"]["periodic"] = "x";
        scene["domain"]["monolayer"] = "y";
        scene["grains"][0]["placement"] = {{"method", "monolayer"}, {"area_fraction", s.area_fraction}};
    }
    if (s.lees_edwards) {
        // Periodic in z too: the sliding images replace the walls (shear_cell.cpp switches the
        // domain to Lees-Edwards; the random packing sees an ordinary periodic box).
        scene["domain"]["periodic"] = s.monolayer ? "xz" : "xyz";
        scene.erase("walls");
    }
    if (s.dissipation == "contact_damping") {
        scene.erase("fluid");
        scene["contact"]["pair_damping"] = s.contact_damping;
    }
    // Without saturation the cap is put out of reach: M_s V would exceed any induced moment.
    if (s.saturation == "none") scene["materials"][0]["saturation_magnetisation"] = 1e300;
    if (flux_density > 0) {
        nlohmann::json mag = s.magnetic;
        const Vec3 b = s.field_direction * flux_density;
        mag["field"] = {{"type", "uniform"}, {"flux_density", {b.x, b.y, b.z}}, {"ramp", s.field_ramp}};
        scene["magnetic"] = mag;
    }
    return scene;
}

std::string ladder_length_key(std::size_t rate_index, bool by_steps) {
    if (rate_index == 0) return by_steps ? "/ladder/steps_first" : "/ladder/strain_first";
    return by_steps ? "/ladder/steps_per_rate" : "/ladder/strain_per_rate";
}

std::string shear_path_of(const std::string& p) {
    const std::pair<const char*, const char*> map[] = {{"/materials/0", "/material"},
                                                       {"/grains/0/size", "/size"},
                                                       {"/grains/0/placement/volume_fraction", "/volume_fraction"},
                                                       {"/grains/0/placement/area_fraction", "/area_fraction"},
                                                       {"/grains/0", "/size"},
                                                       {"/domain", "/cell/size"},
                                                       {"/magnetic/field", "/field"},
                                                       {"/magnetic", "/magnetic"},
                                                       {"/run", "/run"},
                                                       {"/output", "/output"}};
    for (const auto& [from, to] : map)
        if (p.rfind(from, 0) == 0) {
            std::string rest = p.substr(std::string(from).size());
            if (std::string(to) == "/cell/size") rest.clear();
            return to + rest;
        }
    return p;
}

}  // namespace mrjam
