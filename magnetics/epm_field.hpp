#pragma once
// The field an EPM valve puts into its fluid, by one of three models of rising cost:
//   circuit  - a reluctance network (instant, no mesh; magnetics/magnetic_circuit.hpp)
//   2d       - planar finite elements on the x-y cross-section through the throat
//   3d       - finite elements on the full device (gmsh + GetDP)
// and the figures a designer asks for: mean and peak |B| in the active fluid, the stray field
// in the inactive gap, uniformity, the force-relevant gradient |grad |B|^2|.
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "magnetics/epm_geometry.hpp"
#include "magnetics/epm_model.hpp"

namespace mrjam::magnetics {

enum class FieldModel { circuit, planar_2d, full_3d };
std::string field_model_name(FieldModel);

// A regular grid of B (x fastest), in the engine's FieldMap layout.
struct FieldGrid {
    std::array<int, 3> count{};
    Vec3 origin, spacing;
    std::vector<Vec3> values;
};

struct EpmFieldRequest {
    EpmModel model;
    FieldModel field_model = FieldModel::full_3d;
    MeshSettings mesh;
    double map_spacing = 0.1e-3;     // field-map node spacing over the fluid
    int picture_pixels = 160;        // mid-plane picture width in grid nodes (0: none)
    std::filesystem::path work_dir;  // mesh, problem and GetDP output (scratch)
};

struct EpmField {
    FieldModel field_model = FieldModel::full_3d;
    double mean_b_active = 0;     // T, volume mean of |B| over the active fluid
    double max_b_active = 0;      // T, largest nodal |B| in the active fluid
    double mean_b_inactive = 0;   // T, volume mean of |B| over the inactive air gap
    double uniformity = 0;        // coefficient of variation of |B| over the active fluid
    double gradient_b2_mean = 0;  // T^2/m, mean of |grad |B|^2| over the active fluid grid nodes
    double gradient_b2_max = 0;   // T^2/m, its largest value there
    double active_volume = 0;     // m^3 (m^2 in 2D and in the circuit: the report's active_fluid_area_m2)
    std::size_t mesh_nodes = 0, mesh_elements = 0;
    int unknowns = 0, solver_iterations = 0;
    double mesh_seconds = 0, solve_seconds = 0;
    FieldGrid fluid_map;             // over the fluid's bounding box (FEM models only)
    FieldGrid picture;               // |B| picture plane z = 0 (FEM models only)
    std::vector<std::string> notes;  // what the model assumed, for the report
};

EpmField compute_epm_field(const EpmFieldRequest&);

// Gradient statistics of |B|^2 over the grid nodes for which `inside` holds (central
// differences in the interior, one-sided at the grid's faces).
template <class Inside>
std::pair<double, double> gradient_b2_statistics(const FieldGrid& grid, Inside inside);

}  // namespace mrjam::magnetics

#include "magnetics/epm_field_gradient.ipp"
