// Snapshot writers (VTK legacy, VTK XML, LAMMPS dump) and the LAMMPS data writer: each file is
// written for a few particles and read back far enough to check counts and exact values.
#include <doctest/doctest.h>

#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/lammps_data.hpp"
#include "io/snapshot.hpp"
#include "test_support.hpp"

namespace {

using mrjam_test::slurp;
struct TempDir : mrjam_test::TempDir {
    TempDir() : mrjam_test::TempDir("mrjam_snapshot") {}
};

namespace fs = std::filesystem;
using mrjam::Domain;
using mrjam::Particles;
using mrjam::SnapshotFormat;
using mrjam::Vec3;

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

std::vector<std::string> words(const std::string& line) {
    std::vector<std::string> w;
    std::istringstream in(line);
    for (std::string s; in >> s;) w.push_back(s);
    return w;
}

double to_double(const std::string& s) { return std::stod(s); }

// Values with long mantissas so any loss of precision shows.
Particles sample_particles() {
    Particles p;
    p.add({0.1234567890123456, 0.2, 0.3}, 5.0e-4, 2500.0, 0);
    p.add({-1.0 / 3.0, 2.0 / 7.0, 1e-9}, 4.5e-4 + 1e-19, 2500.0, 1);
    p.add({0.75, -0.000123456789, 0.5}, 6.0e-4, 2500.0, 2);
    p.add({1e-300, 123456.789, -0.0}, 1.0e-3, 2500.0, 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double s = static_cast<double>(i) + 1.0;
        p.velocity[i] = {0.1 * s, -0.2 / s, 1.0 / 3.0 * s};
        p.angular_velocity[i] = {10.0 * s, 20.0 / 3.0, -30.0 * s};
        p.force[i] = {1e-6 * s, -2e-7, 3.0 / 11.0};
        p.dipole_moment[i] = {0.0, 1e-12 / s, -5e-13};
        p.id[i] = 100 + 7 * i;  // ids need not equal indices
    }
    return p;
}

Domain sample_domain() {
    Domain d;
    d.lo = {-0.5, -1.0, 0.0};
    d.hi = {1.0 / 3.0, 2.0, 0.01};
    d.periodic = {true, false, true};
    return d;
}

template <class T>
T read_big_endian(const std::string& bytes, std::size_t offset) {
    REQUIRE(offset + sizeof(T) <= bytes.size());
    unsigned char raw[sizeof(T)];
    for (std::size_t k = 0; k < sizeof(T); ++k)
        raw[k] = static_cast<unsigned char>(bytes[offset + sizeof(T) - 1 - k]);  // reverse to LE
    std::uint64_t bits = 0;
    for (std::size_t k = 0; k < sizeof(T); ++k) bits |= std::uint64_t{raw[k]} << (8 * k);
    if constexpr (sizeof(T) == 8) {
        return std::bit_cast<T>(bits);
    } else if constexpr (sizeof(T) == 4) {
        return std::bit_cast<T>(static_cast<std::uint32_t>(bits));
    } else {
        return std::bit_cast<T>(static_cast<std::uint16_t>(bits));
    }
}

// Byte offset just past `marker` in `bytes`; fails the test if the marker is missing.
std::size_t after(const std::string& bytes, const std::string& marker, std::size_t from = 0) {
    const auto at = bytes.find(marker, from);
    REQUIRE_MESSAGE(at != std::string::npos, "missing: " << marker);
    return at + marker.size();
}

std::string base64_decode(const std::string& text) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    };
    std::string out;
    unsigned buffer = 0;
    int bits = 0;
    for (char c : text) {
        if (c == '=' || c == ' ' || c == '\n') continue;
        const int v = value(c);
        REQUIRE_MESSAGE(v >= 0, "bad base64 character " << c);
        buffer = (buffer << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out += static_cast<char>((buffer >> bits) & 0xFFu);
        }
    }
    return out;
}

template <class T>
std::vector<T> little_endian_values(const std::string& bytes, std::size_t offset, std::size_t count) {
    REQUIRE(offset + count * sizeof(T) <= bytes.size());
    std::vector<T> v(count);
    for (std::size_t i = 0; i < count; ++i) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes.data() + offset + i * sizeof(T), sizeof(T));
        if constexpr (std::endian::native == std::endian::big)
            for (std::size_t a = 0, b = sizeof(T) - 1; a < b; ++a, --b) std::swap(raw[a], raw[b]);
        std::memcpy(&v[i], raw, sizeof(T));
    }
    return v;
}

// Minimal XML check: tags nest and close in order, attributes of each element collected.
struct XmlElement {
    std::string name;
    std::map<std::string, std::string> attributes;
    std::string text;  // character data directly inside the element
};

std::vector<XmlElement> parse_xml(const std::string& doc) {
    std::vector<XmlElement> all;
    std::vector<std::size_t> open;
    std::size_t pos = 0;
    REQUIRE(doc.rfind("<?xml", 0) == 0);
    pos = after(doc, "?>");
    while (true) {
        const auto lt = doc.find('<', pos);
        if (lt == std::string::npos) break;
        if (!open.empty()) all[open.back()].text += doc.substr(pos, lt - pos);
        const auto gt = doc.find('>', lt);
        REQUIRE(gt != std::string::npos);
        std::string tag = doc.substr(lt + 1, gt - lt - 1);
        pos = gt + 1;
        if (tag[0] == '/') {
            REQUIRE_MESSAGE(!open.empty(), "unbalanced </" << tag << ">");
            CHECK(all[open.back()].name == tag.substr(1));
            open.pop_back();
            continue;
        }
        const bool self_closing = tag.back() == '/';
        if (self_closing) tag.pop_back();
        XmlElement e;
        std::istringstream in(tag);
        in >> e.name;
        std::string rest;
        std::getline(in, rest);
        std::size_t a = 0;
        while ((a = rest.find('=', a)) != std::string::npos) {
            auto key_start = rest.find_last_of(' ', a);
            const std::string key = rest.substr(key_start + 1, a - key_start - 1);
            REQUIRE(rest[a + 1] == '"');
            const auto close = rest.find('"', a + 2);
            REQUIRE(close != std::string::npos);
            e.attributes[key] = rest.substr(a + 2, close - a - 2);
            a = close;
        }
        all.push_back(e);
        if (!self_closing) open.push_back(all.size() - 1);
    }
    CHECK(open.empty());
    return all;
}

const XmlElement& find_array(const std::vector<XmlElement>& xml, const std::string& name) {
    for (const auto& e : xml)
        if (e.name == "DataArray" && e.attributes.count("Name") && e.attributes.at("Name") == name) return e;
    FAIL("no DataArray named " << name);
    throw std::logic_error("unreachable");
}

// Decodes a binary inline DataArray: UInt64 byte count followed by the payload.
template <class T>
std::vector<T> decode_array(const XmlElement& e, std::size_t expected_count) {
    CHECK(e.attributes.at("format") == "binary");
    const std::string bytes = base64_decode(e.text);
    const auto header = little_endian_values<std::uint64_t>(bytes, 0, 1);
    CHECK(header[0] == expected_count * sizeof(T));
    CHECK(bytes.size() == 8 + expected_count * sizeof(T));
    return little_endian_values<T>(bytes, 8, expected_count);
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("snapshot format names and extensions") {
        CHECK(mrjam::snapshot_format_from_name("vtk") == SnapshotFormat::vtk_legacy);
        CHECK(mrjam::snapshot_format_from_name("vtp") == SnapshotFormat::vtk_xml);
        CHECK(mrjam::snapshot_format_from_name("lammps") == SnapshotFormat::lammps_dump);
        CHECK(mrjam::snapshot_extension(SnapshotFormat::vtk_legacy) == ".vtk");
        CHECK(mrjam::snapshot_extension(SnapshotFormat::vtk_xml) == ".vtp");
        CHECK(mrjam::snapshot_extension(SnapshotFormat::lammps_dump) == ".dump");
        try {
            mrjam::snapshot_format_from_name("xyz");
            FAIL("expected std::invalid_argument");
        } catch (const std::invalid_argument& e) {
            const std::string msg = e.what();
            CHECK(msg.find("xyz") != std::string::npos);
            CHECK(msg.find("vtk") != std::string::npos);
            CHECK(msg.find("vtp") != std::string::npos);
            CHECK(msg.find("lammps") != std::string::npos);
        }
    }

    TEST_CASE("LAMMPS dump round-trips every column at full precision") {
        TempDir dir;
        const Particles p = sample_particles();
        const Domain d = sample_domain();
        const std::string path = dir.file("snap.dump");
        mrjam::write_snapshot(path, SnapshotFormat::lammps_dump, p, d, 1234, 1.234e-3);

        const auto lines = split_lines(slurp(path));
        REQUIRE(lines.size() == 9 + p.size());
        CHECK(lines[0] == "ITEM: TIMESTEP");
        CHECK(lines[1] == "1234");
        CHECK(lines[2] == "ITEM: NUMBER OF ATOMS");
        CHECK(lines[3] == std::to_string(p.size()));
        CHECK(lines[4] == "ITEM: BOX BOUNDS pp ff pp");
        for (int k = 0; k < 3; ++k) {
            const auto w = words(lines[5 + k]);
            REQUIRE(w.size() == 2);
            CHECK(to_double(w[0]) == d.lo[k]);
            CHECK(to_double(w[1]) == d.hi[k]);
        }
        CHECK(lines[8] == "ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz fx fy fz mux muy muz");
        for (std::size_t i = 0; i < p.size(); ++i) {
            const auto w = words(lines[9 + i]);
            REQUIRE(w.size() == 18);
            CHECK(std::stoull(w[0]) == p.id[i]);
            CHECK(std::stoul(w[1]) == p.material[i] + 1u);
            CHECK(to_double(w[2]) == p.radius[i]);
            const Vec3* vectors[5] = {&p.position[i], &p.velocity[i], &p.angular_velocity[i], &p.force[i],
                                      &p.dipole_moment[i]};
            for (int v = 0; v < 5; ++v)
                for (int k = 0; k < 3; ++k) CHECK(to_double(w[3 + 3 * v + k]) == (*vectors[v])[k]);
        }
    }

    TEST_CASE("VTK legacy file is big-endian binary POLYDATA with the point arrays") {
        TempDir dir;
        const Particles p = sample_particles();
        const std::size_t n = p.size();
        const std::string path = dir.file("snap.vtk");
        mrjam::write_snapshot(path, SnapshotFormat::vtk_legacy, p, sample_domain(), 77, 0.5);
        const std::string bytes = slurp(path);

        CHECK(bytes.rfind("# vtk DataFile Version 3.0\n", 0) == 0);
        CHECK(bytes.find("\nBINARY\nDATASET POLYDATA\n") != std::string::npos);
        CHECK(read_big_endian<double>(bytes, after(bytes, "TIME 1 1 double\n")) == 0.5);
        CHECK(read_big_endian<std::int64_t>(bytes, after(bytes, "CYCLE 1 1 vtktypeint64\n")) == 77);

        const std::size_t points = after(bytes, "POINTS " + std::to_string(n) + " double\n");
        for (std::size_t i = 0; i < n; ++i)
            for (int k = 0; k < 3; ++k)
                CHECK(read_big_endian<double>(bytes, points + (3 * i + k) * 8) == p.position[i][k]);
        // The first coordinate byte by byte: big-endian means the sign/exponent byte comes first.
        const auto bits = std::bit_cast<std::uint64_t>(p.position[0].x);
        CHECK(static_cast<unsigned char>(bytes[points]) == (bits >> 56));
        CHECK(static_cast<unsigned char>(bytes[points + 7]) == (bits & 0xFFu));

        const std::size_t verts = after(bytes, "VERTICES " + std::to_string(n) + " " + std::to_string(2 * n) + "\n");
        for (std::size_t i = 0; i < n; ++i) {
            CHECK(read_big_endian<std::int32_t>(bytes, verts + 8 * i) == 1);
            CHECK(read_big_endian<std::int32_t>(bytes, verts + 8 * i + 4) == static_cast<std::int32_t>(i));
        }

        const std::size_t point_data = after(bytes, "POINT_DATA " + std::to_string(n) + "\n");
        const std::string count = std::to_string(n);
        const std::size_t radius = after(bytes, "SCALARS radius double 1\nLOOKUP_TABLE default\n", point_data);
        const std::size_t field = after(bytes, "FIELD FieldData 5\n", point_data);
        const std::size_t ids = after(bytes, "id 1 " + count + " vtktypeuint64\n", field);
        const std::size_t mats = after(bytes, "material 1 " + count + " unsigned_short\n", field);
        for (std::size_t i = 0; i < n; ++i) {
            CHECK(read_big_endian<double>(bytes, radius + 8 * i) == p.radius[i]);
            CHECK(read_big_endian<std::uint64_t>(bytes, ids + 8 * i) == p.id[i]);
            CHECK(read_big_endian<std::uint16_t>(bytes, mats + 2 * i) == p.material[i]);
        }
        const std::pair<std::string, const std::vector<Vec3>*> vectors[] = {
            {"VECTORS velocity double\n", &p.velocity},
            {"angular_velocity 3 " + count + " double\n", &p.angular_velocity},
            {"force 3 " + count + " double\n", &p.force},
            {"dipole_moment 3 " + count + " double\n", &p.dipole_moment}};
        for (const auto& [header, values] : vectors) {
            const std::size_t at = after(bytes, header, point_data);
            for (std::size_t i = 0; i < n; ++i)
                for (int k = 0; k < 3; ++k)
                    CHECK(read_big_endian<double>(bytes, at + (3 * i + k) * 8) == (*values)[i][k]);
        }
        // Last array ends the file: its payload plus the closing newline.
        const std::size_t last = after(bytes, "dipole_moment 3 " + count + " double\n", field);
        CHECK(bytes.size() == last + n * 24 + 1);
    }

    TEST_CASE("VTK XML PolyData is well formed and carries the arrays") {
        TempDir dir;
        const Particles p = sample_particles();
        const std::size_t n = p.size();
        const std::string path = dir.file("snap.vtp");
        mrjam::write_snapshot(path, SnapshotFormat::vtk_xml, p, sample_domain(), 5, 2.5e-6);
        const auto xml = parse_xml(slurp(path));

        REQUIRE(!xml.empty());
        CHECK(xml[0].name == "VTKFile");
        CHECK(xml[0].attributes.at("type") == "PolyData");
        CHECK(xml[0].attributes.at("header_type") == "UInt64");
        CHECK(xml[0].attributes.at("byte_order") == "LittleEndian");
        std::size_t pieces = 0;
        for (const auto& e : xml) {
            if (e.name != "Piece") continue;
            ++pieces;
            CHECK(e.attributes.at("NumberOfPoints") == std::to_string(n));
            CHECK(e.attributes.at("NumberOfVerts") == std::to_string(n));
        }
        CHECK(pieces == 1);

        CHECK(to_double(find_array(xml, "TIME").text) == 2.5e-6);
        CHECK(find_array(xml, "CYCLE").text == "5");

        const auto positions = decode_array<double>(find_array(xml, "Points"), 3 * n);
        const auto radius = decode_array<double>(find_array(xml, "radius"), n);
        const auto ids = decode_array<std::uint64_t>(find_array(xml, "id"), n);
        const auto mats = decode_array<std::uint16_t>(find_array(xml, "material"), n);
        const auto conn = decode_array<std::int64_t>(find_array(xml, "connectivity"), n);
        const auto offs = decode_array<std::int64_t>(find_array(xml, "offsets"), n);
        for (std::size_t i = 0; i < n; ++i) {
            for (int k = 0; k < 3; ++k) CHECK(positions[3 * i + k] == p.position[i][k]);
            CHECK(radius[i] == p.radius[i]);
            CHECK(ids[i] == p.id[i]);
            CHECK(mats[i] == p.material[i]);
            CHECK(conn[i] == static_cast<std::int64_t>(i));
            CHECK(offs[i] == static_cast<std::int64_t>(i + 1));
        }
        const std::pair<const char*, const std::vector<Vec3>*> vectors[] = {{"velocity", &p.velocity},
                                                                            {"angular_velocity", &p.angular_velocity},
                                                                            {"force", &p.force},
                                                                            {"dipole_moment", &p.dipole_moment}};
        for (const auto& [name, field] : vectors) {
            const auto& e = find_array(xml, name);
            CHECK(e.attributes.at("NumberOfComponents") == "3");
            const auto v = decode_array<double>(e, 3 * n);
            for (std::size_t i = 0; i < n; ++i)
                for (int k = 0; k < 3; ++k) CHECK(v[3 * i + k] == (*field)[i][k]);
        }
    }

    TEST_CASE("snapshots of an empty particle set are still valid files") {
        TempDir dir;
        const Particles none;
        for (auto format : {SnapshotFormat::vtk_legacy, SnapshotFormat::vtk_xml, SnapshotFormat::lammps_dump}) {
            const std::string path = dir.file("empty" + mrjam::snapshot_extension(format));
            mrjam::write_snapshot(path, format, none, sample_domain(), 0, 0.0);
            CHECK(fs::file_size(path) > 0);
        }
        CHECK(split_lines(slurp(dir.file("empty.dump"))).size() == 9);
        const auto xml = parse_xml(slurp(dir.file("empty.vtp")));
        for (const auto& e : xml)
            if (e.name == "Piece") CHECK(e.attributes.at("NumberOfPoints") == "0");
    }

    TEST_CASE("writers name the path when the file cannot be opened") {
        TempDir dir;
        const std::string path = dir.file("no_such_dir/snap.vtk");
        for (auto format : {SnapshotFormat::vtk_legacy, SnapshotFormat::vtk_xml, SnapshotFormat::lammps_dump}) {
            try {
                mrjam::write_snapshot(path, format, sample_particles(), sample_domain(), 0, 0.0);
                FAIL("expected std::runtime_error");
            } catch (const std::runtime_error& e) {
                CHECK(std::string(e.what()).find(path) != std::string::npos);
            }
        }
        try {
            mrjam::write_lammps_data(path, sample_particles(), sample_domain(), {2500.0, 2500.0, 2500.0});
            FAIL("expected std::runtime_error");
        } catch (const std::runtime_error& e) {
            CHECK(std::string(e.what()).find(path) != std::string::npos);
        }
    }

    TEST_CASE("LAMMPS data file for atom_style granular") {
        TempDir dir;
        const Particles p = sample_particles();
        const Domain d = sample_domain();
        const std::vector<double> density = {2500.0, 7874.0, 1000.0 / 3.0};
        const std::string path = dir.file("state.data");
        mrjam::write_lammps_data(path, p, d, density);
        const auto lines = split_lines(slurp(path));

        std::size_t atoms = 0, types = 0;
        int bounds = 0;
        std::size_t atoms_at = 0, velocities_at = 0;
        for (std::size_t l = 1; l < lines.size(); ++l) {  // line 0 is the free-form title
            const auto w = words(lines[l]);
            if (w.size() == 2 && w[1] == "atoms") atoms = std::stoul(w[0]);
            if (w.size() == 3 && w[1] == "atom" && w[2] == "types") types = std::stoul(w[0]);
            if (w.size() == 4 && w[2] == std::string(1, "xyz"[bounds]) + "lo") {
                CHECK(w[3] == std::string(1, "xyz"[bounds]) + "hi");
                CHECK(to_double(w[0]) == d.lo[bounds]);
                CHECK(to_double(w[1]) == d.hi[bounds]);
                ++bounds;
            }
            if (lines[l] == "Atoms") atoms_at = l;
            if (lines[l] == "Velocities") velocities_at = l;
        }
        CHECK(atoms == p.size());
        CHECK(types == density.size());
        CHECK(bounds == 3);
        REQUIRE(atoms_at > 0);
        REQUIRE(velocities_at > atoms_at);

        // Sections: keyword, blank line, one line per atom.
        for (std::size_t i = 0; i < p.size(); ++i) {
            const auto a = words(lines[atoms_at + 2 + i]);
            REQUIRE(a.size() == 7);
            CHECK(std::stoull(a[0]) == p.id[i] + 1);
            CHECK(std::stoul(a[1]) == p.material[i] + 1u);
            CHECK(to_double(a[2]) == 2.0 * p.radius[i]);
            CHECK(to_double(a[3]) == density[p.material[i]]);
            for (int k = 0; k < 3; ++k) CHECK(to_double(a[4 + k]) == p.position[i][k]);

            const auto v = words(lines[velocities_at + 2 + i]);
            REQUIRE(v.size() == 7);
            CHECK(std::stoull(v[0]) == p.id[i] + 1);
            for (int k = 0; k < 3; ++k) {
                CHECK(to_double(v[1 + k]) == p.velocity[i][k]);
                CHECK(to_double(v[4 + k]) == p.angular_velocity[i][k]);
            }
        }
        CHECK(lines.size() == velocities_at + 2 + p.size());

        CHECK_THROWS_AS(mrjam::write_lammps_data(path, p, d, {2500.0}), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::write_lammps_data(path, p, d, {}), std::invalid_argument);
        CHECK_THROWS_AS(mrjam::write_lammps_data(path, p, d, {2500.0, 0.0, 1.0}), std::invalid_argument);
    }

}  // TEST_SUITE("unit")
