#pragma once
// Meshing an assembly of solids with gmsh's C++ API (OpenCASCADE kernel). A model builder adds
// its pieces (each tagged with the region it belongs to) inside a GmshSession; mesh_assembly()
// embeds them in an air box, makes every interface conformal, names the regions as physical
// groups (the numbers the GetDP problem uses), grades the element size and writes the mesh.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam::magnetics {

using DimTags = std::vector<std::pair<int, int>>;

// gmsh keeps global state: one session at a time, finalised on every exit path.
class GmshSession {
public:
    explicit GmshSession(const std::string& model_name);
    ~GmshSession();
    GmshSession(const GmshSession&) = delete;
    GmshSession& operator=(const GmshSession&) = delete;
};

struct RegionPieces {
    int region = 0;  // physical group number
    DimTags pieces;  // OCC entities of the model's dimension, not overlapping other regions
};

// A box where elements are at most `size`, growing linearly to the far size over `thickness`.
struct Refinement {
    Vec3 lo, hi;
    double size = 0;
    double thickness = 0;
};

struct MeshRequest {
    int dimension = 3;       // 3: volumes; 2: planar cross-section in the x-y plane
    Vec3 air_lo, air_hi;     // the air box (the truncation boundary where phi = 0)
    double far_size = 2e-3;  // element size at the air box boundary
    std::vector<Refinement> refinements;
    int air_region = 0;       // physical number for the remaining air
    int boundary_region = 0;  // physical number for the air box boundary
};

struct MeshSummary {
    std::size_t nodes = 0;
    std::size_t elements = 0;  // tetrahedra (3D) or triangles (2D)
    double seconds = 0;
};

MeshSummary mesh_assembly(const std::vector<RegionPieces>& regions, const MeshRequest& request,
                          const std::filesystem::path& mesh_file);

}  // namespace mrjam::magnetics
