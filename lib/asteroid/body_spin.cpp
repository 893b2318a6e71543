#include "asteroid/body_spin.hpp"

#include <algorithm>
#include <functional>

#include "contact_clusters.hpp"

namespace mrjam {

BodyMembers heaviest_cluster(const System& s) {
    const Particles& p = s.particles;
    BodyMembers b;
    if (p.size() == 0) return b;
    const ContactClusters clusters = contact_clusters(s);
    b.cluster_masses.assign(clusters.size.size(), 0.0);
    for (std::size_t i = 0; i < p.size(); ++i) b.cluster_masses[clusters.label[i]] += p.mass[i];
    const std::size_t heaviest = static_cast<std::size_t>(
        std::max_element(b.cluster_masses.begin(), b.cluster_masses.end()) - b.cluster_masses.begin());
    for (std::size_t i = 0; i < p.size(); ++i)
        if (clusters.label[i] == heaviest) b.grains.push_back(i);
    for (std::size_t c = 0; c < clusters.size.size(); ++c)
        if (c != heaviest) b.other_cluster_sizes.push_back(clusters.size[c]);
    std::sort(b.cluster_masses.begin(), b.cluster_masses.end(), std::greater<>());
    return b;
}

namespace {

void centre_of(const Particles& p, const std::vector<std::size_t>& members, Vec3& x, Vec3& v) {
    double m = 0;
    x = {};
    v = {};
    for (std::size_t i : members) {
        m += p.mass[i];
        x += p.position[i] * p.mass[i];
        v += p.velocity[i] * p.mass[i];
    }
    x = x / m;
    v = v / m;
}

}  // namespace

BodySpin body_spin(const Particles& p, const std::vector<std::size_t>& members) {
    BodySpin b;
    if (members.empty()) return b;
    Vec3 xc, vc;
    centre_of(p, members, xc, vc);
    double l_z = 0;
    for (std::size_t i : members) {
        const Vec3 r = p.position[i] - xc, v = p.velocity[i] - vc;
        l_z += p.mass[i] * (r.x * v.y - r.y * v.x) + p.inertia[i] * p.angular_velocity[i].z;
        b.i_zz += p.mass[i] * (r.x * r.x + r.y * r.y) + p.inertia[i];
    }
    b.rate = l_z / b.i_zz;
    return b;
}

Vec3 spin_up_body(Particles& p, const std::vector<std::size_t>& members, double delta_omega) {
    if (members.empty()) return {};
    Vec3 xc, vc;
    centre_of(p, members, xc, vc);
    const Vec3 w{0, 0, delta_omega};
    Vec3 added{};
    for (std::size_t i : members) {
        const Vec3 r = p.position[i] - xc, dv = cross(w, r);
        p.velocity[i] += dv;
        p.angular_velocity[i] += w;
        added += cross(r, dv) * p.mass[i] + w * p.inertia[i];
    }
    return added;
}

}  // namespace mrjam
