#include "gravity/self_gravity.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "particles.hpp"

namespace mrjam {

namespace {

constexpr int kMaxDepth = 48;  // below this a cube is 2^-48 of the cloud: grains that close share a leaf

int octant_of(const Vec3& x, const Vec3& centre) {
    return (x.x >= centre.x ? 1 : 0) | (x.y >= centre.y ? 2 : 0) | (x.z >= centre.z ? 4 : 0);
}

Vec3 octant_centre(const Vec3& centre, double side, int k) {
    const double h = 0.25 * side;
    return {centre.x + (k & 1 ? h : -h), centre.y + (k & 2 ? h : -h), centre.z + (k & 4 ? h : -h)};
}

// Adds m (3 s s - s^2 I) to a packed quadrupole.
void add_quadrupole(double* q, double m, const Vec3& s) {
    const double s2 = dot(s, s);
    q[0] += m * (3 * s.x * s.x - s2);
    q[1] += m * (3 * s.y * s.y - s2);
    q[2] += m * (3 * s.z * s.z - s2);
    q[3] += m * 3 * s.x * s.y;
    q[4] += m * 3 * s.x * s.z;
    q[5] += m * 3 * s.y * s.z;
}

}  // namespace

void direct_gravity(const Particles& p, double G, std::vector<Vec3>& acceleration, int threads) {
    const std::size_t n = p.size();
    acceleration.assign(n, Vec3{});
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 a{};
        for (std::size_t j = 0; j < n; ++j)
            if (j != i) a += pair_gravity(p.position[j] - p.position[i], p.mass[j], p.radius[i] + p.radius[j], G);
        acceleration[i] = a;
    }
}

double gravitational_energy(const Particles& p, double G) {
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j)
            e -= G * p.mass[i] * p.mass[j] / std::max(norm(p.position[j] - p.position[i]), p.radius[i] + p.radius[j]);
    return e;
}

void GravityTree::build(const Particles& p) {
    nodes_.clear();
    order_.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) order_[i] = i;
    if (p.size() == 0) return;
    Vec3 lo = p.position[0], hi = p.position[0];
    for (const Vec3& x : p.position) {
        lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
        hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
    }
    const double side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) * (1 + 1e-12) + 1e-300;
    nodes_.reserve(2 * p.size() / std::max(1, settings_.leaf_size) + 16);
    make_node(p, 0, p.size(), (lo + hi) * 0.5, side, 0);
    compute_moments(p, 0);
}

int GravityTree::make_node(const Particles& p, std::size_t begin, std::size_t end, const Vec3& centre, double side,
                           int depth) {
    Node n;
    n.centre = centre;
    n.side = side;
    n.begin = begin;
    n.end = end;
    nodes_.push_back(n);
    const int index = static_cast<int>(nodes_.size()) - 1;
    if (end - begin > static_cast<std::size_t>(settings_.leaf_size) && depth < kMaxDepth) split(p, index, depth);
    return index;
}

// Sorts the node's grains into its eight octants (a counting sort of order_) and makes a child
// for each octant that has grains.
void GravityTree::split(const Particles& p, int node, int depth) {
    const Vec3 centre = nodes_[node].centre;
    const double side = nodes_[node].side;
    const std::size_t begin = nodes_[node].begin, end = nodes_[node].end;
    std::array<std::size_t, 9> start{};
    for (std::size_t k = begin; k < end; ++k) ++start[octant_of(p.position[order_[k]], centre) + 1];
    for (int k = 0; k < 8; ++k) start[k + 1] += start[k];
    std::vector<std::size_t> sorted(end - begin);
    std::array<std::size_t, 8> fill{};
    for (int k = 0; k < 8; ++k) fill[k] = start[k];
    for (std::size_t k = begin; k < end; ++k) sorted[fill[octant_of(p.position[order_[k]], centre)]++] = order_[k];
    std::copy(sorted.begin(), sorted.end(), order_.begin() + static_cast<std::ptrdiff_t>(begin));
    // Children are made in two passes so that they sit next to each other in nodes_.
    std::array<int, 8> made{};
    int first = -1, count = 0;
    for (int k = 0; k < 8; ++k) {
        if (start[k + 1] == start[k]) continue;
        Node c;
        c.centre = octant_centre(centre, side, k);
        c.side = 0.5 * side;
        c.begin = begin + start[k];
        c.end = begin + start[k + 1];
        nodes_.push_back(c);
        made[count] = static_cast<int>(nodes_.size()) - 1;
        if (first < 0) first = made[count];
        ++count;
    }
    nodes_[node].first_child = first;
    nodes_[node].children = count;
    for (int k = 0; k < count; ++k) {
        const Node& c = nodes_[made[k]];
        if (c.end - c.begin > static_cast<std::size_t>(settings_.leaf_size) && depth + 1 < kMaxDepth)
            split(p, made[k], depth + 1);
    }
}

void GravityTree::compute_moments(const Particles& p, int node) {
    Node& n = nodes_[node];
    n.mass = 0;
    Vec3 weighted{};
    if (n.children == 0) {
        for (std::size_t k = n.begin; k < n.end; ++k) {
            n.mass += p.mass[order_[k]];
            weighted += p.position[order_[k]] * p.mass[order_[k]];
        }
        n.com = n.mass > 0 ? weighted / n.mass : n.centre;
        for (double& v : n.q) v = 0;
        for (std::size_t k = n.begin; k < n.end; ++k)
            add_quadrupole(n.q, p.mass[order_[k]], p.position[order_[k]] - n.com);
    } else {
        for (int c = n.first_child; c < n.first_child + n.children; ++c) {
            compute_moments(p, c);
            nodes_[node].mass += nodes_[c].mass;
            weighted += nodes_[c].com * nodes_[c].mass;
        }
        Node& m = nodes_[node];  // compute_moments may not grow nodes_, but keep the reference fresh
        m.com = m.mass > 0 ? weighted / m.mass : m.centre;
        for (double& v : m.q) v = 0;
        for (int c = m.first_child; c < m.first_child + m.children; ++c) {
            for (int k = 0; k < 6; ++k) m.q[k] += nodes_[c].q[k];
            add_quadrupole(m.q, nodes_[c].mass, nodes_[c].com - m.com);
        }
    }
    Node& m = nodes_[node];
    m.reach = m.side / settings_.opening_angle + norm(m.com - m.centre);
}

// The tree walk for grain i: a node far enough (beyond its reach) acts through its monopole and
// quadrupole, a nearer leaf grain by grain. With r from the node's centre of mass to the grain
// and the potential -G (M / r + r.Q.r / (2 r^5)), the acceleration is
// -G M r / r^3 + G Q r / r^5 - (5/2) G (r.Q.r) r / r^7.
Vec3 GravityTree::acceleration_of(const Particles& p, std::size_t i, double G) const {
    const Vec3 x = p.position[i];
    Vec3 a{};
    int stack[8 * kMaxDepth + 8];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        const Vec3 r = x - n.com;
        const double r2 = dot(r, r);
        if (r2 > n.reach * n.reach) {
            const double inv_r2 = 1 / r2, inv_r = std::sqrt(inv_r2), inv_r3 = inv_r * inv_r2;
            a -= r * (G * n.mass * inv_r3);
            if (settings_.quadrupole) {
                const Vec3 qr{n.q[0] * r.x + n.q[3] * r.y + n.q[4] * r.z, n.q[3] * r.x + n.q[1] * r.y + n.q[5] * r.z,
                              n.q[4] * r.x + n.q[5] * r.y + n.q[2] * r.z};
                const double inv_r5 = inv_r3 * inv_r2;
                a += qr * (G * inv_r5) - r * (2.5 * G * dot(r, qr) * inv_r5 * inv_r2);
            }
        } else if (n.children == 0) {
            for (std::size_t k = n.begin; k < n.end; ++k) {
                const std::size_t j = order_[k];
                if (j != i) a += pair_gravity(p.position[j] - x, p.mass[j], p.radius[i] + p.radius[j], G);
            }
        } else {
            for (int c = n.first_child; c < n.first_child + n.children; ++c) stack[top++] = c;
        }
    }
    return a;
}

void GravityTree::accelerations(const Particles& p, double G, std::vector<Vec3>& acceleration, int threads) const {
    acceleration.assign(p.size(), Vec3{});
    if (nodes_.empty()) return;
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads)
    for (std::size_t i = 0; i < p.size(); ++i) acceleration[i] = acceleration_of(p, i, G);
}

}  // namespace mrjam
