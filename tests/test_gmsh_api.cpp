// gmsh's API reached through its C interface, opened on first use (magnetics/gmsh_api.hpp): the
// C++ names must carry their arguments and results through, and a failed call must throw with
// gmsh's own message rather than return a meaningless tag.
#include <doctest/doctest.h>

#include <string>

#include "magnetics/gmsh_api.hpp"
#include "magnetics/gmsh_assembly.hpp"

using namespace mrjam::magnetics;

TEST_SUITE("unit") {
    TEST_CASE("gmsh api: a box's entities, boundary and bounding box come back as gmsh made them") {
        GmshSession session("api_check");
        const int box = gmsh::model::occ::addBox(0, 0, 0, 1, 2, 3);
        gmsh::model::occ::synchronize();
        gmsh::vectorpair volumes, faces;
        gmsh::model::getEntities(volumes, 3);
        REQUIRE(volumes.size() == 1);
        CHECK(volumes[0] == std::pair{3, box});
        gmsh::model::getBoundary(volumes, faces, true, false, false);
        CHECK(faces.size() == 6);  // a box has six faces
        for (const auto& [dim, tag] : faces) CHECK(dim == 2);
        double x0, y0, z0, x1, y1, z1;
        gmsh::model::getBoundingBox(3, box, x0, y0, z0, x1, y1, z1);
        // OCC pads bounding boxes by its tolerance (1e-7): the box's extents within that.
        CHECK(x1 - x0 == doctest::Approx(1).epsilon(1e-6));
        CHECK(y1 - y0 == doctest::Approx(2).epsilon(1e-6));
        CHECK(z1 - z0 == doctest::Approx(3).epsilon(1e-6));
    }

    TEST_CASE("gmsh api: the nested results of a boolean and of a mesh are copied whole") {
        GmshSession session("api_nested");
        const int a = gmsh::model::occ::addRectangle(0, 0, 0, 2, 1);
        const int b = gmsh::model::occ::addRectangle(1, 0, 0, 2, 1);
        gmsh::vectorpair out;
        std::vector<gmsh::vectorpair> map;
        gmsh::model::occ::fragment({{2, a}}, {{2, b}}, out, map);
        gmsh::model::occ::synchronize();
        CHECK(out.size() == 3);  // left, overlap, right
        REQUIRE(map.size() == 2);
        CHECK(map[0].size() == 2);  // each rectangle is now two pieces, sharing the overlap
        CHECK(map[1].size() == 2);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::option::setNumber("Mesh.MeshSizeMax", 0.25);
        gmsh::model::mesh::generate(2);
        std::vector<int> types;
        std::vector<std::vector<std::size_t>> tags, nodes;
        gmsh::model::mesh::getElements(types, tags, nodes, 2);
        REQUIRE(types.size() == 1);
        CHECK(types[0] == 2);  // 3-node triangles
        REQUIRE(tags.size() == 1);
        CHECK(nodes[0].size() == 3 * tags[0].size());
        std::vector<std::size_t> node_tags;
        std::vector<double> coords, parametric;
        gmsh::model::mesh::getNodes(node_tags, coords, parametric);
        CHECK(coords.size() == 3 * node_tags.size());
        CHECK(node_tags.size() >= 32);  // the 3 x 1 strip's perimeter alone, 8 long at 0.25
    }

    TEST_CASE("gmsh api: a failed call throws GmshError with gmsh's message") {
        GmshSession session("api_error");
        // Points 1000 and 1001 do not exist.
        try {
            gmsh::model::occ::addLine(1000, 1001);
            FAIL("addLine on missing points returned");
        } catch (const gmsh::GmshError& e) {
            const std::string what = e.what();
            CAPTURE(what);
            CHECK(what.find("1000") != std::string::npos);
        }
    }
}
