#include "magnetic/external_field.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace mrjam {

double UniformField::strength(double time) const {
    if (time < on_ || time >= off_) return 0.0;
    if (ramp_ > 0 && time < on_ + ramp_) return (time - on_) / ramp_;
    return 1.0;
}

FieldMap::FieldMap(std::array<int, 3> count, Vec3 origin, Vec3 spacing, std::vector<Vec3> values, double scale)
    : count_(count), origin_(origin), spacing_(spacing), values_(std::move(values)), scale_(scale) {
    for (int k = 0; k < 3; ++k) {
        if (count_[k] < 2) throw std::invalid_argument("a field map needs at least 2 nodes along each axis");
        if (!(spacing_[k] > 0)) throw std::invalid_argument("field map node spacing must be positive");
    }
    if (values_.size() != static_cast<std::size_t>(count_[0]) * count_[1] * count_[2])
        throw std::invalid_argument("field map holds " + std::to_string(values_.size()) + " values for " +
                                    std::to_string(count_[0] * count_[1] * count_[2]) + " nodes");
}

Vec3 FieldMap::upper_corner() const {
    return {origin_.x + spacing_.x * (count_[0] - 1), origin_.y + spacing_.y * (count_[1] - 1),
            origin_.z + spacing_.z * (count_[2] - 1)};
}

double FieldMap::largest_flux_density() const {
    double largest = 0;
    for (const Vec3& b : values_) largest = std::max(largest, norm(b));
    return largest * scale_;
}

FieldMap FieldMap::read(const std::string& path, double scale) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open field map " + path);
    std::string line;
    int line_no = 0;
    auto next = [&](const char* what) {
        do {
            if (!std::getline(in, line)) throw std::runtime_error(path + ": ended before " + what);
            ++line_no;
        } while (line.empty() || line[0] == '#');
        return std::istringstream(line);
    };
    auto bad = [&](const char* what) {
        return std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " + what);
    };
    {
        auto s = next("the header");
        std::string magic;
        int version = 0;
        if (!(s >> magic >> version) || magic != "mrjam-fieldmap" || version != 1) throw bad("\"mrjam-fieldmap 1\"");
    }
    std::array<int, 3> count{};
    Vec3 origin, spacing;
    {
        auto s = next("the node counts");
        if (!(s >> count[0] >> count[1] >> count[2])) throw bad("three node counts");
    }
    {
        auto s = next("the origin");
        if (!(s >> origin.x >> origin.y >> origin.z)) throw bad("the origin x0 y0 z0");
    }
    {
        auto s = next("the spacing");
        if (!(s >> spacing.x >> spacing.y >> spacing.z)) throw bad("the spacing dx dy dz");
    }
    if (!(spacing.x > 0 && spacing.y > 0 && spacing.z > 0)) throw bad("a positive spacing dx dy dz (metres)");
    if (count[0] < 2 || count[1] < 2 || count[2] < 2 || count[0] > 4096 || count[1] > 4096 || count[2] > 4096)
        throw std::runtime_error(path + ": node counts must be between 2 and 4096");
    // Read node by node, not allocated from the header: a damaged header must not ask for terabytes.
    const std::size_t nodes = static_cast<std::size_t>(count[0]) * count[1] * count[2];
    std::vector<Vec3> values;
    for (std::size_t k = 0; k < nodes; ++k) {
        auto s = next("more field values");
        Vec3 v;
        if (!(s >> v.x >> v.y >> v.z) || !finite(v)) throw bad("Bx By Bz (finite numbers, tesla)");
        values.push_back(v);
    }
    // More values than the header's nodes usually means a wrong header (the grid read skewed).
    while (std::getline(in, line)) {
        ++line_no;
        if (line.find_first_not_of(" \t\r") != std::string::npos && line[0] != '#')
            throw std::runtime_error(path + ":" + std::to_string(line_no) + ": more values than the header's " +
                                     std::to_string(count[0]) + " x " + std::to_string(count[1]) + " x " +
                                     std::to_string(count[2]) + " nodes; check the node counts");
    }
    return FieldMap(count, origin, spacing, std::move(values), scale);
}

void FieldMap::write(const std::string& path) const {
    std::ofstream out(path);
    if (!out) throw std::runtime_error("cannot write field map " + path);
    out << std::setprecision(17) << "mrjam-fieldmap 1\n"
        << count_[0] << ' ' << count_[1] << ' ' << count_[2] << '\n'
        << origin_.x << ' ' << origin_.y << ' ' << origin_.z << '\n'
        << spacing_.x << ' ' << spacing_.y << ' ' << spacing_.z << '\n';
    for (const Vec3& v : values_) out << v.x << ' ' << v.y << ' ' << v.z << '\n';
}

FieldMap::Cell FieldMap::locate(const Vec3& x) const {
    Cell c{};
    for (int k = 0; k < 3; ++k) {
        const double u = (x[k] - origin_[k]) / spacing_[k];
        const double top = count_[k] - 1;
        c.outside[k] = u < 0 || u > top;
        const double clamped = std::clamp(u, 0.0, top);
        c.i[k] = std::min(static_cast<int>(std::floor(clamped)), count_[k] - 2);
        c.f[k] = clamped - c.i[k];
    }
    return c;
}

Vec3 FieldMap::flux_density(const Vec3& x, double) const {
    const Cell c = locate(x);
    Vec3 b{};
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double w = (dx ? c.f[0] : 1 - c.f[0]) * (dy ? c.f[1] : 1 - c.f[1]) * (dz ? c.f[2] : 1 - c.f[2]);
                b += node(c.i[0] + dx, c.i[1] + dy, c.i[2] + dz) * w;
            }
    return b * scale_;
}

Gradient FieldMap::gradient(const Vec3& x, double) const {
    const Cell c = locate(x);
    Gradient g{};
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const double wx = dx ? c.f[0] : 1 - c.f[0], wy = dy ? c.f[1] : 1 - c.f[1],
                             wz = dz ? c.f[2] : 1 - c.f[2];
                const double sx = dx ? 1 : -1, sy = dy ? 1 : -1, sz = dz ? 1 : -1;
                // d/dx of the trilinear weights; zero across a face the point lies beyond.
                const double d[3] = {c.outside[0] ? 0 : sx * wy * wz / spacing_.x,
                                     c.outside[1] ? 0 : wx * sy * wz / spacing_.y,
                                     c.outside[2] ? 0 : wx * wy * sz / spacing_.z};
                const Vec3& b = node(c.i[0] + dx, c.i[1] + dy, c.i[2] + dz);
                for (int l = 0; l < 3; ++l)
                    for (int k = 0; k < 3; ++k) g[l][k] += b[l] * d[k] * scale_;
            }
    return g;
}

}  // namespace mrjam
