#include "shear/shear_stress.hpp"

#include <cmath>

#include "magnetic/magnetic_model.hpp"
#include "terms/drag_term.hpp"
#include "terms/pair_damping_term.hpp"

namespace mrjam {
namespace {

// Calls fn(i, j, k, d, r2) for every listed pair within its range that has a free grain (pairs
// inside one raft carry no stress across the gap), d the pair vector with the image shift.
template <class PairFn>
void for_each_pair_with_free_grain(const Particles& p, const NeighborList& list, PairFn fn) {
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i) {
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            if (p.raft[i] >= 0 && p.raft[j] >= 0) continue;
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const double r2 = norm2(d);
            if (r2 >= list.range_sq[k]) continue;
            fn(i, j, k, d, r2);
        }
    }
}

// Sum over touching grain pairs with a free grain of weight(d, image) f_ij,x, re-evaluating each
// contact law on a copy of its history (the state is not changed). The weight is d_z = z_i - z_j
// for the virial, or which side of the sliding boundary the pair spans for the plane stress.
template <RollingModel Rolling, CohesionModel Cohesion, class Weight>
double contact_moment(const System& s, Weight weight) {
    const Particles& p = s.particles;
    const NeighborList& list = s.contacts;
    const double damping = pair_damping_coefficient(s);
    double sum = 0;
    for_each_pair_with_free_grain(
        p, list, [&](std::size_t i, std::uint32_t j, std::uint32_t k, const Vec3& d, double r2) {
            const Vec3 dv = p.velocity[i] - p.velocity[j] + list.image_velocity(list.image[k]);
            ContactInput in = grain_pair_input(d, r2, p.radius[i], p.radius[j], p.mass[i], p.mass[j], dv,
                                               p.angular_velocity[i], p.angular_velocity[j]);
            in.rolling_inertia = 1.0 / (1.0 / p.rolling_inertia(i) + 1.0 / p.rolling_inertia(j));
            ContactHistory h = list.touching[k] ? list.history[k] : ContactHistory{};
            ContactOutput out;
            hertz_mindlin<Rolling, Cohesion>(s.pairs(p.material[i], p.material[j]), in, h, s.dt, out);
            const double wgt = weight(d, list.image[k]);
            sum += wgt * out.force_on_i.x;
            if (damping > 0) sum += wgt * (-damping * dv.x);
        });
    return sum;
}

template <RollingModel Rolling, class Weight>
double contact_moment_cohesion(const System& s, Weight w) {
    switch (s.physics.cohesion) {
        case CohesionModel::none:
            return contact_moment<Rolling, CohesionModel::none>(s, w);
        case CohesionModel::sjkr:
            return contact_moment<Rolling, CohesionModel::sjkr>(s, w);
        case CohesionModel::dmt:
            return contact_moment<Rolling, CohesionModel::dmt>(s, w);
    }
    return 0;
}

template <class Weight>
double contact_moment_any(const System& s, Weight w) {
    if (!s.physics.contact) return 0;
    switch (s.physics.rolling) {
        case RollingModel::none:
            return contact_moment_cohesion<RollingModel::none>(s, w);
        case RollingModel::epsd:
            return contact_moment_cohesion<RollingModel::epsd>(s, w);
        case RollingModel::sds:
            return contact_moment_cohesion<RollingModel::sds>(s, w);
    }
    return 0;
}

double separation_z(const Vec3& d, std::uint8_t) { return d.z; }

// +1 when the pair reaches through the sliding boundary with the owner below it (the partner's
// image above), -1 with the owner above: the sign that turns f_on_owner into the force on the
// lower grain from the upper one.
double across_boundary(const Vec3&, std::uint8_t image) { return -(image / 9 - 1); }

// The same sum for the magnetic pairs, with the dipole-dipole force of eq. 4.8 (the moments are
// the ones the last force evaluation used, up to the lagged update that followed it).
template <class Weight>
double magnetic_moment_sum(const System& s, Weight weight) {
    if (!s.magnetic.enabled) return 0;
    const Particles& p = s.particles;
    const NeighborList& list = s.magnetic.pairs;
    double sum = 0;
    for_each_pair_with_free_grain(
        p, list, [&](std::size_t i, std::uint32_t j, std::uint32_t k, const Vec3& d, double r2) {
            const double inv_r2 = 1.0 / r2;
            const double c = inv_r2 * std::sqrt(inv_r2) / (4.0 * M_PI);
            const Vec3 mi = p.dipole_moment[i], mj = p.dipole_moment[j];
            const Vec3 force = dipole_pair_force(mi, mj, d, inv_r2, c, dot(mi, d), dot(mj, d));
            sum += weight(d, list.image[k]) * force.x;
        });
    return sum;
}

}  // namespace

ShearStress shear_stress(const System& s, int upper_raft, int lower_raft, int top_wall, int bottom_wall, double z_lower,
                         double z_upper) {
    const Particles& p = s.particles;
    const Vec3 L = s.domain.length();
    const double area = L.x * L.y;
    ShearStress out;
    double f_upper = 0, f_lower = 0, drag_moment = 0, kinetic = 0;
    const double z_mid = 0.5 * (z_lower + z_upper);
    const double viscosity = carrier_viscosity(s);
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.raft[i] == upper_raft && upper_raft >= 0)
            f_upper += p.force[i].x;
        else if (p.raft[i] == lower_raft && lower_raft >= 0)
            f_lower += p.force[i].x;
        else if (p.raft[i] < 0) {
            const Vec3 u = s.flow->velocity(p.position[i], s.time);
            if (viscosity > 0)
                drag_moment +=
                    (p.position[i].z - z_mid) * (-(p.velocity[i].x - u.x) * 6.0 * M_PI * viscosity * p.radius[i]);
            kinetic += p.mass[i] * (p.velocity[i].x - u.x) * p.velocity[i].z;
        }
    }
    if (top_wall >= 0) f_upper += s.walls[top_wall].force.x;
    if (bottom_wall >= 0) f_lower += s.walls[bottom_wall].force.x;
    out.upper = -f_upper / area;
    out.lower = f_lower / area;
    const double volume = area * (z_upper - z_lower);
    out.bulk =
        -(contact_moment_any(s, separation_z) + magnetic_moment_sum(s, separation_z) + drag_moment + kinetic) / volume;
    return out;
}

double lees_edwards_stress(const System& s) {
    const Particles& p = s.particles;
    const Vec3 L = s.domain.length();
    double kinetic = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 u = s.flow->velocity(p.position[i], s.time);
        kinetic += p.mass[i] * (p.velocity[i].x - u.x) * p.velocity[i].z;
    }
    return -(contact_moment_any(s, separation_z) + magnetic_moment_sum(s, separation_z) + kinetic) / (L.x * L.y * L.z);
}

double lees_edwards_boundary_stress(const System& s) {
    const Vec3 L = s.domain.length();
    return (contact_moment_any(s, across_boundary) + magnetic_moment_sum(s, across_boundary)) / (L.x * L.y);
}

ChainState chain_state(const System& s, const Vec3& field_direction) {
    const Particles& p = s.particles;
    const NeighborList& list = s.contacts;
    std::size_t contacts = 0;
    double cos_sum = 0;
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i) {
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const double r2 = norm2(d);
            if (r2 >= list.range_sq[k]) continue;
            ++contacts;
            cos_sum += std::abs(dot(d, field_direction)) / std::sqrt(r2);
        }
    }
    ChainState c;
    c.contacts_per_grain = p.size() ? 2.0 * contacts / p.size() : 0.0;
    c.mean_abs_cos = contacts ? cos_sum / contacts : 0.0;
    return c;
}

}  // namespace mrjam
