#include "magnetics/gmsh_api.hpp"

// Declarations only: the functions are reached through dlsym, never linked.
#include <gmshc.h>

#include <type_traits>

#include "core/shared_library.hpp"

namespace mrjam::gmsh_api {
namespace {

// Every C function used, resolved together when the library opens, so a gmsh too old for one of
// them is refused at once, by name.
// clang-format off
#define MRJAM_GMSH_FUNCTIONS(X) \
    X(Initialize) \
    X(Finalize) \
    X(Write) \
    X(Free) \
    X(LoggerGetLastError) \
    X(OptionSetNumber) \
    X(ModelAdd) \
    X(ModelAddPhysicalGroup) \
    X(ModelGetEntities) \
    X(ModelGetBoundary) \
    X(ModelGetBoundingBox) \
    X(ModelMeshGenerate) \
    X(ModelMeshGetNodes) \
    X(ModelMeshGetElements) \
    X(ModelMeshFieldAdd) \
    X(ModelMeshFieldSetNumber) \
    X(ModelMeshFieldSetNumbers) \
    X(ModelMeshFieldSetString) \
    X(ModelMeshFieldSetAsBackgroundMesh) \
    X(ModelOccAddPoint) \
    X(ModelOccAddLine) \
    X(ModelOccAddCircleArc) \
    X(ModelOccAddCurveLoop) \
    X(ModelOccAddPlaneSurface) \
    X(ModelOccAddRectangle) \
    X(ModelOccAddDisk) \
    X(ModelOccAddBox) \
    X(ModelOccAddCylinder) \
    X(ModelOccAddCone) \
    X(ModelOccExtrude) \
    X(ModelOccFuse) \
    X(ModelOccCut) \
    X(ModelOccIntersect) \
    X(ModelOccFragment) \
    X(ModelOccSynchronize)
// clang-format on

struct Library {
#define MRJAM_GMSH_POINTER(name) decltype(&::gmsh##name) name = nullptr;
    MRJAM_GMSH_FUNCTIONS(MRJAM_GMSH_POINTER)
#undef MRJAM_GMSH_POINTER
};

Library load() {
    const std::string fix = "install it with bash scripts/install-deps.sh";
    const SharedLibrary gmsh = SharedLibrary::open<GmshError>(MRJAM_GMSH_SONAME, MRJAM_GMSH_PATH, fix);
    Library api;
#define MRJAM_GMSH_RESOLVE(name) gmsh.resolve<GmshError>(api.name, "gmsh" #name, fix);
    MRJAM_GMSH_FUNCTIONS(MRJAM_GMSH_RESOLVE)
#undef MRJAM_GMSH_RESOLVE
    return api;
}

const Library& api() {
    static const Library library = load();
    return library;
}

[[noreturn]] void fail(const char* function) {
    std::string message = std::string("gmsh") + function + " failed";
    char* last = nullptr;
    int ierr = 0;
    api().LoggerGetLastError(&last, &ierr);
    if (last) {
        if (ierr == 0 && *last) message = last;
        api().Free(last);
    }
    throw GmshError(message);
}

// Calls a gmsh C function whose last argument is its error flag; a set flag throws.
template <class F, class... Args>
auto call(const char* name, F function, Args... args) {
    int ierr = 0;
    if constexpr (std::is_void_v<decltype(function(args..., &ierr))>) {
        function(args..., &ierr);
        if (ierr) fail(name);
    } else {
        auto result = function(args..., &ierr);
        if (ierr) fail(name);
        return result;
    }
}

std::vector<int> flatten(const vectorpair& dim_tags) {
    std::vector<int> flat;
    flat.reserve(2 * dim_tags.size());
    for (const auto& [dim, tag] : dim_tags) {
        flat.push_back(dim);
        flat.push_back(tag);
    }
    return flat;
}

// Takes over an array gmsh allocated: copied out and freed.
template <class T>
std::vector<T> take(T* data, std::size_t n) {
    std::vector<T> out(data, data + n);
    api().Free(data);
    return out;
}

vectorpair take_pairs(int* flat, std::size_t n) {
    vectorpair out;
    out.reserve(n / 2);
    for (std::size_t k = 0; k + 1 < n; k += 2) out.emplace_back(flat[k], flat[k + 1]);
    api().Free(flat);
    return out;
}

// Takes over a list of arrays gmsh allocated (map of a boolean operation, tags per element type).
template <class T, class Convert>
auto take_lists(T** lists, std::size_t* sizes, std::size_t count, Convert convert) {
    std::vector<decltype(convert(lists[0], std::size_t{0}))> out;
    out.reserve(count);
    for (std::size_t k = 0; k < count; ++k) out.push_back(convert(lists[k], sizes[k]));
    api().Free(sizes);
    api().Free(lists);
    return out;
}

// The boolean operations share one C signature.
using BooleanFunction = decltype(&::gmshModelOccFuse);
void boolean(const char* name, BooleanFunction function, const vectorpair& object, const vectorpair& tool,
             vectorpair& out, std::vector<vectorpair>& map, int tag, bool remove_object, bool remove_tool) {
    std::vector<int> a = flatten(object), b = flatten(tool);
    int* out_flat = nullptr;
    std::size_t out_n = 0, map_nn = 0;
    int** map_flat = nullptr;
    std::size_t* map_n = nullptr;
    call(name, function, a.data(), a.size(), b.data(), b.size(), &out_flat, &out_n, &map_flat, &map_n, &map_nn, tag,
         int(remove_object), int(remove_tool));
    out = take_pairs(out_flat, out_n);
    map = take_lists(map_flat, map_n, map_nn, take_pairs);
}

}  // namespace

void initialize() { call("Initialize", api().Initialize, 0, nullptr, 1); }
void finalize() { call("Finalize", api().Finalize); }
void write(const std::string& file_name) { call("Write", api().Write, file_name.c_str()); }

void option::setNumber(const std::string& name, double value) {
    call("OptionSetNumber", api().OptionSetNumber, name.c_str(), value);
}

void model::add(const std::string& name) { call("ModelAdd", api().ModelAdd, name.c_str()); }

int model::addPhysicalGroup(int dim, const std::vector<int>& tags, int tag) {
    std::vector<int> t = tags;
    return call("ModelAddPhysicalGroup", api().ModelAddPhysicalGroup, dim, t.data(), t.size(), tag);
}

void model::getEntities(vectorpair& dimTags, int dim) {
    int* flat = nullptr;
    std::size_t n = 0;
    call("ModelGetEntities", api().ModelGetEntities, &flat, &n, dim);
    dimTags = take_pairs(flat, n);
}

void model::getBoundary(const vectorpair& dimTags, vectorpair& outDimTags, bool combined, bool oriented,
                        bool recursive) {
    std::vector<int> in = flatten(dimTags);
    int* flat = nullptr;
    std::size_t n = 0;
    call("ModelGetBoundary", api().ModelGetBoundary, in.data(), in.size(), &flat, &n, int(combined), int(oriented),
         int(recursive));
    outDimTags = take_pairs(flat, n);
}

void model::getBoundingBox(int dim, int tag, double& xmin, double& ymin, double& zmin, double& xmax, double& ymax,
                           double& zmax) {
    call("ModelGetBoundingBox", api().ModelGetBoundingBox, dim, tag, &xmin, &ymin, &zmin, &xmax, &ymax, &zmax);
}

void model::mesh::generate(int dim) { call("ModelMeshGenerate", api().ModelMeshGenerate, dim); }

void model::mesh::getNodes(std::vector<std::size_t>& nodeTags, std::vector<double>& coord,
                           std::vector<double>& parametricCoord, int dim, int tag, bool includeBoundary,
                           bool returnParametricCoord) {
    std::size_t *tags = nullptr, n_tags = 0, n_coord = 0, n_param = 0;
    double *xyz = nullptr, *param = nullptr;
    call("ModelMeshGetNodes", api().ModelMeshGetNodes, &tags, &n_tags, &xyz, &n_coord, &param, &n_param, dim, tag,
         int(includeBoundary), int(returnParametricCoord));
    nodeTags = take(tags, n_tags);
    coord = take(xyz, n_coord);
    parametricCoord = take(param, n_param);
}

void model::mesh::getElements(std::vector<int>& elementTypes, std::vector<std::vector<std::size_t>>& elementTags,
                              std::vector<std::vector<std::size_t>>& nodeTags, int dim, int tag) {
    int* types = nullptr;
    std::size_t n_types = 0, n_elements = 0, n_nodes = 0;
    std::size_t **elements = nullptr, **nodes = nullptr, *element_sizes = nullptr, *node_sizes = nullptr;
    call("ModelMeshGetElements", api().ModelMeshGetElements, &types, &n_types, &elements, &element_sizes, &n_elements,
         &nodes, &node_sizes, &n_nodes, dim, tag);
    elementTypes = take(types, n_types);
    elementTags = take_lists(elements, element_sizes, n_elements, take<std::size_t>);
    nodeTags = take_lists(nodes, node_sizes, n_nodes, take<std::size_t>);
}

int model::mesh::field::add(const std::string& fieldType, int tag) {
    return call("ModelMeshFieldAdd", api().ModelMeshFieldAdd, fieldType.c_str(), tag);
}
void model::mesh::field::setNumber(int tag, const std::string& option, double value) {
    call("ModelMeshFieldSetNumber", api().ModelMeshFieldSetNumber, tag, option.c_str(), value);
}
void model::mesh::field::setNumbers(int tag, const std::string& option, const std::vector<double>& value) {
    std::vector<double> v = value;
    call("ModelMeshFieldSetNumbers", api().ModelMeshFieldSetNumbers, tag, option.c_str(), v.data(), v.size());
}
void model::mesh::field::setString(int tag, const std::string& option, const std::string& value) {
    call("ModelMeshFieldSetString", api().ModelMeshFieldSetString, tag, option.c_str(), value.c_str());
}
void model::mesh::field::setAsBackgroundMesh(int tag) {
    call("ModelMeshFieldSetAsBackgroundMesh", api().ModelMeshFieldSetAsBackgroundMesh, tag);
}

int model::occ::addPoint(double x, double y, double z, double meshSize, int tag) {
    return call("ModelOccAddPoint", api().ModelOccAddPoint, x, y, z, meshSize, tag);
}
int model::occ::addLine(int startTag, int endTag, int tag) {
    return call("ModelOccAddLine", api().ModelOccAddLine, startTag, endTag, tag);
}
int model::occ::addCircleArc(int startTag, int centerTag, int endTag, int tag) {
    return call("ModelOccAddCircleArc", api().ModelOccAddCircleArc, startTag, centerTag, endTag, tag);
}
int model::occ::addCurveLoop(const std::vector<int>& curveTags, int tag) {
    std::vector<int> c = curveTags;
    return call("ModelOccAddCurveLoop", api().ModelOccAddCurveLoop, c.data(), c.size(), tag);
}
int model::occ::addPlaneSurface(const std::vector<int>& wireTags, int tag) {
    std::vector<int> w = wireTags;
    return call("ModelOccAddPlaneSurface", api().ModelOccAddPlaneSurface, w.data(), w.size(), tag);
}
int model::occ::addRectangle(double x, double y, double z, double dx, double dy, int tag, double roundedRadius) {
    return call("ModelOccAddRectangle", api().ModelOccAddRectangle, x, y, z, dx, dy, tag, roundedRadius);
}
int model::occ::addDisk(double xc, double yc, double zc, double rx, double ry, int tag) {
    return call("ModelOccAddDisk", api().ModelOccAddDisk, xc, yc, zc, rx, ry, tag);
}
int model::occ::addBox(double x, double y, double z, double dx, double dy, double dz, int tag) {
    return call("ModelOccAddBox", api().ModelOccAddBox, x, y, z, dx, dy, dz, tag);
}
int model::occ::addCylinder(double x, double y, double z, double dx, double dy, double dz, double r, int tag,
                            double angle) {
    return call("ModelOccAddCylinder", api().ModelOccAddCylinder, x, y, z, dx, dy, dz, r, tag, angle);
}
int model::occ::addCone(double x, double y, double z, double dx, double dy, double dz, double r1, double r2, int tag,
                        double angle) {
    return call("ModelOccAddCone", api().ModelOccAddCone, x, y, z, dx, dy, dz, r1, r2, tag, angle);
}

void model::occ::extrude(const vectorpair& dimTags, double dx, double dy, double dz, vectorpair& outDimTags,
                         const std::vector<int>& numElements, const std::vector<double>& heights, bool recombine) {
    std::vector<int> in = flatten(dimTags), layers = numElements;
    std::vector<double> h = heights;
    int* flat = nullptr;
    std::size_t n = 0;
    call("ModelOccExtrude", api().ModelOccExtrude, in.data(), in.size(), dx, dy, dz, &flat, &n, layers.data(),
         layers.size(), h.data(), h.size(), int(recombine));
    outDimTags = take_pairs(flat, n);
}

void model::occ::fuse(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
                      std::vector<vectorpair>& outDimTagsMap, int tag, bool removeObject, bool removeTool) {
    boolean("ModelOccFuse", api().ModelOccFuse, objectDimTags, toolDimTags, outDimTags, outDimTagsMap, tag,
            removeObject, removeTool);
}
void model::occ::cut(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
                     std::vector<vectorpair>& outDimTagsMap, int tag, bool removeObject, bool removeTool) {
    boolean("ModelOccCut", api().ModelOccCut, objectDimTags, toolDimTags, outDimTags, outDimTagsMap, tag, removeObject,
            removeTool);
}
void model::occ::intersect(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
                           std::vector<vectorpair>& outDimTagsMap, int tag, bool removeObject, bool removeTool) {
    boolean("ModelOccIntersect", api().ModelOccIntersect, objectDimTags, toolDimTags, outDimTags, outDimTagsMap, tag,
            removeObject, removeTool);
}
void model::occ::fragment(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
                          std::vector<vectorpair>& outDimTagsMap, int tag, bool removeObject, bool removeTool) {
    boolean("ModelOccFragment", api().ModelOccFragment, objectDimTags, toolDimTags, outDimTags, outDimTagsMap, tag,
            removeObject, removeTool);
}
void model::occ::synchronize() { call("ModelOccSynchronize", api().ModelOccSynchronize); }

}  // namespace mrjam::gmsh_api
