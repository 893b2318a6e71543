#include "io/snapshot.hpp"

#include <glib.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace mrjam {

namespace {

// ---- byte order --------------------------------------------------------------------------

template <class T>
T byteswap_value(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    auto bytes = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
    for (std::size_t a = 0, b = sizeof(T) - 1; a < b; ++a, --b) std::swap(bytes[a], bytes[b]);
    return std::bit_cast<T>(bytes);
}

// Appends the bytes of v to out in the requested byte order.
template <class T>
void put(std::string& out, T v, std::endian order) {
    if (order != std::endian::native) v = byteswap_value(v);
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    out.append(raw, sizeof(T));
}

// ---- text numbers ------------------------------------------------------------------------

// Shortest decimal form that parses back to exactly the same double.
void put_text(std::string& out, double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out.append(buf, r.ptr);
}

template <class I>
requires std::is_integral_v<I>
void put_text(std::string& out, I v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out.append(buf, r.ptr);
}

// ---- file output -------------------------------------------------------------------------

class Output {
public:
    explicit Output(const std::string& path) : path_(path), file_(path, std::ios::binary | std::ios::trunc) {
        if (!file_) throw std::runtime_error("mrjam: cannot open snapshot file '" + path_ + "' for writing");
    }

    // Appends buf to the file and empties it.
    void flush(std::string& buf) {
        file_.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
        if (!file_) throw std::runtime_error("mrjam: error while writing snapshot file '" + path_ + "'");
    }

    void close() {
        file_.close();
        if (!file_) throw std::runtime_error("mrjam: error while closing snapshot file '" + path_ + "'");
    }

private:
    std::string path_;
    std::ofstream file_;
};

constexpr std::size_t flush_threshold = std::size_t{1} << 22;

// ---- VTK legacy --------------------------------------------------------------------------

// Writes the 3n doubles of v big-endian, then the newline that ends a legacy data block.
void legacy_vec3s(std::string& out, const std::vector<Vec3>& v) {
    for (const Vec3& x : v) {
        put(out, x.x, std::endian::big);
        put(out, x.y, std::endian::big);
        put(out, x.z, std::endian::big);
    }
    out += '\n';
}

void legacy_field_vec3s(std::string& out, const char* name, const std::vector<Vec3>& v) {
    out += name;
    out += " 3 ";
    put_text(out, v.size());
    out += " double\n";
    legacy_vec3s(out, v);
}

// One scalar per grain, big-endian, as a FIELD array (ids, materials, the modes' extra arrays).
template <class T>
void legacy_field_scalars(std::string& out, const std::string& name, const char* vtk_type, const std::vector<T>& v) {
    out += name;
    out += " 1 ";
    put_text(out, v.size());
    out += ' ';
    out += vtk_type;
    out += '\n';
    for (T x : v) put(out, x, std::endian::big);
    out += '\n';
}

void write_vtk_legacy(Output& file, const Particles& p, long step, double time,
                      const std::vector<IntPointArray>& extra) {
    const std::size_t n = p.size();
    if (n > static_cast<std::size_t>(INT32_MAX / 2))
        throw std::runtime_error("mrjam: too many particles for a legacy VTK file; use vtp");
    std::string out;
    out.reserve(n * 24 + 1024);
    out += "# vtk DataFile Version 3.0\nmrjam step ";
    put_text(out, step);
    out += " time ";
    put_text(out, time);
    out += "\nBINARY\nDATASET POLYDATA\n";
    out += "FIELD FieldData 2\nTIME 1 1 double\n";
    put(out, time, std::endian::big);
    out += "\nCYCLE 1 1 vtktypeint64\n";
    put(out, static_cast<std::int64_t>(step), std::endian::big);
    out += '\n';

    out += "POINTS ";
    put_text(out, n);
    out += " double\n";
    legacy_vec3s(out, p.position);
    file.flush(out);
    if (n == 0) return;  // no cells and no point data: empty sections are not valid

    out += "VERTICES ";
    put_text(out, n);
    out += ' ';
    put_text(out, 2 * n);
    out += '\n';
    for (std::size_t i = 0; i < n; ++i) {
        put(out, std::int32_t{1}, std::endian::big);
        put(out, static_cast<std::int32_t>(i), std::endian::big);
    }
    out += '\n';
    file.flush(out);

    out += "POINT_DATA ";
    put_text(out, n);
    out += '\n';
    // radius and velocity as the active scalars and vectors, the rest as a field: legacy readers
    // keep only the first SCALARS/VECTORS section unless told otherwise, but read every field
    // array.
    out += "SCALARS radius double 1\nLOOKUP_TABLE default\n";
    for (double x : p.radius) put(out, x, std::endian::big);
    out += '\n';
    file.flush(out);
    out += "VECTORS velocity double\n";
    legacy_vec3s(out, p.velocity);
    file.flush(out);
    out += "FIELD FieldData ";
    put_text(out, 5 + extra.size());
    out += '\n';
    legacy_field_scalars(out, "id", "vtktypeuint64", p.id);
    legacy_field_scalars(out, "material", "unsigned_short", p.material);
    file.flush(out);
    legacy_field_vec3s(out, "angular_velocity", p.angular_velocity);
    file.flush(out);
    legacy_field_vec3s(out, "force", p.force);
    file.flush(out);
    legacy_field_vec3s(out, "dipole_moment", p.dipole_moment);
    file.flush(out);
    for (const IntPointArray& a : extra) {
        legacy_field_scalars(out, a.name, "int", a.values);
        file.flush(out);
    }
}

// ---- VTK XML -----------------------------------------------------------------------------

// Base64 (GLib's streaming encoder, loaded with librsvg) fed bytes piecewise; one stream per
// DataArray, as VTK itself writes uncompressed inline data (header and payload encoded as one
// continuous stream).
class Base64 {
public:
    explicit Base64(std::string& out) : out_(out) {}

    void bytes(const void* data, std::size_t size) {
        const std::size_t at = out_.size();
        out_.resize(at + (size / 3 + 1) * 4 + 4);  // what g_base64_encode_step may write
        const gsize written =
            g_base64_encode_step(static_cast<const guchar*>(data), size, FALSE, out_.data() + at, &state_, &save_);
        out_.resize(at + written);
    }

    template <class T>
    void value(T v) {
        if (std::endian::native != std::endian::little) v = byteswap_value(v);
        bytes(&v, sizeof(T));
    }

    void finish() {
        const std::size_t at = out_.size();
        out_.resize(at + 5);  // what g_base64_encode_close may write
        out_.resize(at + g_base64_encode_close(FALSE, out_.data() + at, &state_, &save_));
    }

private:
    std::string& out_;
    gint state_ = 0, save_ = 0;
};

// Opens a binary DataArray, writes the UInt64 byte-count header, calls body(encoder) to encode
// the payload, and closes the element.
template <class Body>
void xml_array(std::string& out, const char* type, const char* name, int components, std::uint64_t payload_bytes,
               Body body) {
    out += "        <DataArray type=\"";
    out += type;
    out += "\"";
    if (name != nullptr) {
        out += " Name=\"";
        out += name;
        out += "\"";
    }
    if (components != 1) {
        out += " NumberOfComponents=\"";
        put_text(out, components);
        out += "\"";
    }
    out += " format=\"binary\">\n          ";
    Base64 enc(out);
    enc.value(payload_bytes);
    body(enc);
    enc.finish();
    out += "\n        </DataArray>\n";
}

void xml_vectors(std::string& out, const char* name, const std::vector<Vec3>& v) {
    xml_array(out, "Float64", name, 3, v.size() * 3 * sizeof(double), [&](Base64& enc) {
        for (const Vec3& x : v) {
            enc.value(x.x);
            enc.value(x.y);
            enc.value(x.z);
        }
    });
}

void write_vtk_xml(Output& file, const Particles& p, long step, double time, const std::vector<IntPointArray>& extra) {
    const std::size_t n = p.size();
    std::string out;
    out.reserve(n * 34 + 2048);
    out += "<?xml version=\"1.0\"?>\n";
    out += "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    out += "  <PolyData>\n";
    out += "    <FieldData>\n";
    out += "      <DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">";
    put_text(out, time);
    out += "</DataArray>\n";
    out += "      <DataArray type=\"Int64\" Name=\"CYCLE\" NumberOfTuples=\"1\" format=\"ascii\">";
    put_text(out, step);
    out += "</DataArray>\n";
    out += "    </FieldData>\n";
    out += "    <Piece NumberOfPoints=\"";
    put_text(out, n);
    out += "\" NumberOfVerts=\"";
    put_text(out, n);
    out += "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";

    out += "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
    xml_array(out, "Float64", "radius", 1, n * sizeof(double), [&](Base64& enc) {
        for (double r : p.radius) enc.value(r);
    });
    file.flush(out);
    xml_array(out, "UInt64", "id", 1, n * sizeof(std::uint64_t), [&](Base64& enc) {
        for (std::uint64_t v : p.id) enc.value(v);
    });
    file.flush(out);
    xml_array(out, "UInt16", "material", 1, n * sizeof(std::uint16_t), [&](Base64& enc) {
        for (std::uint16_t v : p.material) enc.value(v);
    });
    file.flush(out);
    xml_vectors(out, "velocity", p.velocity);
    file.flush(out);
    xml_vectors(out, "angular_velocity", p.angular_velocity);
    file.flush(out);
    xml_vectors(out, "force", p.force);
    file.flush(out);
    xml_vectors(out, "dipole_moment", p.dipole_moment);
    file.flush(out);
    for (const IntPointArray& a : extra) {
        xml_array(out, "Int32", a.name.c_str(), 1, n * sizeof(std::int32_t), [&](Base64& enc) {
            for (std::int32_t v : a.values) enc.value(v);
        });
        file.flush(out);
    }
    out += "      </PointData>\n";

    out += "      <Points>\n";
    xml_vectors(out, "Points", p.position);
    file.flush(out);
    out += "      </Points>\n";

    out += "      <Verts>\n";
    xml_array(out, "Int64", "connectivity", 1, n * sizeof(std::int64_t), [&](Base64& enc) {
        for (std::size_t i = 0; i < n; ++i) enc.value(static_cast<std::int64_t>(i));
    });
    file.flush(out);
    xml_array(out, "Int64", "offsets", 1, n * sizeof(std::int64_t), [&](Base64& enc) {
        for (std::size_t i = 0; i < n; ++i) enc.value(static_cast<std::int64_t>(i + 1));
    });
    file.flush(out);
    out += "      </Verts>\n";
    out += "    </Piece>\n  </PolyData>\n</VTKFile>\n";
    file.flush(out);
}

// ---- LAMMPS dump -------------------------------------------------------------------------

void put_vec(std::string& out, const Vec3& v) {
    out += ' ';
    put_text(out, v.x);
    out += ' ';
    put_text(out, v.y);
    out += ' ';
    put_text(out, v.z);
}

void write_lammps_dump(Output& file, const Particles& p, const Domain& d, long step,
                       const std::vector<IntPointArray>& extra) {
    const std::size_t n = p.size();
    std::string out;
    out.reserve(std::min<std::size_t>(n * 400, flush_threshold) + 1024);
    out += "ITEM: TIMESTEP\n";
    put_text(out, step);
    out += "\nITEM: NUMBER OF ATOMS\n";
    put_text(out, n);
    out += "\nITEM: BOX BOUNDS";
    for (int k = 0; k < 3; ++k) out += d.periodic[k] ? " pp" : " ff";
    out += '\n';
    for (int k = 0; k < 3; ++k) {
        put_text(out, d.lo[k]);
        out += ' ';
        put_text(out, d.hi[k]);
        out += '\n';
    }
    out += "ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz fx fy fz mux muy muz";
    for (const IntPointArray& a : extra) {
        out += ' ';
        out += a.name;
    }
    out += '\n';
    for (std::size_t i = 0; i < n; ++i) {
        put_text(out, p.id[i]);
        out += ' ';
        put_text(out, static_cast<unsigned>(p.material[i]) + 1u);
        out += ' ';
        put_text(out, p.radius[i]);
        put_vec(out, p.position[i]);
        put_vec(out, p.velocity[i]);
        put_vec(out, p.angular_velocity[i]);
        put_vec(out, p.force[i]);
        put_vec(out, p.dipole_moment[i]);
        for (const IntPointArray& a : extra) {
            out += ' ';
            put_text(out, a.values[i]);
        }
        out += '\n';
        if (out.size() >= flush_threshold) file.flush(out);
    }
    file.flush(out);
}

}  // namespace

SnapshotFormat snapshot_format_from_name(const std::string& name) {
    if (name == "vtk") return SnapshotFormat::vtk_legacy;
    if (name == "vtp") return SnapshotFormat::vtk_xml;
    if (name == "lammps") return SnapshotFormat::lammps_dump;
    throw std::invalid_argument("unknown snapshot format '" + name + "' (valid: vtk, vtp, lammps)");
}

std::string snapshot_extension(SnapshotFormat format) {
    switch (format) {
        case SnapshotFormat::vtk_legacy:
            return ".vtk";
        case SnapshotFormat::vtk_xml:
            return ".vtp";
        case SnapshotFormat::lammps_dump:
            return ".dump";
    }
    throw std::invalid_argument("unknown snapshot format");
}

void write_snapshot(const std::string& path, SnapshotFormat format, const Particles& particles, const Domain& domain,
                    long step, double time, const std::vector<IntPointArray>& extra) {
    // Checked before the file is opened, so a bad call leaves no half-written snapshot behind.
    for (const IntPointArray& a : extra) {
        if (a.values.size() != particles.size())
            throw std::invalid_argument("snapshot array '" + a.name + "' has " + std::to_string(a.values.size()) +
                                        " values for " + std::to_string(particles.size()) + " particles");
        if (a.name.empty() || a.name.find_first_of(" \t\n\"<>&") != std::string::npos)
            throw std::invalid_argument("snapshot array name '" + a.name + "' must be one token without markup");
    }
    Output file(path);
    switch (format) {
        case SnapshotFormat::vtk_legacy:
            write_vtk_legacy(file, particles, step, time, extra);
            break;
        case SnapshotFormat::vtk_xml:
            write_vtk_xml(file, particles, step, time, extra);
            break;
        case SnapshotFormat::lammps_dump:
            write_lammps_dump(file, particles, domain, step, extra);
            break;
    }
    file.close();
}

}  // namespace mrjam
