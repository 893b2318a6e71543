#include "magnetics/bare_magnet.hpp"

#include <chrono>

#include <gmsh.h>

#include "magnetics/gmsh_assembly.hpp"

namespace mrjam::magnetics {

BareMagnetSolution solve_bare_magnet(const Cuboid& magnet, const BareMagnetMesh& mesh,
                                     const std::vector<LineRequest>& lines, const std::filesystem::path& work_dir) {
    const auto start = std::chrono::steady_clock::now();
    constexpr int kMagnet = 1, kAir = 2, kBoundary = 10;
    std::filesystem::create_directories(work_dir);
    const auto mesh_file = work_dir / "magnet.msh";
    BareMagnetSolution out;
    {
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
        // Fine around the magnet and over the probe lines' neighbourhood (two magnet sizes).
        const Vec3 pad = 2.0 * magnet.size;
        request.refinements.push_back({lo - pad, lo + magnet.size + pad, mesh.magnet_size, 0.25 * mesh.air_box});
        out.elements = mesh_assembly({{kMagnet, {{3, box}}}}, request, mesh_file).elements;
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
