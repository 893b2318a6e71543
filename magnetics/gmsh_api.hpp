#pragma once
// gmsh's API, the part mrjam meshes with, loaded on its first call.
//
// Linked at build time, libgmsh made every mrjam process (--help, a refused scene, a shear run)
// load OpenCASCADE, FLTK and X11 before main(): 0.14 s of dynamic linking per process, twice
// with the wait-policy re-exec (apps/cli_common.hpp), most of the test suite's start-up cost.
// Only the magnetics model meshes, so the library is opened with dlopen() on the first call here
// and reached through gmsh's C API (gmshc.h, the stable interface gmsh ships for bindings).
//
// The names and defaults mirror gmsh.h's C++ API, so the model builders read as gmsh's own
// documentation: inside mrjam::magnetics, gmsh::model::occ::addBox is this addBox.
// A failed call throws GmshError with gmsh's last logged error (the C++ API threw it as a string).
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mrjam::gmsh_api {

using vectorpair = std::vector<std::pair<int, int>>;

// A gmsh call that failed, or the library that could not be opened.
struct GmshError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void initialize();
void finalize();
void write(const std::string& file_name);

namespace option {
void setNumber(const std::string& name, double value);
}

namespace model {
void add(const std::string& name);
int addPhysicalGroup(int dim, const std::vector<int>& tags, int tag = -1);
void getEntities(vectorpair& dimTags, int dim = -1);
void getBoundary(const vectorpair& dimTags, vectorpair& outDimTags, bool combined = true, bool oriented = true,
                 bool recursive = false);
void getBoundingBox(int dim, int tag, double& xmin, double& ymin, double& zmin, double& xmax, double& ymax,
                    double& zmax);

namespace mesh {
void generate(int dim = 3);
void getNodes(std::vector<std::size_t>& nodeTags, std::vector<double>& coord, std::vector<double>& parametricCoord,
              int dim = -1, int tag = -1, bool includeBoundary = false, bool returnParametricCoord = true);
void getElements(std::vector<int>& elementTypes, std::vector<std::vector<std::size_t>>& elementTags,
                 std::vector<std::vector<std::size_t>>& nodeTags, int dim = -1, int tag = -1);

namespace field {
int add(const std::string& fieldType, int tag = -1);
void setNumber(int tag, const std::string& option, double value);
void setNumbers(int tag, const std::string& option, const std::vector<double>& value);
void setString(int tag, const std::string& option, const std::string& value);
void setAsBackgroundMesh(int tag);
}  // namespace field
}  // namespace mesh

namespace occ {
int addPoint(double x, double y, double z, double meshSize = 0., int tag = -1);
int addLine(int startTag, int endTag, int tag = -1);
int addCircleArc(int startTag, int centerTag, int endTag, int tag = -1);
int addCurveLoop(const std::vector<int>& curveTags, int tag = -1);
int addPlaneSurface(const std::vector<int>& wireTags, int tag = -1);
int addRectangle(double x, double y, double z, double dx, double dy, int tag = -1, double roundedRadius = 0.);
int addDisk(double xc, double yc, double zc, double rx, double ry, int tag = -1);
int addBox(double x, double y, double z, double dx, double dy, double dz, int tag = -1);
int addCylinder(double x, double y, double z, double dx, double dy, double dz, double r, int tag = -1,
                double angle = 2 * 3.14159265358979323846);
int addCone(double x, double y, double z, double dx, double dy, double dz, double r1, double r2, int tag = -1,
            double angle = 2 * 3.14159265358979323846);
void extrude(const vectorpair& dimTags, double dx, double dy, double dz, vectorpair& outDimTags,
             const std::vector<int>& numElements = {}, const std::vector<double>& heights = {}, bool recombine = false);
void fuse(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
          std::vector<vectorpair>& outDimTagsMap, int tag = -1, bool removeObject = true, bool removeTool = true);
void cut(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
         std::vector<vectorpair>& outDimTagsMap, int tag = -1, bool removeObject = true, bool removeTool = true);
void intersect(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
               std::vector<vectorpair>& outDimTagsMap, int tag = -1, bool removeObject = true, bool removeTool = true);
void fragment(const vectorpair& objectDimTags, const vectorpair& toolDimTags, vectorpair& outDimTags,
              std::vector<vectorpair>& outDimTagsMap, int tag = -1, bool removeObject = true, bool removeTool = true);
void synchronize();
}  // namespace occ
}  // namespace model

}  // namespace mrjam::gmsh_api

namespace mrjam::magnetics {
namespace gmsh = mrjam::gmsh_api;
}
