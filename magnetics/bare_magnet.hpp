#pragma once
// Verification model: one uniformly magnetised cuboid magnet alone in air, meshed and solved by
// the same gmsh + GetDP pipeline as the valve, so its field can be checked against the closed
// form (magnetics/cuboid_field.hpp). Used by the test suite and `mrjam-bench magnetics`.
#include <filesystem>
#include <vector>

#include "magnetics/cuboid_field.hpp"
#include "magnetics/getdp_problem.hpp"

namespace mrjam::magnetics {

struct BareMagnetMesh {
    double magnet_size = 0.2e-3;  // elements in and around the magnet
    double far_size = 4e-3;       // at the air box
    double air_box = 40e-3;       // cube side
};

struct BareMagnetSolution {
    std::vector<std::vector<Vec3>> lines;  // B at the requested points, per line
    std::size_t elements = 0;
    int unknowns = 0;
    double seconds = 0;
};

// The magnet's recoil permeability is 1 so the closed form (which assumes mu = mu0 everywhere)
// is the exact answer the mesh must converge to.
BareMagnetSolution solve_bare_magnet(const Cuboid& magnet, const BareMagnetMesh& mesh,
                                     const std::vector<LineRequest>& lines, const std::filesystem::path& work_dir);

}  // namespace mrjam::magnetics
