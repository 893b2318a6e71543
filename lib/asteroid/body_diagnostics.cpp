#include "asteroid/body_diagnostics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "asteroid/body_spin.hpp"

namespace mrjam {

void equivalent_ellipsoid(const Particles& p, const std::vector<std::size_t>& members, Vec3& centre,
                          double semi_axes[3]) {
    double m = 0;
    Vec3 x{};
    for (std::size_t i : members) {
        m += p.mass[i];
        x += p.position[i] * p.mass[i];
    }
    centre = x / m;
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (std::size_t i : members) {
        const Vec3 r = p.position[i] - centre;
        const Eigen::Vector3d v(r.x, r.y, r.z);
        cov += p.mass[i] * (v * v.transpose() + Eigen::Matrix3d::Identity() * (p.radius[i] * p.radius[i] / 5.0));
    }
    cov /= m;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov, Eigen::EigenvaluesOnly);
    for (int k = 0; k < 3; ++k) semi_axes[k] = std::sqrt(5.0 * std::max(0.0, eig.eigenvalues()[2 - k]));
}

namespace {

// Grain volume fraction of the body in four shells of a quarter of R_eq = (abc)^(1/3) each, by
// grain centre: the outer shell of a flattened body is partly empty, which it then shows.
std::vector<double> shell_packing(const Particles& p, const std::vector<std::size_t>& members, const Vec3& centre,
                                  double r_eq) {
    std::vector<double> volume(4, 0.0);
    for (std::size_t i : members) {
        const double r = norm(p.position[i] - centre) / r_eq;
        const std::size_t k = std::min<std::size_t>(3, static_cast<std::size_t>(std::max(0.0, r) * 4.0));
        if (r < 1.0) volume[k] += 4.0 / 3.0 * M_PI * std::pow(p.radius[i], 3);
    }
    for (std::size_t k = 0; k < 4; ++k) {
        const double lo = r_eq * k / 4.0, hi = r_eq * (k + 1) / 4.0;
        volume[k] /= 4.0 / 3.0 * M_PI * (hi * hi * hi - lo * lo * lo);
    }
    return volume;
}

}  // namespace

BodyDiagnostics diagnose_body(const System& s, double initial_mass) {
    const Particles& p = s.particles;
    BodyDiagnostics d;
    d.time = s.time;
    d.grains = p.size();
    if (p.size() == 0) return d;
    // The body is the heaviest cluster, not the most numerous: a seed grain alone can outweigh
    // hundreds of cloud grains.
    const BodyMembers members = heaviest_cluster(s);
    const std::vector<std::size_t>& body = members.grains;
    d.body_grains = body.size();
    double mass = 0, grain_volume = 0, moment_sum = 0;
    Vec3 moment{};
    for (std::size_t i : body) {
        mass += p.mass[i];
        grain_volume += 4.0 / 3.0 * M_PI * std::pow(p.radius[i], 3);
        moment += p.dipole_moment[i];
        moment_sum += norm(p.dipole_moment[i]);
    }
    d.body_mass_fraction = mass / initial_mass;
    equivalent_ellipsoid(p, body, d.centre, d.semi_axes);
    const double volume = 4.0 / 3.0 * M_PI * d.semi_axes[0] * d.semi_axes[1] * d.semi_axes[2];
    d.bulk_density = volume > 0 ? mass / volume : 0;
    d.porosity = volume > 0 ? 1.0 - grain_volume / volume : 0;
    d.shell_packing = shell_packing(p, body, d.centre, std::cbrt(d.semi_axes[0] * d.semi_axes[1] * d.semi_axes[2]));
    d.net_dipole = norm(moment);
    d.dipole_alignment = moment_sum > 0 ? d.net_dipole / moment_sum : 0;
    const std::size_t outside = p.size() - body.size();
    std::size_t grouped = 0, clumped = 0;
    for (std::size_t size : members.other_cluster_sizes) {
        if (size >= 2) grouped += size;
        if (size > 10) clumped += size;
    }
    d.outside_grouped = outside > 0 ? static_cast<double>(grouped) / outside : 0;
    d.outside_clumped = outside > 0 ? static_cast<double>(clumped) / outside : 0;
    return d;
}

nlohmann::json to_json(const BodyDiagnostics& d) {
    return {{"time_s", d.time},
            {"grains", d.grains},
            {"body_grains", d.body_grains},
            {"body_mass_fraction", d.body_mass_fraction},
            {"body_centre_m", {d.centre.x, d.centre.y, d.centre.z}},
            {"semi_axes_m", {d.semi_axes[0], d.semi_axes[1], d.semi_axes[2]}},
            {"bulk_density_kg_m3", d.bulk_density},
            {"porosity", d.porosity},
            {"shell_packing_fraction", d.shell_packing},
            {"net_dipole_A_m2", d.net_dipole},
            {"dipole_alignment", d.dipole_alignment},
            {"outside_in_chains_or_clumps", d.outside_grouped},
            {"outside_in_clumps_over_10", d.outside_clumped}};
}

}  // namespace mrjam
