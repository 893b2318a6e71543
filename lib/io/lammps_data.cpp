#include "io/lammps_data.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace mrjam {

namespace {

// Shortest decimal form that parses back to exactly the same value.
template <class T>
void put_text(std::string& out, T v) {
    static_assert(std::is_arithmetic_v<T>);
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof(buf), v);
    out.append(buf, r.ptr);
}

void put_words(std::string& out, std::initializer_list<double> values) {
    for (double v : values) {
        out += ' ';
        put_text(out, v);
    }
}

}  // namespace

void write_lammps_data(const std::string& path, const Particles& p, const Domain& domain,
                       const std::vector<double>& density_per_material) {
    const std::size_t n = p.size();
    if (density_per_material.empty()) throw std::invalid_argument("write_lammps_data: density_per_material is empty");
    for (double rho : density_per_material)
        if (!(rho > 0.0)) throw std::invalid_argument("write_lammps_data: densities must be positive");
    constexpr std::uint64_t max_lammps_id = 2147483647;  // tagint is a 32-bit int in LIGGGHTS
    for (std::size_t i = 0; i < n; ++i) {
        if (p.material[i] >= density_per_material.size())
            throw std::invalid_argument("write_lammps_data: particle " + std::to_string(p.id[i]) + " has material " +
                                        std::to_string(p.material[i]) + " but only " +
                                        std::to_string(density_per_material.size()) + " densities were given");
        if (p.id[i] >= max_lammps_id)
            throw std::invalid_argument("write_lammps_data: particle id " + std::to_string(p.id[i]) +
                                        " does not fit a LAMMPS atom id");
    }

    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    if (!file) throw std::runtime_error("mrjam: cannot open LAMMPS data file '" + path + "' for writing");

    constexpr std::size_t flush_threshold = std::size_t{1} << 22;
    auto flush = [&](std::string& buf) {
        file.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
        if (!file) throw std::runtime_error("mrjam: error while writing LAMMPS data file '" + path + "'");
    };

    std::string out;
    out.reserve(std::min<std::size_t>(n * 200, flush_threshold) + 1024);
    out += "LAMMPS data file written by mrjam (atom_style granular: id type diameter density x y z)\n\n";
    put_text(out, n);
    out += " atoms\n";
    put_text(out, density_per_material.size());
    out += " atom types\n\n";
    static const char* const axis_names[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) {
        put_text(out, domain.lo[k]);
        out += ' ';
        put_text(out, domain.hi[k]);
        out += ' ';
        out += axis_names[k];
        out += "lo ";
        out += axis_names[k];
        out += "hi\n";
    }

    // read_data rejects empty sections, so an empty set is the header alone.
    if (n > 0) out += "\nAtoms\n\n";
    for (std::size_t i = 0; i < n; ++i) {
        put_text(out, p.id[i] + 1);
        out += ' ';
        put_text(out, static_cast<unsigned>(p.material[i]) + 1u);
        put_words(out, {2.0 * p.radius[i], density_per_material[p.material[i]], p.position[i].x, p.position[i].y,
                        p.position[i].z});
        out += '\n';
        if (out.size() >= flush_threshold) flush(out);
    }

    if (n > 0) out += "\nVelocities\n\n";
    for (std::size_t i = 0; i < n; ++i) {
        put_text(out, p.id[i] + 1);
        put_words(out, {p.velocity[i].x, p.velocity[i].y, p.velocity[i].z, p.angular_velocity[i].x,
                        p.angular_velocity[i].y, p.angular_velocity[i].z});
        out += '\n';
        if (out.size() >= flush_threshold) flush(out);
    }
    flush(out);
    file.close();
    if (!file) throw std::runtime_error("mrjam: error while closing LAMMPS data file '" + path + "'");
}

}  // namespace mrjam
