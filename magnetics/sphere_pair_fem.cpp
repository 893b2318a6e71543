#include "magnetics/sphere_pair_fem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/format.hpp"
#include "magnetics/getdp_problem.hpp"
#include "magnetics/gmsh_api.hpp"
#include "magnetics/gmsh_assembly.hpp"

namespace mrjam::magnetics {

namespace fs = std::filesystem;

namespace {

constexpr double kMu0 = 4e-7 * std::numbers::pi;
constexpr int kIron = 1, kFluid = 2, kBoundary = 3;

// Full precision for gmsh's expressions.
std::string num(double v) { return format_number(v, 17); }

// Element sizes (lengths in radii): in the gap a third of its local height (gap + r^2 between
// two unit spheres), growing with the height above the mid-plane; on the sphere's surface 1/40
// growing by 0.08 of the distance from it (the far dipole field, whose moment is read there); the far field at most a
// tenth of the truncation radius.
void set_mesh_sizes(const SpherePairFemRequest& r, double centre) {
    namespace field = gmsh::model::mesh::field;
    const double k = 1.0 / r.refinement;
    const int gap = field::add("MathEval");
    field::setString(gap, "F", num(k / 3) + " * (" + num(r.gap) + " + x * x) + " + num(0.3 * k) + " * y");
    const int surface = field::add("MathEval");
    field::setString(surface, "F",
                     num(k / 40) + " + " + num(0.08 * k) + " * Fabs(Sqrt(x * x + (y - " + num(centre) + ") * (y - " +
                         num(centre) + ")) - 1)");
    const int smallest = field::add("Min");
    field::setNumbers(smallest, "FieldsList", {double(gap), double(surface)});
    field::setAsBackgroundMesh(smallest);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeMax", r.outer_radius / 10);
    gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
    gmsh::option::setNumber("General.NumThreads", 1);
}

// The quarter disk r, z >= 0 of the truncation radius, with the upper sphere's half disk cut in
// as its own region; the Dirichlet boundary is the arc and the mid-plane, not the axis.
void mesh_pair(const SpherePairFemRequest& r, const fs::path& mesh_file) {
    namespace occ = gmsh::model::occ;
    GmshSession session("sphere_pair");
    const double far = r.outer_radius, centre = 1 + r.gap / 2;
    DimTags quarter, half, out;
    std::vector<DimTags> map;
    occ::intersect({{2, occ::addDisk(0, 0, 0, far, far)}}, {{2, occ::addRectangle(0, 0, 0, far, far)}}, quarter, map);
    occ::intersect({{2, occ::addDisk(0, centre, 0, 1, 1)}}, {{2, occ::addRectangle(0, centre - 1, 0, 1, 2)}}, half,
                   map);
    occ::fragment(quarter, half, out, map);
    occ::synchronize();
    std::vector<int> iron, fluid;
    for (const auto& [d, tag] : map[1]) iron.push_back(tag);
    DimTags surfaces;
    gmsh::model::getEntities(surfaces, 2);
    for (const auto& [d, tag] : surfaces)
        if (std::find(iron.begin(), iron.end(), tag) == iron.end()) fluid.push_back(tag);
    if (iron.empty() || fluid.empty()) throw std::runtime_error("gmsh: the sphere pair's regions did not form");
    gmsh::model::addPhysicalGroup(2, iron, kIron);
    gmsh::model::addPhysicalGroup(2, fluid, kFluid);

    DimTags boundary;
    gmsh::model::getBoundary(surfaces, boundary, true, false, false);
    std::vector<int> dirichlet;
    for (const auto& [d, tag] : boundary) {
        double x0, y0, z0, x1, y1, z1;
        gmsh::model::getBoundingBox(1, std::abs(tag), x0, y0, z0, x1, y1, z1);
        if (x1 > 1e-9 * far) dirichlet.push_back(std::abs(tag));  // not on the axis x = 0
    }
    gmsh::model::addPhysicalGroup(1, dirichlet, kBoundary);
    set_mesh_sizes(r, centre);
    gmsh::model::mesh::generate(2);
    gmsh::write(mesh_file.string());
}

// Sample segments along the mid-plane, finer near the axis where the gap field peaks.
std::vector<LineRequest> mid_plane_segments(double far) {
    std::vector<LineRequest> lines;
    double from = 0;
    for (double to : {0.02, 0.2, 2.0, 20.0, 40.0, 100.0, 200.0, 2000.0, 20000.0}) {
        to = std::min(to, far * (1 - 1e-9));
        lines.push_back({{from, 0, 0}, {to, 0, 0}, 2001});
        from = to;
        if (to >= far * (1 - 1e-9)) break;
    }
    return lines;
}

// Two dipoles m at heights +-c give H_z - H0 = 2 m (3 c^2 / rho^2 - 1) / (4 pi rho^3) on the
// mid-plane (rho^2 = r^2 + c^2); averaged over the samples between 40 and 100 radii.
double far_field_polarisability(const std::vector<LineRequest>& lines, const std::vector<std::vector<Vec3>>& values,
                                const SpherePairFemRequest& r) {
    const double c = 1 + r.gap / 2;
    double sum = 0;
    int count = 0;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (!(lines[i].from.x >= 40 - 1e-9 && lines[i].to.x <= 100 + 1e-9)) continue;
        const double dr = (lines[i].to.x - lines[i].from.x) / (lines[i].points - 1);
        for (int k = 0; k < lines[i].points; ++k) {
            const double rho2 = std::pow(lines[i].from.x + k * dr, 2) + c * c, rho = std::sqrt(rho2);
            const double hz = values[i][k].y / (kMu0 * r.applied_field);
            // 2 m / (4 pi a^3 H0) with a = 1
            sum += (hz - 1) * rho2 * rho / (3 * c * c / rho2 - 1);
            ++count;
        }
    }
    if (count == 0) throw std::runtime_error("sphere pair FEM: no far-field samples (truncation radius below 100?)");
    return sum / count;
}

}  // namespace

SpherePairFemResult solve_sphere_pair_fem(const SpherePairFemRequest& r, const fs::path& work_dir) {
    if (!(r.gap > 0) || !(r.applied_field > 0) || !(r.relative_permeability > 1) || !(r.outer_radius > 200) ||
        !(r.refinement > 0))
        throw std::invalid_argument(
            "sphere pair FEM: gap, field, permeability - 1, refinement must be positive and "
            "the truncation radius above 200 radii (the moment is read at 40-100)");
    const auto start = std::chrono::steady_clock::now();
    fs::create_directories(work_dir);
    const fs::path mesh_file = work_dir / "pair.msh";
    mesh_pair(r, mesh_file);

    ProblemRequest p;
    p.dimension = 2;
    p.axisymmetric = true;
    p.applied_field = {0, r.applied_field, 0};
    RegionMaterial iron{kIron,     "Iron",       r.relative_permeability,
                        {0, 0, 0}, r.saturating, kMu0 * r.saturation_magnetisation};
    p.regions = {iron, {kFluid, "Fluid", 1.0, {0, 0, 0}, false, 0}};
    p.boundary_region = kBoundary;
    p.lines = mid_plane_segments(r.outer_radius);
    p.direct_solver = true;  // 20-35 thousand unknowns: LU in well under a second, where CG stalls in saturation
    p.nonlinear_iterations = 60;
    // GetDP's relative residual stalls at 1e-7 to 1.5e-6 (more in deeper saturation) after 3-5
    // quadratic Newton steps; 1e-5 is past the knee and changes the force by far less than the mesh.
    p.nonlinear_tolerance = 1e-5;
    const Solution s = solve_with_getdp(p, work_dir, mesh_file);

    // The trapezoid rule on each segment for -(1/2) integral (h_z^2 - h_r^2 - 1) 2 pi r dr, with
    // h = H / H0 (B / mu0 in the fluid): the force over mu0 H0^2 a^2.
    SpherePairFemResult out;
    double integral = 0;
    for (std::size_t i = 0; i < p.lines.size(); ++i) {
        const auto& line = p.lines[i];
        const auto& b = s.line_values[i];
        const double dr = (line.to.x - line.from.x) / (line.points - 1);
        for (int k = 0; k < line.points; ++k) {
            const double radius = line.from.x + k * dr;
            const double hz = b[k].y / (kMu0 * r.applied_field), hr = b[k].x / (kMu0 * r.applied_field);
            const double weight = (k == 0 || k == line.points - 1) ? 0.5 : 1.0;
            integral += weight * dr * (hz * hz - hr * hr - 1) * 2 * std::numbers::pi * radius;
            out.max_gap_flux_density = std::max(out.max_gap_flux_density, std::hypot(b[k].x, b[k].y));
        }
    }
    out.polarisability = far_field_polarisability(p.lines, s.line_values, r);
    // Beyond the truncation radius h_z - 1 = -alpha / r^3: the plane's remaining part of the
    // integral is -4 pi alpha / R_out.
    out.force_coefficient = -0.5 * (integral - 4 * std::numbers::pi * out.polarisability / r.outer_radius);
    out.unknowns = s.unknowns;
    out.newton_steps = s.nonlinear_steps;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace mrjam::magnetics
