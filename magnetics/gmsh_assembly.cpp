#include "magnetics/gmsh_assembly.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <map>
#include <set>
#include <stdexcept>

#include "magnetics/gmsh_api.hpp"

namespace mrjam::magnetics {

GmshSession::GmshSession(const std::string& model_name) {
    // Gmsh may take over Ctrl-C; the caller's handling (mrjam's checkpoint-and-exit, or the
    // default) is put back so an interrupt during meshing is not swallowed.
    const auto on_int = std::signal(SIGINT, SIG_DFL), on_term = std::signal(SIGTERM, SIG_DFL);
    gmsh::initialize();
    std::signal(SIGINT, on_int);
    std::signal(SIGTERM, on_term);
    // MRJAM_GMSH_VERBOSE=1 shows gmsh's own log, for diagnosing a geometry that will not mesh.
    gmsh::option::setNumber("General.Terminal", std::getenv("MRJAM_GMSH_VERBOSE") ? 1 : 0);
    gmsh::option::setNumber("General.Verbosity", 2);
    gmsh::model::add(model_name);
}

GmshSession::~GmshSession() { gmsh::finalize(); }

namespace {

int add_refinement_field(const Refinement& r, double far_size) {
    const int f = gmsh::model::mesh::field::add("Box");
    gmsh::model::mesh::field::setNumber(f, "VIn", r.size);
    gmsh::model::mesh::field::setNumber(f, "VOut", far_size);
    gmsh::model::mesh::field::setNumber(f, "XMin", r.lo.x);
    gmsh::model::mesh::field::setNumber(f, "YMin", r.lo.y);
    gmsh::model::mesh::field::setNumber(f, "ZMin", r.lo.z);
    gmsh::model::mesh::field::setNumber(f, "XMax", r.hi.x);
    gmsh::model::mesh::field::setNumber(f, "YMax", r.hi.y);
    gmsh::model::mesh::field::setNumber(f, "ZMax", r.hi.z);
    gmsh::model::mesh::field::setNumber(f, "Thickness", r.thickness);
    return f;
}

std::size_t count_elements(int dimension) {
    std::vector<int> types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, dimension);
    std::size_t n = 0;
    for (const auto& t : tags) n += t.size();
    return n;
}

}  // namespace

MeshSummary mesh_assembly(const std::vector<RegionPieces>& regions, const MeshRequest& request,
                          const std::filesystem::path& mesh_file) {
    const auto start = std::chrono::steady_clock::now();
    const int dim = request.dimension;
    const Vec3 lo = request.air_lo, hi = request.air_hi;
    const int air = dim == 3 ? gmsh::model::occ::addBox(lo.x, lo.y, lo.z, hi.x - lo.x, hi.y - lo.y, hi.z - lo.z)
                             : gmsh::model::occ::addRectangle(lo.x, lo.y, 0.0, hi.x - lo.x, hi.y - lo.y);

    // Fragment the air box with every piece: interfaces become conformal. The map gives, per
    // input entity, the entities it became; the air box's list also holds the pieces inside it,
    // so the air proper is what no other region claims.
    DimTags tools;
    std::vector<std::size_t> owner;  // region index of each tool
    for (std::size_t r = 0; r < regions.size(); ++r)
        for (const auto& p : regions[r].pieces) {
            tools.push_back(p);
            owner.push_back(r);
        }
    DimTags out;
    std::vector<DimTags> map;
    gmsh::model::occ::fragment({{dim, air}}, tools, out, map);
    gmsh::model::occ::synchronize();

    std::map<std::size_t, std::set<int>> region_entities;
    std::set<int> claimed;
    for (std::size_t t = 0; t < tools.size(); ++t)
        for (const auto& [d, tag] : map[t + 1])
            if (d == dim) {
                region_entities[owner[t]].insert(tag);
                claimed.insert(tag);
            }
    std::vector<int> air_entities;
    for (const auto& [d, tag] : map[0])
        if (d == dim && !claimed.count(tag)) air_entities.push_back(tag);
    if (air_entities.empty()) throw std::runtime_error("gmsh: the device fills the whole air box; enlarge the air box");

    for (std::size_t r = 0; r < regions.size(); ++r) {
        const auto& ents = region_entities[r];
        if (ents.empty())
            throw std::runtime_error("gmsh: region " + std::to_string(regions[r].region) +
                                     " vanished in the boolean operations (degenerate geometry)");
        gmsh::model::addPhysicalGroup(dim, std::vector<int>(ents.begin(), ents.end()), regions[r].region);
    }
    gmsh::model::addPhysicalGroup(dim, air_entities, request.air_region);

    // The truncation boundary: the combined boundary of everything is the air box's outside.
    DimTags all, boundary;
    gmsh::model::getEntities(all, dim);
    gmsh::model::getBoundary(all, boundary, true, false, false);
    std::vector<int> boundary_tags;
    for (const auto& [d, tag] : boundary) boundary_tags.push_back(std::abs(tag));
    gmsh::model::addPhysicalGroup(dim - 1, boundary_tags, request.boundary_region);

    // Element size: the smallest of the refinement boxes, the far size elsewhere.
    std::vector<double> fields;
    for (const auto& r : request.refinements) fields.push_back(add_refinement_field(r, request.far_size));
    const int minimum = gmsh::model::mesh::field::add("Min");
    gmsh::model::mesh::field::setNumbers(minimum, "FieldsList", fields);
    gmsh::model::mesh::field::setAsBackgroundMesh(minimum);
    gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
    gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
    gmsh::option::setNumber("Mesh.MeshSizeMax", request.far_size);
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);  // Delaunay: robust on thin fragments
    gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
    gmsh::option::setNumber("General.NumThreads", 1);

    try {
        gmsh::model::mesh::generate(dim);
    } catch (const std::exception& e) {
        throw std::runtime_error(std::string("gmsh could not mesh the model: ") + e.what() +
                                 " (try a different mesh size, or check the geometry for touching edges)");
    }
    gmsh::write(mesh_file.string());

    MeshSummary summary;
    std::vector<std::size_t> node_tags;
    std::vector<double> coords, parametric;
    gmsh::model::mesh::getNodes(node_tags, coords, parametric);
    summary.nodes = node_tags.size();
    summary.elements = count_elements(dim);
    summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
}

}  // namespace mrjam::magnetics
