#include "jam/jam_engine_scene.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "fluid/slot_valve_flow.hpp"

namespace mrjam {

using json = nlohmann::json;

namespace {
json vec(double x, double y, double z) { return json::array({x, y, z}); }
}  // namespace

json jam_stages(const JamProtocol& p) {
    json stages = json::array({{{"name", "flow"}, {"duration", p.flow_time}}});
    if (p.order == JamOrder::closed_first) {
        stages.push_back({{"name", "magnetise"}, {"duration", p.magnetise_time}});
        stages.push_back({{"name", "pressure"}, {"duration", p.max_time}});
    } else {
        stages.push_back({{"name", "field_on"}, {"duration", p.max_time}});
    }
    stages.push_back({{"name", "release"}, {"duration", std::max(p.hold_time + p.release_time, 1e-12)}});
    return stages;
}

json jam_engine_scene(const JamScene& js, const JamEngineInputs& in) {
    const ValveGeometry& v = js.valve;
    const double rb = v.bore_radius();
    const double hx = js.half_width();
    const double d_up = v.upstream_length, d_down = v.downstream_length;
    const double inset = 1e-9;
    json valve_si = {{"tube_inner_diameter", v.tube_inner_diameter},
                     {"wall_thickness", v.wall_thickness},
                     {"constriction_diameter", v.constriction_diameter},
                     {"taper_length", v.taper_length},
                     {"throat_length", v.throat_length},
                     {"upstream_length", d_up},
                     {"downstream_length", d_down}};
    if (v.is_slot()) {
        valve_si["orifice"] = "slot";
        valve_si["slot_width"] = v.slot_width;
    }
    json walls = json::array({{{"name", "valve"}, {"type", "passage"}, {"valve", valve_si}}});
    json materials = json::array({in.material});
    json material_pairs = json::array();
    if (js.is_slab()) {
        std::string face_material = "iron";
        if (in.frictionless_slab) {
            json face = in.material;
            face["name"] = face_material = "slab_face";
            materials.push_back(face);
            material_pairs.push_back({{"materials", {"iron", "slab_face"}},
                                      {"friction", 0.0},
                                      {"rolling_friction", 0.0},
                                      {"cohesion_energy_density", 0.0}});
        }
        for (const auto& [name, side] : {std::pair{"slab_low", -1.0}, std::pair{"slab_high", 1.0}})
            walls.push_back({{"name", name},
                             {"type", "plane"},
                             {"material", face_material},
                             {"point", vec(side * hx, 0, 0)},
                             {"normal", vec(-side, 0, 0)}});
    }
    // Grains start at the feed fraction everywhere in the passage (a box inside the slab's
    // chord, or a cylinder for the full bore, per slice), so grains cross the throat from the
    // start and the no-field flux is measured in the first flow period.
    auto region = [&](double z0, double z1, double radius) {
        if (radius == 0) {  // the slot's straight part, in the slab if the slot is wider
            const double sx = std::min(0.5 * v.slot_width, hx), sy = v.throat_radius();
            return json{
                {"shape", "box"}, {"lo", vec(-sx + inset, -sy + inset, z0)}, {"hi", vec(sx - inset, sy - inset, z1)}};
        }
        const double y = std::sqrt(std::max(0.0, radius * radius - hx * hx));
        if (js.is_slab())
            return json{
                {"shape", "box"}, {"lo", vec(-hx + inset, -y + inset, z0)}, {"hi", vec(hx - inset, y - inset, z1)}};
        return json{
            {"shape", "cylinder"}, {"axis", "z"}, {"base", vec(0, 0, z0)}, {"radius", radius}, {"length", z1 - z0}};
    };
    json size = {{"distribution", "table"}, {"diameters", in.diameters}, {"frequencies", in.mass}, {"basis", "volume"}};
    // The circular taper is filled as a staircase of slices two largest grains long, each as wide
    // as the cone at its narrow end, so the feed fraction holds in the taper too (within the
    // staircase's wedges, ~5 % of the taper's volume) and the stretch as a whole carries the
    // mix's fraction. (Filling only the throat's radius there left the 10 um stretch at 0.28
    // overall.) The slot's taper keeps the slot's straight box.
    std::vector<std::tuple<double, double, double>> slices{{-d_up, v.taper_start_z(), rb}};
    if (v.is_slot()) {
        slices.emplace_back(v.taper_start_z(), v.throat_end_z(), 0.0);
    } else {
        const double start = v.taper_start_z(), throat_start = -0.5 * v.throat_length;
        // At most 256 slices (the bundled valves use 5-20): the wedges' share falls as 1/n, to a
        // few tenths of a per cent there, while grains far too fine to simulate (refused by the
        // packer's memory check) would otherwise make a million slices of JSON before that
        // refusal: 11.5 s for 1 nm grains, 0.7 s with the cap.
        const double two_grains = 2.0 * js.largest_diameter;
        const int n = static_cast<int>(std::clamp(std::ceil(v.taper_length / two_grains), 1.0, 256.0));
        for (int k = 0; k < n; ++k) {
            const double z0 = start + k * v.taper_length / n, z1 = start + (k + 1) * v.taper_length / n;
            slices.emplace_back(z0, z1, v.passage_radius(z1));
        }
        slices.emplace_back(throat_start, v.throat_end_z(), v.throat_radius());
    }
    slices.emplace_back(v.throat_end_z(), d_down, rb);
    json batches = json::array();
    for (const auto& [z0, z1, radius] : slices) {
        if (!(z1 > z0)) continue;  // a valve without a taper (a step) or without a throat (a sharp edge)
        batches.push_back(
            {{"material", "iron"},
             {"size", size},
             {"placement",
              {{"method", "random"}, {"volume_fraction", js.feed_fraction}, {"region", region(z0, z1, radius)}}}});
        if (in.heavier_below > 0) batches.back()["mass_scaling"] = {{"below_diameter", in.heavier_below}};
    }
    // The flow scales with the supply pressure through the linear circuit, so a raised hold
    // pressure speeds up what the contacts may see.
    const double pressure_ratio = std::max(1.0, js.protocol.hold_pressure / js.flow.supply_pressure);
    const double throat_speed =
        pressure_ratio * (v.is_slot() ? SlotValveFlow(v.slot(), js.flow.bore_speed).plug_speed(0.0)
                                      : js.flow.bore_speed * std::pow(rb / v.throat_radius(), 2));
    json flow_json = {
        {"type", "valve"}, {"valve", valve_si}, {"bore_speed", js.flow.bore_speed}, {"profile", in.profile}};
    if (in.profile == "converging") flow_json["jet_length"] = js.flow.jet_length;
    const json output_json = engine_output_json(in.output);
    // Rolling resistance (EPSD, as the source's chapter 2) and cohesion (SJKR) only when asked for.
    json contact_json = {{"model", "hertz_mindlin"}};
    if (in.material["rolling_friction"].get<double>() > 0) contact_json["rolling"] = "epsd";
    if (in.material["cohesion_energy_density"].get<double>() > 0) contact_json["cohesion"] = "sjkr";
    json magnetic_json = {{"field", in.field}};
    if (in.cutoff_diameters > 0) magnetic_json["cutoff"] = {{"diameters", in.cutoff_diameters}};
    if (in.magnetic_update_interval > 1) magnetic_json["update_interval"] = in.magnetic_update_interval;
    if (in.close_pairs_min_gap > 0)
        magnetic_json["close_pairs"] = {{"model", "linear"}, {"min_gap", in.close_pairs_min_gap}};
    if (in.close_pairs_saturating) magnetic_json["close_pairs"] = {{"model", "saturating"}};
    json run_json = {{"timestep", "auto"}, {"characteristic_speed", std::max(throat_speed, 0.1)}};
    if (in.neighbour_skin > 0) run_json["skin"] = in.neighbour_skin;
    json fluid_json = {{"viscosity", in.viscosity}, {"flow", flow_json}};
    if (in.flow_lookup_interval > 1) fluid_json["lookup_interval"] = in.flow_lookup_interval;
    return {{"description", "mrjam jam: generated from the jam scene"},
            {"seed", in.seed},
            {"domain", {{"lo", vec(-hx, -rb, -d_up)}, {"hi", vec(hx, rb, d_down)}, {"periodic", "z"}}},
            {"materials", materials},
            {"material_pairs", material_pairs},
            {"contact", contact_json},
            {"fluid", fluid_json},
            {"walls", walls},
            {"grains", batches},
            {"magnetic", magnetic_json},
            {"run", run_json},
            {"stages", jam_stages(js.protocol)},
            {"output", output_json}};
}

}  // namespace mrjam
