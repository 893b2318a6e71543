#pragma once
// The contact law of one touching pair (grain-grain or grain-wall), header-only so the pair loop
// inlines it. Rolling and cohesion models are template parameters: a scene that names neither
// compiles them out of the hot loop, so no virtual call or branch is paid per pair.
//
// Normal:     F_n = k_n d - gamma_n v_n, k_n = 4/3 Y* sqrt(R* d),
//             gamma_n = 2 sqrt(5/6) beta sqrt(S_n m*), S_n = 2 Y* sqrt(R* d)       (eq. 2.1)
// Tangential: Mindlin spring k_t = 8 G* sqrt(R* d) on the accumulated tangential displacement,
//             dashpot 2 sqrt(5/6) beta sqrt(k_t m*), capped at mu |F_n| (Coulomb).
// Rolling:    EPSD (Ai et al. 2011, model C) or SDS (Luding; LAMMPS "rolling sds", eq. 4.4).
// Cohesion:   SJKR F = k_c A (A = area of the overlap circle) or DMT F = 4 pi gamma R* (eq. 4.5).
#include <cmath>

#include "contact/material.hpp"
#include "core/vec3.hpp"

namespace mrjam {

enum class RollingModel { none, epsd, sds };
enum class CohesionModel { none, sjkr, dmt };

// What a contact remembers between steps.
struct ContactHistory {
    Vec3 tangential{};  // accumulated tangential displacement (m)
    Vec3 rolling{};     // EPSD: spring torque (N m); SDS: accumulated rolling displacement (m)
};

// Kinematics of one contact, prepared by the caller.
struct ContactInput {
    Vec3 normal;                // unit vector from j to i
    double overlap;             // d = R_i + R_j - |x_i - x_j| > 0
    double distance;            // |x_i - x_j|; for a wall, R_i - d
    double radius_i, radius_j;  // radius_j unused for a wall
    double arm_i, arm_j;        // centre to contact point (arm_j unused for a wall)
    double reduced_radius;      // R* (R_i for a wall)
    double reduced_mass;        // m* (m_i for a wall)
    double rolling_inertia;     // EPSD I_r (Ai et al. eq. 16)
    Vec3 contact_velocity;      // velocity of i relative to j at the contact point
    Vec3 relative_spin;         // omega_i - omega_j
    bool wall;
};

// The kinematics of a grain-grain contact from the pair's separation d = x_i - x_j (image shift
// included), r2 = |d|^2 < (R_i + R_j)^2, and relative velocity dv = v_i - v_j (image velocity
// included). The rolling inertia is left to the caller: only EPSD reads it.
inline ContactInput grain_pair_input(const Vec3& d, double r2, double ri, double rj, double mi, double mj,
                                     const Vec3& dv, const Vec3& wi, const Vec3& wj) {
    const double dist = std::sqrt(r2), rsum = ri + rj;
    ContactInput in;
    in.normal = d * (1.0 / dist);
    in.overlap = rsum - dist;
    in.distance = dist;
    in.radius_i = ri;
    in.radius_j = rj;
    in.reduced_radius = ri * rj / rsum;
    in.reduced_mass = mi * mj / (mi + mj);
    in.rolling_inertia = 0;
    // The contact point sits (R - overlap / 2) from each centre, so the two lever arms add up to
    // the separation and a tangential force pair conserves the angular momentum exactly (full
    // radii, the classic LAMMPS/LIGGGHTS arms, leave overlap x F_t per contact).
    in.arm_i = ri - 0.5 * in.overlap;
    in.arm_j = rj - 0.5 * in.overlap;
    in.contact_velocity = dv - cross(wi * in.arm_i + wj * in.arm_j, in.normal);
    in.relative_spin = wi - wj;
    in.wall = false;
    return in;
}

struct ContactOutput {
    Vec3 force_on_i;  // force on j is the opposite
    Vec3 torque_on_i;
    Vec3 torque_on_j;
    double normal_force;  // elastic plus damping, positive when repulsive (without cohesion)
};

// Rotates a history vector into the current tangent plane, keeping its length, so a contact
// that turns does not feed a normal component back into the tangential force.
inline void project_to_tangent_plane(Vec3& h, const Vec3& n) {
    const double before = norm2(h);
    if (before == 0) return;
    h -= n * dot(h, n);
    const double after = norm2(h);
    if (after > 0) h *= std::sqrt(before / after);
}

template <RollingModel Rolling, CohesionModel Cohesion>
inline void hertz_mindlin(const PairCoefficients& c, const ContactInput& in, ContactHistory& history, double dt,
                          ContactOutput& out) {
    constexpr double damping_factor = 1.8257418583505538;  // 2 sqrt(5/6)
    const Vec3& n = in.normal;
    const double contact_radius_sq = in.reduced_radius * in.overlap;  // a^2 of Hertz
    const double root = std::sqrt(contact_radius_sq);

    // Normal.
    const double kn = 4.0 / 3.0 * c.effective_youngs * root;
    const double sn = 2.0 * c.effective_youngs * root;
    const double sqrt_sn_m = std::sqrt(sn * in.reduced_mass);
    const double gamma_n = damping_factor * c.damping_beta * sqrt_sn_m;
    const double vn = dot(in.contact_velocity, n);
    const double fn = kn * in.overlap - gamma_n * vn;

    // Tangential with history and Coulomb cap.
    const Vec3 vt = in.contact_velocity - n * vn;
    project_to_tangent_plane(history.tangential, n);
    history.tangential += vt * dt;
    const double kt = 8.0 * c.effective_shear * root;
    // sqrt(k_t m*) = sqrt(S_n m*) sqrt(4 G*/Y*): one square root per contact instead of two.
    const double gamma_t = damping_factor * c.damping_beta * sqrt_sn_m * c.tangential_to_normal_root;
    Vec3 ft = -(history.tangential * kt) - vt * gamma_t;
    const double ft_max = c.friction * std::fabs(fn);
    const double ft_mag2 = norm2(ft);
    if (ft_mag2 > ft_max * ft_max) {
        // Sliding: the force sits on the cone and the spring is reset to match it.
        ft *= ft_max / std::sqrt(ft_mag2);
        history.tangential = kt > 0 ? -(ft + vt * gamma_t) / kt : Vec3{};
    }

    double f_normal_total = fn;
    if constexpr (Cohesion == CohesionModel::sjkr) {
        double area;
        if (in.wall) {
            area = M_PI * in.overlap * (2.0 * in.radius_i - in.overlap);
        } else {
            // Area of the circle where the two sphere surfaces intersect.
            const double d = in.distance, ri = in.radius_i, rj = in.radius_j;
            area = -M_PI / 4.0 * ((d - ri - rj) * (d + ri - rj) * (d - ri + rj) * (d + ri + rj)) / (d * d);
        }
        f_normal_total -= c.cohesion_energy_density * area;
    } else if constexpr (Cohesion == CohesionModel::dmt) {
        f_normal_total -= 4.0 * M_PI * c.surface_energy * in.reduced_radius;
    }

    out.force_on_i = n * f_normal_total + ft;
    out.normal_force = fn;
    // Torque from the tangential force, applied at the contact point of each sphere.
    const Vec3 nxft = cross(n, ft);
    out.torque_on_i = nxft * (-in.arm_i);
    out.torque_on_j = nxft * (-in.arm_j);

    if constexpr (Rolling == RollingModel::epsd) {
        // Ai et al. 2011, model C: spring torque k_r dtheta capped at mu_r R* |F_n|; viscous
        // damping only while the spring is elastic. Twisting about n is not resisted.
        Vec3 spin = in.relative_spin - n * dot(in.relative_spin, n);
        project_to_tangent_plane(history.rolling, n);
        const double kr = 2.25 * kn * c.rolling_friction * c.rolling_friction * in.reduced_radius * in.reduced_radius;
        history.rolling -= spin * (kr * dt);
        const double m_max = c.rolling_friction * in.reduced_radius * std::fabs(fn);
        const double m_mag2 = norm2(history.rolling);
        Vec3 torque = history.rolling;
        if (m_mag2 > m_max * m_max) {
            history.rolling *= m_max / std::sqrt(m_mag2);
            torque = history.rolling;
        } else {
            const double cr = c.rolling_damping * 2.0 * std::sqrt(in.rolling_inertia * kr);
            torque -= spin * cr;
        }
        out.torque_on_i += torque;
        out.torque_on_j -= torque;
    } else if constexpr (Rolling == RollingModel::sds) {
        // Rolling velocity R* (omega_i - omega_j) x n (Wang et al. 2015), spring-dashpot-slider.
        const Vec3 v_roll = cross(in.relative_spin, n) * in.reduced_radius;
        project_to_tangent_plane(history.rolling, n);
        history.rolling += v_roll * dt;
        Vec3 fr = -(history.rolling * c.rolling_stiffness) - v_roll * c.rolling_viscous;
        const double fr_max = c.rolling_friction * std::fabs(fn);
        const double fr_mag2 = norm2(fr);
        if (fr_mag2 > fr_max * fr_max) {
            fr *= fr_max / std::sqrt(fr_mag2);
            history.rolling =
                c.rolling_stiffness > 0 ? -(fr + v_roll * c.rolling_viscous) / c.rolling_stiffness : Vec3{};
        }
        const Vec3 torque = cross(n, fr) * in.reduced_radius;
        out.torque_on_i += torque;
        out.torque_on_j -= torque;
    }
}

}  // namespace mrjam
