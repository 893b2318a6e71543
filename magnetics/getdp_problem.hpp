#pragma once
// A magnetostatic problem for GetDP in the total magnetic scalar potential phi:
//     H = -grad phi,   B = mu0 mu_r H + B_r,   div B = 0,   phi = 0 on the air box.
// No gauge is needed and the system is symmetric positive definite, so conjugate gradients
// with an incomplete Cholesky preconditioner solve it in seconds; second-order hierarchical
// elements make volume means converge fast. Soft iron may follow a Frohlich-Kennelly
// saturation curve, solved by Newton iteration.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/vec3.hpp"
#include "magnetics/element_sampler.hpp"

namespace mrjam::magnetics {

struct RegionMaterial {
    int region = 0;
    std::string name;                  // GetDP group name (letters only)
    double relative_permeability = 1;  // recoil permeability for magnets
    Vec3 remanence{0, 0, 0};           // B_r, tesla
    bool saturating = false;           // Frohlich-Kennelly: mu(H) = mu0 + J_s / (H_k + |H|)
    double saturation = 2.0;           // J_s, tesla
};

struct LineRequest {
    Vec3 from, to;
    int points = 2;
};

struct ProblemRequest {
    int dimension = 3;
    // 2D only: the mesh's x is the radius and y the axis of a body of revolution (GetDP's VolAxi).
    bool axisymmetric = false;
    // The uniform field the truncation boundary imposes, phi = -H0 . x there (A/m); zero for a
    // device that makes its own field.
    Vec3 applied_field{0, 0, 0};
    std::vector<RegionMaterial> regions;  // every meshed region (air included)
    int boundary_region = 0;
    std::vector<int> measured_regions;  // volume, mean |B|, mean |B|^2, max |B| reported for each
    std::vector<int> sampled_regions;   // B exported per element, to sample anywhere in them
    bool section = false;               // |B| on the plane z = 0 (3D: a cut; 2D: the whole mesh)
    std::vector<LineRequest> lines;
    double solver_tolerance = 1e-10;  // relative residual of CG
    // LU instead of CG: for small 2D problems whose saturated iron leaves CG with incomplete
    // Cholesky stalling (the sphere pair deep in saturation).
    bool direct_solver = false;
    int nonlinear_iterations = 40;
    double nonlinear_tolerance = 1e-5;
};

struct RegionField {
    int region = 0;
    double volume = 0;          // m^3 (m^2 per metre of depth in 2D)
    double mean_b = 0;          // volume mean of |B|, tesla
    double mean_b_squared = 0;  // volume mean of |B|^2
    double max_b = 0;           // largest |B| at the element nodes of the region
};

struct Solution {
    std::vector<RegionField> fields;
    ElementField sampled;                        // B on the sampled regions' elements
    ElementField section;                        // |B| (in x) on triangles of the plane z = 0
    std::vector<std::vector<Vec3>> line_values;  // per line request
    int unknowns = 0;
    int solver_iterations = 0;      // CG iterations (last linear solve)
    int nonlinear_steps = 0;        // Newton steps (0 for a linear problem)
    double nonlinear_residual = 0;  // GetDP's last relative nonlinear residual
    double seconds = 0;
    const RegionField& field(int region) const;
};

// The failure of the solver: the message carries GetDP's own words and the log path.
class SolverError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The .pro text (exposed for inspection and tests).
std::string getdp_problem_text(const ProblemRequest&);

// Writes the problem next to the mesh in `work_dir`, runs getdp, reads the results. Throws
// SolverError if getdp is missing, fails or does not converge.
Solution solve_with_getdp(const ProblemRequest&, const std::filesystem::path& work_dir,
                          const std::filesystem::path& mesh_file);

// Where getdp is (PATH lookup); empty if it is not installed.
std::string find_getdp();

}  // namespace mrjam::magnetics
