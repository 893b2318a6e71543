#include "asteroid/cloud.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/random.hpp"
#include "gravity/self_gravity.hpp"
#include "particles.hpp"

namespace mrjam {

std::vector<Vec3> lattice_cloud(long count, double spacing, double diameter, double clearance) {
    // A cube of sites large enough that its inscribed sphere holds `count` sites beyond the seed.
    const double seed_sites = clearance > 0 ? 4.0 / 3.0 * M_PI * std::pow(clearance / spacing + 1.0, 3) : 0.0;
    const long half = static_cast<long>(std::ceil(std::cbrt(3.0 * (count + seed_sites) / (4.0 * M_PI)))) + 2;
    struct Site {
        long i, j, k;
        double r2;
    };
    std::vector<Site> sites;
    for (long k = -half; k <= half; ++k)
        for (long j = -half; j <= half; ++j)
            for (long i = -half; i <= half; ++i) {
                const double r2 = spacing * spacing * static_cast<double>(i * i + j * j + k * k);
                const double reach = clearance + 0.5 * diameter;
                if (clearance > 0 && r2 < reach * reach) continue;
                sites.push_back({i, j, k, r2});
            }
    std::sort(sites.begin(), sites.end(), [](const Site& a, const Site& b) {
        return std::tie(a.r2, a.k, a.j, a.i) < std::tie(b.r2, b.k, b.j, b.i);
    });
    sites.resize(static_cast<std::size_t>(std::min<long>(count, static_cast<long>(sites.size()))));
    std::vector<Vec3> out;
    out.reserve(sites.size());
    for (const Site& s : sites)
        out.push_back(Vec3{static_cast<double>(s.i), static_cast<double>(s.j), static_cast<double>(s.k)} * spacing);
    return out;
}

namespace {

Vec3 centre_of_mass(const Particles& p, Vec3* velocity) {
    Vec3 x{}, v{};
    double m = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        x += p.position[i] * p.mass[i];
        v += p.velocity[i] * p.mass[i];
        m += p.mass[i];
    }
    if (velocity) *velocity = v / m;
    return x / m;
}

}  // namespace

void give_cloud_motion(Particles& p, const std::vector<char>& thermal, double thermal_speed, double spin,
                       std::uint64_t seed) {
    Rng rng(seed ^ 0x9e3779b97f4a7c15ull);  // a stream of its own, apart from the placement's
    for (std::size_t i = 0; i < p.size(); ++i) {
        p.velocity[i] = {};
        p.angular_velocity[i] = {};
        if (!thermal[i]) continue;
        p.velocity[i] = Vec3{rng.normal(), rng.normal(), rng.normal()} * thermal_speed;
        const double spin_sigma = thermal_speed * std::sqrt(p.mass[i] / p.inertia[i]);
        p.angular_velocity[i] = Vec3{rng.normal(), rng.normal(), rng.normal()} * spin_sigma;
    }
    Vec3 v_com;
    const Vec3 x_com = centre_of_mass(p, &v_com);
    const Vec3 omega{0, 0, spin};
    for (std::size_t i = 0; i < p.size(); ++i) p.velocity[i] += cross(omega, p.position[i] - x_com) - v_com;
}

CloudEnergetics cloud_energetics(const Particles& p, double spin, double G) {
    CloudEnergetics e;
    Vec3 v_com;
    const Vec3 x_com = centre_of_mass(p, &v_com);
    double i_zz = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 r = p.position[i] - x_com, v = p.velocity[i] - v_com;
        e.mass += p.mass[i];
        e.radius = std::max(e.radius, norm(r) + p.radius[i]);
        e.kinetic += 0.5 * p.mass[i] * norm2(v) + 0.5 * p.inertia[i] * norm2(p.angular_velocity[i]);
        i_zz += p.mass[i] * (r.x * r.x + r.y * r.y) + p.inertia[i];
    }
    e.spin_kinetic = 0.5 * i_zz * spin * spin;
    e.binding = -gravitational_energy(p, G);
    e.virial_ratio = e.binding > 0 ? e.kinetic / e.binding : INFINITY;
    e.orbital_rate = std::sqrt(G * e.mass / (e.radius * e.radius * e.radius));
    e.spin_ratio = std::fabs(spin) / e.orbital_rate;
    const double mean_density = e.mass / (4.0 / 3.0 * M_PI * e.radius * e.radius * e.radius);
    e.free_fall_time = std::sqrt(3.0 * M_PI / (32.0 * G * mean_density));
    return e;
}

}  // namespace mrjam
