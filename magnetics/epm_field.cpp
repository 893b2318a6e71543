#include "magnetics/epm_field.hpp"

#include <cmath>
#include <stdexcept>

#include "core/format.hpp"
#include "magnetics/getdp_problem.hpp"
#include "magnetics/gmsh_api.hpp"
#include "magnetics/magnetic_circuit.hpp"

namespace mrjam::magnetics {

std::string field_model_name(FieldModel m) {
    switch (m) {
        case FieldModel::circuit:
            return "circuit";
        case FieldModel::planar_2d:
            return "2d";
        case FieldModel::full_3d:
            return "3d";
    }
    return "?";
}

namespace {

std::vector<RegionMaterial> epm_materials(const EpmModel& m, int dim) {
    const auto& mg = m.magnets;
    const auto& mat = m.materials;
    std::vector<RegionMaterial> r;
    if (dim == 3) {
        r.push_back({region::alnico,
                     "Alnico",
                     mg.alnico.recoil_permeability,
                     {0, mg.alnico_polarity * mg.alnico.remanence, 0}});
        r.push_back({region::ndfeb, "NdFeB", mg.ndfeb.recoil_permeability, {0, mg.ndfeb.remanence, 0}});
    } else {
        // The planar model cannot hold two magnets side by side in z: it uses their average over
        // the bracket width (remanence and permeability weighted by the share of the width each
        // magnet fills; the spacing and the overhang count as air).
        const double share = mg.depth / m.bracket.width;
        const double remanence = share * (mg.alnico_polarity * mg.alnico.remanence + mg.ndfeb.remanence);
        const double mu = share * (mg.alnico.recoil_permeability + mg.ndfeb.recoil_permeability) + (1.0 - 2.0 * share);
        r.push_back({region::magnet_pair, "MagnetPair", mu, {0, remanence, 0}});
    }
    RegionMaterial iron{region::iron, "Iron", mat.iron_relative_permeability, {0, 0, 0}};
    iron.saturating = mat.iron_nonlinear;
    iron.saturation = mat.iron_saturation;
    r.push_back(iron);
    r.push_back({region::fluid_active, "FluidActive", mat.fluid_relative_permeability, {0, 0, 0}});
    if (dim == 3) r.push_back({region::fluid_passive, "FluidPassive", mat.fluid_relative_permeability, {0, 0, 0}});
    r.push_back({region::inactive_air, "InactiveAir", 1.0, {0, 0, 0}});
    r.push_back({region::valve_body, "ValveBody", 1.0, {0, 0, 0}});
    r.push_back({region::air, "Air", 1.0, {0, 0, 0}});
    return r;
}

int nodes_for(double length, double spacing) {
    return std::max(2, static_cast<int>(std::lround(length / spacing)) + 1);
}

FieldGrid empty_grid(Vec3 lo, Vec3 hi, std::array<int, 3> count) {
    FieldGrid f;
    f.count = count;
    f.origin = lo;
    auto step = [](double a, double b, int n) { return n > 1 ? (b - a) / (n - 1) : 0.0; };
    f.spacing = Vec3{step(lo.x, hi.x, count[0]), step(lo.y, hi.y, count[1]), step(lo.z, hi.z, count[2])};
    f.values.assign(static_cast<std::size_t>(count[0]) * count[1] * count[2], Vec3{0, 0, 0});
    return f;
}

template <class Fn>
void for_each_node(FieldGrid& f, Fn fn) {
    std::size_t n = 0;
    for (int k = 0; k < f.count[2]; ++k)
        for (int j = 0; j < f.count[1]; ++j)
            for (int i = 0; i < f.count[0]; ++i, ++n)
                fn(Vec3{f.origin.x + i * f.spacing.x, f.origin.y + j * f.spacing.y, f.origin.z + k * f.spacing.z},
                   f.values[n]);
}

// B over the bore's bounding box (the whole modelled tube length in 3D, the section in 2D),
// from the fluid's own elements only. The grains live in the fluid, and the map is interpolated
// trilinearly: a node inside the valve body or an iron insert would carry that solid's field
// into the cells next to the wall (B's tangential part jumps by the permeability ratio there, 10
// from fluid to plastic, and an insert's iron holds a few tesla), which is a spurious gradient
// force on every grain within one node spacing of the wall. A node outside the fluid takes the
// fluid's value where the ray from it to the axis enters the fluid: the field at the wall, held
// constant outwards.
FieldGrid fluid_map(const EpmModel& m, int dim, double spacing, const ElementSampler& fluid) {
    const double rb = m.valve.bore_radius();
    const int n = nodes_for(2 * rb, spacing);
    const double z0 = dim == 3 ? -m.valve.upstream_length : 0.0, z1 = dim == 3 ? m.valve.downstream_length : 0.0;
    FieldGrid f = empty_grid({-rb, -rb, z0}, {rb, rb, z1}, {n, n, dim == 3 ? nodes_for(z1 - z0, spacing) : 1});
    constexpr int kRaySteps = 400;  // steps of r / 400 inwards: the wall is found to 0.25 % of r
    for_each_node(f, [&](const Vec3& x, Vec3& value) {
        auto b = fluid.sample(x);
        for (int step = 1; !b && step <= kRaySteps; ++step) {
            const double shrink = 1.0 - static_cast<double>(step) / kRaySteps;
            b = fluid.sample({x.x * shrink, x.y * shrink, x.z});
        }
        if (!b)
            throw std::runtime_error("field map node (" + format_number(x.x * 1e3) + ", " + format_number(x.y * 1e3) +
                                     ", " + format_number(x.z * 1e3) + ") mm: no fluid element on its ray to the axis");
        value = *b;
    });
    return f;
}

// |B| (in x) on the cross-section z = 0 over the device; NaN outside the cut.
FieldGrid picture_map(const EpmModel& m, int pixels, const ElementSampler& section) {
    const EpmLayout layout = epm_layout(m);
    const double pad = 0.5e-3;
    const Vec3 lo{layout.device_lo.x - pad, layout.device_lo.y - pad, 0.0};
    const double spacing = (layout.device_hi.x + pad - lo.x) / (pixels - 1);
    const int ny = nodes_for(layout.device_hi.y + pad - lo.y, spacing);
    FieldGrid f = empty_grid(lo, {lo.x + (pixels - 1) * spacing, lo.y + (ny - 1) * spacing, 0.0}, {pixels, ny, 1});
    for_each_node(f, [&](const Vec3& x, Vec3& value) {
        const auto b = section.sample(x);
        value = {b ? b->x : std::nan(""), 0, 0};
    });
    return f;
}

// A planar model is invariant along z: its map is the section repeated at the two ends of the
// modelled tube, so the engine can read it like a 3D map.
FieldGrid extrude_planar(FieldGrid section, const ValveGeometry& v) {
    const std::size_t layer = section.values.size();
    section.values.resize(2 * layer);
    std::copy(section.values.begin(), section.values.begin() + static_cast<std::ptrdiff_t>(layer),
              section.values.begin() + static_cast<std::ptrdiff_t>(layer));
    section.count[2] = 2;
    section.origin.z = -v.upstream_length;
    section.spacing.z = v.upstream_length + v.downstream_length;
    return section;
}

}  // namespace

EpmField compute_epm_field(const EpmFieldRequest& request) {
    const EpmModel& m = request.model;
    if (request.field_model == FieldModel::circuit) return circuit_field(m);
    const int dim = request.field_model == FieldModel::full_3d ? 3 : 2;
    // A fresh directory: an earlier solve's result files must not be read as this one's if
    // GetDP writes none (it can exit 0 on some failures).
    std::filesystem::remove_all(request.work_dir);
    std::filesystem::create_directories(request.work_dir);
    const auto mesh_file = request.work_dir / "epm.msh";

    EpmField out;
    out.field_model = request.field_model;
    try {
        GmshSession session("epm");
        const auto pieces = add_epm_pieces(m, dim);
        const MeshSummary mesh = mesh_assembly(pieces, epm_mesh_request(m, dim, request.mesh), mesh_file);
        out.mesh_nodes = mesh.nodes;
        out.mesh_elements = mesh.elements;
        out.mesh_seconds = mesh.seconds;
    } catch (const gmsh::GmshError& e) {
        throw std::runtime_error(std::string("gmsh failed: ") + e.what() + " (set MRJAM_GMSH_VERBOSE=1 for its log)");
    }

    ProblemRequest problem;
    problem.dimension = dim;
    problem.regions = epm_materials(m, dim);
    problem.boundary_region = region::boundary;
    problem.measured_regions = {region::fluid_active, region::inactive_air};
    // The field map is the fluid's field (fluid_map above).
    problem.sampled_regions = {region::fluid_active};
    if (dim == 3) problem.sampled_regions.push_back(region::fluid_passive);
    problem.section = request.picture_pixels > 1;
    const Solution s = solve_with_getdp(problem, request.work_dir, mesh_file);

    const RegionField& active = s.field(region::fluid_active);
    out.mean_b_active = active.mean_b;
    out.max_b_active = active.max_b;
    out.active_volume = active.volume;
    const double variance = std::max(0.0, active.mean_b_squared - active.mean_b * active.mean_b);
    out.uniformity = active.mean_b > 0 ? std::sqrt(variance) / active.mean_b : 0.0;
    out.mean_b_inactive = s.field(region::inactive_air).mean_b;
    out.unknowns = s.unknowns;
    out.solver_iterations = s.solver_iterations;
    out.solve_seconds = s.seconds;
    out.fluid_map = fluid_map(m, dim, request.map_spacing, ElementSampler(s.sampled));
    if (problem.section) out.picture = picture_map(m, request.picture_pixels, ElementSampler(s.section));

    const double half_width = 0.5 * m.bracket.width;
    const ValveGeometry& valve = m.valve;
    auto in_active = [&](const Vec3& x) {
        if (dim == 2) return x.x * x.x + x.y * x.y < valve.bore_radius() * valve.bore_radius();
        return std::abs(x.z) <= half_width && valve.in_fluid(x);
    };
    const auto [mean_gradient, max_gradient] = gradient_b2_statistics(out.fluid_map, in_active);
    out.gradient_b2_mean = mean_gradient;
    out.gradient_b2_max = max_gradient;
    if (dim == 2) {
        out.fluid_map = extrude_planar(out.fluid_map, valve);
        out.notes.push_back(
            "2d: planar section through the throat; the magnets are averaged over the bracket width, "
            "the fluid is the bore disc, the field is taken as invariant along the tube (no end leakage)");
    }
    return out;
}

}  // namespace mrjam::magnetics
