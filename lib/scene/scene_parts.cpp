#include "scene/scene_parts.hpp"

#include <algorithm>
#include <cmath>

#include "fluid/slot_valve_flow.hpp"
#include "fluid/valve_flow.hpp"

namespace mrjam {

int read_axis(SceneNode& node, const std::string& key, std::optional<std::string> fallback) {
    const std::string a = node.choice(key, {"x", "y", "z"}, fallback);
    return a[0] - 'x';
}

Region read_region(SceneNode node, const Domain& domain) {
    const std::string shape = node.choice("shape", {"box", "cylinder"}, "box");
    Region region;
    if (shape == "box") {
        const Vec3 lo = node.vector("lo", units::length, domain.lo);
        const Vec3 hi = node.vector("hi", units::length, domain.hi);
        for (int k = 0; k < 3; ++k)
            if (!(hi[k] > lo[k])) node.fail("hi", "each component must exceed the matching component of lo");
        region = Region::box(lo, hi);
    } else {
        const int axis = read_axis(node, "axis", "z");
        const Vec3 base = node.vector("base", units::length, std::nullopt);
        const double radius = node.quantity("radius", units::length, std::nullopt, Bounds::positive());
        const double length = node.quantity("length", units::length, std::nullopt, Bounds::positive());
        region = Region::cylinder(base, axis, radius, length);
    }
    node.finish();
    return region;
}

SizeDistribution read_size_distribution(SceneNode node) {
    const std::string kind = node.choice("distribution", {"single", "lognormal", "table"}, "single");
    SizeDistribution result = SizeDistribution::single(1);
    if (kind == "single") {
        result = SizeDistribution::single(node.quantity("diameter", units::length, std::nullopt, Bounds::positive()));
    } else if (kind == "lognormal") {
        const double median = node.quantity("median_diameter", units::length, std::nullopt, Bounds::positive());
        const double sigma = node.number("sigma_ln", std::nullopt, Bounds::positive());
        const double dmin =
            node.quantity("min_diameter", units::length, median * std::exp(-3 * sigma), Bounds::positive());
        const double dmax =
            node.quantity("max_diameter", units::length, median * std::exp(3 * sigma), Bounds::positive());
        // Name the key the user wrote: a min_diameter above the defaulted max_diameter is the min's fault.
        if (!(dmax > dmin) && !node.has("max_diameter"))
            node.fail("min_diameter",
                      "must be below max_diameter, which defaults to median_diameter e^(3 sigma_ln) = " +
                          format_number(dmax) + " m; lower it or give max_diameter");
        if (!(dmax > dmin)) node.fail("max_diameter", "must exceed min_diameter");
        result = SizeDistribution::lognormal(median, sigma, dmin, dmax);
    } else {
        const auto diameters = node.quantity_list("diameters", units::length, Bounds::positive());
        const auto frequencies = node.quantity_list("frequencies", units::dimensionless, Bounds::non_negative());
        if (diameters.size() != frequencies.size())
            node.fail("frequencies", "needs one entry per diameter (" + std::to_string(diameters.size()) + ")");
        const std::string basis = node.choice("basis", {"number", "volume"}, "number");
        try {
            result = SizeDistribution::table(diameters, frequencies,
                                             basis == "number" ? SizeDistribution::FrequencyBasis::number
                                                               : SizeDistribution::FrequencyBasis::volume);
        } catch (const std::invalid_argument& e) {
            node.fail("frequencies", e.what());
        }
    }
    node.finish();
    return result;
}

std::shared_ptr<FlowField> read_flow(SceneNode node, const Domain& domain) {
    const std::string type = node.choice("type", {"still", "uniform", "couette", "axial", "valve"}, "still");
    std::shared_ptr<FlowField> flow;
    if (type == "still") {
        flow = std::make_shared<StillFlow>();
    } else if (type == "valve") {
        // The source's profile through the valve (fluid/valve_flow.hpp): `bore_speed` inside the
        // constriction's diameter in the bore, raised by the area ratio inside the constriction.
        const ValveGeometry valve = read_valve(node.object("valve"));
        const double speed = node.quantity("bore_speed", units::velocity, 0.273, Bounds::non_negative());
        if (valve.is_slot()) {
            // The slot's profile is the conserving reading only (fluid/slot_valve_flow.hpp).
            if (node.choice("profile", valve_flow_profile_names(), "conserving") != "conserving")
                node.fail("profile", "a slot orifice has the conserving profile only; use \"conserving\"");
            flow = std::make_shared<SlotValveFlow>(valve.slot(), speed);
        } else {
            const std::string name = node.choice("profile", valve_flow_profile_names(), "source");
            double jet = 0;
            if (name == "converging") {
                jet = node.quantity("jet_length", units::length, valve.taper_length, Bounds::positive());
                // The domain's periodic seam (if along z) must see the bore's profile on both sides.
                if (valve.throat_end_z() + jet > valve.downstream_length * (1 + 1e-12))
                    node.fail("jet_length",
                              "the stream must re-open to the bore before the modelled tube ends (at most " +
                                  format_number((valve.downstream_length - valve.throat_end_z()) * 1e3) +
                                  " mm here); shorten it or lengthen valve/downstream_length");
            }
            flow = std::make_shared<ValveFlow>(valve, speed, valve_flow_profile(name), jet);
        }
    } else if (type == "uniform") {
        flow = std::make_shared<UniformFlow>(node.vector("velocity", units::velocity, std::nullopt));
    } else if (type == "couette") {
        const int axis = read_axis(node, "gradient_axis", "z");
        const double lower = node.quantity("lower", units::length, domain.lo[axis]);
        const double upper = node.quantity("upper", units::length, domain.hi[axis]);
        if (!(upper > lower)) node.fail("upper", "must lie above 'lower' along the gradient axis");
        const Vec3 vl = node.vector("lower_velocity", units::velocity, std::nullopt);
        const Vec3 vu = node.vector("upper_velocity", units::velocity, std::nullopt);
        flow = std::make_shared<CouetteFlow>(axis, lower, upper, vl, vu);
    } else {
        const int axis = read_axis(node, "axis", "z");
        Vec3 centre_default = (domain.lo + domain.hi) * 0.5;
        const Vec3 centre = node.vector("centre", units::length, centre_default);
        const bool parabolic = node.choice("shape", {"parabolic", "plug"}, "parabolic") == "parabolic";
        std::vector<AxialFlow::Station> stations;
        if (node.has("stations")) {
            for (auto st : node.objects("stations", true)) {
                AxialFlow::Station s;
                s.position = st.quantity("position", units::length, std::nullopt);
                s.centreline_speed = st.quantity("centreline_speed", units::velocity, std::nullopt);
                s.radius = st.quantity("radius", units::length, std::nullopt, Bounds::positive());
                st.finish();
                stations.push_back(s);
            }
            if (stations.empty()) node.fail("stations", "needs at least one station");
        } else {
            AxialFlow::Station s;
            s.position = 0;
            s.centreline_speed = node.quantity("centreline_speed", units::velocity, std::nullopt);
            s.radius = node.quantity("radius", units::length, std::nullopt, Bounds::positive());
            stations.push_back(s);
        }
        flow = std::make_shared<AxialFlow>(axis, centre, stations, parabolic);
    }
    node.finish();
    return flow;
}

std::uint16_t material_index(SceneNode& node, const std::string& key, const std::vector<std::string>& names,
                             std::optional<std::string> fallback) {
    const std::string name = node.choice(key, names, fallback);
    for (std::size_t m = 0; m < names.size(); ++m)
        if (names[m] == name) return static_cast<std::uint16_t>(m);
    return 0;
}

Wall read_wall(SceneNode node, const std::vector<std::string>& material_names) {
    Wall w;
    w.name = node.text("name", std::nullopt);
    const std::string type = node.choice("type", {"plane", "cylinder", "passage"}, std::nullopt);
    w.material = material_index(node, "material", material_names, material_names.front());
    w.velocity = node.vector("velocity", units::velocity, Vec3{});
    if (type == "passage") {
        // The valve's bore and constriction about the z axis (geometry/valve.hpp frame), extended
        // past the modelled length so periodic images never meet its ends.
        const ValveGeometry valve = read_valve(node.object("valve"));
        const std::string name = w.name;
        const auto material = w.material;
        w = passage_wall(name, valve, valve.upstream_length + valve.downstream_length);
        w.material = material;
    } else if (type == "plane") {
        w.kind = Wall::Kind::plane;
        w.point = node.vector("point", units::length, std::nullopt);
        const Vec3 n = node.vector("normal", units::dimensionless, std::nullopt);
        if (norm(n) == 0) node.fail("normal", "must be a non-zero vector pointing towards the grains");
        w.normal = n / norm(n);
    } else {
        w.kind = Wall::Kind::cylinder;
        w.point = node.vector("point", units::length, std::nullopt);
        const Vec3 a = node.vector("axis", units::dimensionless, Vec3{0, 0, 1});
        if (norm(a) == 0) node.fail("axis", "must be a non-zero vector");
        w.axis = a / norm(a);
        w.radius = node.quantity("radius", units::length, std::nullopt, Bounds::positive());
        w.inside = node.boolean("inside", true);
    }
    node.finish();
    return w;
}

ValveGeometry read_valve(SceneNode node) {
    ValveGeometry v;
    const auto L = units::length;
    v.tube_inner_diameter = node.quantity("tube_inner_diameter", L, v.tube_inner_diameter, Bounds::positive());
    v.wall_thickness = node.quantity("wall_thickness", L, v.wall_thickness, Bounds::any());
    if (node.has("constriction") && node.has("constriction_diameter"))
        node.fail("constriction", "give either a preset name (constriction) or constriction_diameter, not both");
    if (node.has("constriction")) {
        // A size given to the preset key ("1 mm") belongs to constriction_diameter: say so.
        const json& given = node.raw("constriction");
        const auto presets = constriction_preset_names();
        if (given.is_string() && std::find(presets.begin(), presets.end(), given.get<std::string>()) == presets.end() &&
            given.get<std::string>().find_first_of("0123456789") != std::string::npos &&
            given.get<std::string>().back() != 'x')
            node.fail("constriction", "takes a preset (20x, 30x or 40x); give a size such as \"" +
                                          given.get<std::string>() + "\" as constriction_diameter instead");
        v.constriction_diameter = constriction_preset(node.choice("constriction", presets, std::nullopt));
    } else
        v.constriction_diameter = node.quantity("constriction_diameter", L, v.constriction_diameter, Bounds::any());
    v.orifice = node.choice("orifice", {"circular", "slot"}, "circular") == "slot" ? Orifice::slot : Orifice::circular;
    if (node.has("slot_width") || v.is_slot()) v.slot_width = node.quantity("slot_width", L, 0.0, Bounds::any());
    v.taper_length = node.quantity("taper_length", L, v.taper_length, Bounds::any());
    v.throat_length = node.quantity("throat_length", L, v.throat_length, Bounds::any());
    v.upstream_length = node.quantity("upstream_length", L, v.upstream_length, Bounds::any());
    v.downstream_length = node.quantity("downstream_length", L, v.downstream_length, Bounds::any());
    node.finish();
    const auto problems = v.problems();
    if (!problems.empty()) {
        const std::string& first = problems.front();
        const auto colon = first.find(": ");
        throw SceneError(node.path() + "/" + first.substr(0, colon), first.substr(colon + 2));
    }
    return v;
}

}  // namespace mrjam
