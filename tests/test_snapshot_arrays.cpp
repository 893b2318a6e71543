// Extra integer point arrays in snapshots (a mode's own per-grain data, such as the jam
// predictor's contact-cluster id): present in each format with the values given, and refused
// when they do not match the particles.
#include <doctest/doctest.h>

#include <sstream>
#include <stdexcept>

#include "io/snapshot.hpp"
#include "test_support.hpp"

using namespace mrjam;

namespace {
Particles three_grains() {
    Particles p;
    p.add({0, 0, 0}, 1e-5, 7800, 0);
    p.add({1e-4, 0, 0}, 1e-5, 7800, 0);
    p.add({0, 1e-4, 0}, 1e-5, 7800, 0);
    return p;
}
}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("snapshots: extra integer arrays in VTK legacy, VTK XML and the LAMMPS dump") {
        mrjam_test::TempDir dir("mrjam_snapshot_arrays");
        const Particles p = three_grains();
        Domain d;
        const std::vector<IntPointArray> extra{{"cluster", {0, 0, 7}}, {"cluster_size", {2, 2, 1}}};

        write_snapshot(dir.file("a.vtk"), SnapshotFormat::vtk_legacy, p, d, 5, 1e-6, extra);
        const std::string vtk = mrjam_test::slurp(dir.file("a.vtk"));
        CHECK(vtk.find("FIELD FieldData 7\n") != std::string::npos);  // the 5 engine arrays and 2 more
        const auto at = vtk.find("\ncluster 1 3 int\n");
        REQUIRE(at != std::string::npos);
        const unsigned char* v =
            reinterpret_cast<const unsigned char*>(vtk.data() + at + std::string("\ncluster 1 3 int\n").size());
        CHECK(v[11] == 7);  // third value, big-endian
        CHECK(v[8] == 0);

        write_snapshot(dir.file("a.vtp"), SnapshotFormat::vtk_xml, p, d, 5, 1e-6, extra);
        const std::string vtp = mrjam_test::slurp(dir.file("a.vtp"));
        CHECK(vtp.find("<DataArray type=\"Int32\" Name=\"cluster\"") != std::string::npos);
        CHECK(vtp.find("<DataArray type=\"Int32\" Name=\"cluster_size\"") != std::string::npos);

        write_snapshot(dir.file("a.dump"), SnapshotFormat::lammps_dump, p, d, 5, 1e-6, extra);
        std::istringstream dump(mrjam_test::slurp(dir.file("a.dump")));
        std::string line, last;
        bool header = false;
        while (std::getline(dump, line)) {
            if (line.rfind("ITEM: ATOMS", 0) == 0)
                header = line.size() > 20 && line.substr(line.size() - 21) == " cluster cluster_size";
            last = line;
        }
        CHECK(header);
        CHECK(last.substr(last.size() - 4) == " 7 1");  // the third grain's two extra columns

        // Wrong length or a name that would break the file: refused before anything is written.
        CHECK_THROWS_AS(
            write_snapshot(dir.file("b.vtk"), SnapshotFormat::vtk_legacy, p, d, 0, 0, {{"cluster", {1, 2}}}),
            std::invalid_argument);
        CHECK_THROWS_AS(
            write_snapshot(dir.file("b.vtk"), SnapshotFormat::vtk_legacy, p, d, 0, 0, {{"two words", {1, 2, 3}}}),
            std::invalid_argument);
        CHECK_FALSE(std::filesystem::exists(dir.file("b.vtk")));
    }

}  // TEST_SUITE
