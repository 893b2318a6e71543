#include "magnetics/bare_magnet.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "magnetics/gmsh_api.hpp"
#include "magnetics/gmsh_assembly.hpp"

namespace mrjam::magnetics {

BareMagnetSolution solve_bare_magnet(const Cuboid& magnet, const BareMagnetMesh& mesh,
                                     const std::vector<LineRequest>& lines, const std::filesystem::path& work_dir) {
    const auto start = std::chrono::steady_clock::now();
    constexpr int kMagnet = 1, kAir = 2, kBoundary = 10;
    std::filesystem::create_directories(work_dir);
    const auto mesh_file = work_dir / "magnet.msh";
    BareMagnetSolution out;
    try {
        GmshSession session("bare_magnet");
        const Vec3 lo = magnet.centre - 0.5 * magnet.size;
        const int box = gmsh::model::occ::addBox(lo.x, lo.y, lo.z, magnet.size.x, magnet.size.y, magnet.size.z);
        MeshRequest request;
        request.dimension = 3;
        const double h = 0.5 * mesh.air_box;
        request.air_lo = magnet.centre - Vec3{h, h, h};
        request.air_hi = magnet.centre + Vec3{h, h, h};
        request.far_size = mesh.far_size;
        request.air_region = kAir;
        request.boundary_region = kBoundary;
        // Fine in and just around the magnet, where the field varies on the magnet's own scale;
        // growing to the far size over a few magnet lengths.
        const Vec3 pad{mesh.magnet_size * 3, mesh.magnet_size * 3, mesh.magnet_size * 3};
        const double grow = 4.0 * std::max({magnet.size.x, magnet.size.y, magnet.size.z});
        request.refinements.push_back({lo - pad, lo + magnet.size + pad, mesh.magnet_size, grow});
        out.elements = mesh_assembly({{kMagnet, {{3, box}}}}, request, mesh_file).elements;
    } catch (const gmsh::GmshError& e) {
        throw std::runtime_error(std::string("gmsh failed: ") + e.what());
    }
    ProblemRequest problem;
    problem.dimension = 3;
    problem.regions = {{kMagnet, "Magnet", 1.0, magnet.remanence_T}, {kAir, "Air", 1.0, {0, 0, 0}}};
    problem.boundary_region = kBoundary;
    problem.lines = lines;
    const Solution s = solve_with_getdp(problem, work_dir, mesh_file);
    out.lines = s.line_values;
    out.unknowns = s.unknowns;
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace mrjam::magnetics
