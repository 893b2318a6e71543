#include "walls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/valve.hpp"
#include "slot_passage_contact.hpp"

namespace mrjam {

bool Wall::touch(const Vec3& x, double r, double& overlap, Vec3& n) const {
    if (kind == Kind::passage) return touch_passage(x, r, overlap, n);
    if (kind == Kind::slot_passage) return touch_slot_passage(x, r, overlap, n);
    if (kind == Kind::plane) {
        const double dist = dot(x - point, normal);
        overlap = r - dist;
        n = normal;
        return overlap > 0;
    }
    Vec3 radial = x - point;
    radial -= axis * dot(radial, axis);
    const double rho = norm(radial);
    if (inside) {
        overlap = rho + r - radius;
        if (overlap <= 0) return false;
        // On the axis itself the direction is arbitrary; any radial unit vector is right there.
        n = rho > 0 ? radial * (-1.0 / rho) : Vec3{1, 0, 0};
    } else {
        overlap = radius + r - rho;
        if (overlap <= 0) return false;
        n = rho > 0 ? radial * (1.0 / rho) : Vec3{1, 0, 0};
    }
    return true;
}

void Wall::find_near_grains(const std::vector<Vec3>& positions, const std::vector<double>& radii, double margin) {
    near.index.clear();
    double overlap;
    Vec3 n;
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (touch(positions[i], radii[i] + margin, overlap, n)) near.index.push_back(static_cast<std::uint32_t>(i));
    near.point = point;
    near.grains = positions.size();
    near.valid = true;
}

double Wall::passage_radius(double s) const {
    double narrowest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
        const auto& a = profile[i];
        const auto& b = profile[i + 1];
        if (s < a[1] || s > b[1] || a[1] == b[1]) continue;  // step faces do not define a narrowest
        const double t = (s - a[1]) / (b[1] - a[1]);
        narrowest = std::min(narrowest, a[0] + t * (b[0] - a[0]));
    }
    return narrowest;
}

// The grain's centre in the (radius, axial) half-plane against the nearest point of the
// generatrix: sphere-on-surface contacts on the bore and the cone, sphere-on-edge at the
// orifice lip (the nearest point is then the corner), sphere-on-face at the step.
//
// In a concave corner (the step face meeting the bore downstream, 90 degrees; the bore meeting
// the cone, ~135) a grain can press on two faces at once. One contact with the nearer face alone
// let a grain pulled into the corner sink into the other face unresisted (a 10 % overlap blow-up
// at the step's corner in a bracket's field map), so the contact there is the sum of the two
// faces' penetration vectors: its overlap and normal are the shortest way out of both
// half-planes for a right-angled corner and close to it for the cone's. The faces count as two
// when both nearest points lie inside their segments; at a convex edge (the lip) the two
// nearest points are the same corner, which is one contact.
bool Wall::touch_passage(const Vec3& x, double r, double& overlap, Vec3& n) const {
    const Vec3 rel = x - point;
    const double s = dot(rel, axis);
    const Vec3 radial = rel - axis * s;
    const double rho = norm(radial);
    struct Nearest {
        double d2 = std::numeric_limits<double>::infinity(), pr = 0, ps = 0;
        bool interior = false;
    };
    Nearest best, second;  // the nearest point, and the nearest on another face inside its segment
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
        const double ar = profile[i][0], as = profile[i][1];
        const double dr = profile[i + 1][0] - ar, ds = profile[i + 1][1] - as;
        const double len2 = dr * dr + ds * ds;
        const double t_free = len2 > 0 ? ((rho - ar) * dr + (s - as) * ds) / len2 : 0.0;
        const double t = std::clamp(t_free, 0.0, 1.0);
        const double pr = ar + t * dr, ps = as + t * ds;
        const Nearest here{(rho - pr) * (rho - pr) + (s - ps) * (s - ps), pr, ps, t_free > 0.0 && t_free < 1.0};
        if (here.d2 < best.d2) {
            if (best.interior) second = best;
            best = here;
        } else if (here.interior && here.d2 < second.d2) {
            second = here;
        }
    }
    const double distance = std::sqrt(best.d2);
    const bool centre_inside = rho < passage_radius(s);
    overlap = centre_inside ? r - distance : r + distance;
    if (overlap <= 0) return false;
    const Vec3 e_r = rho > 0 ? radial * (1.0 / rho) : Vec3{1, 0, 0};
    // From the wall point towards the centre (reversed if the centre went through the wall).
    double nr = rho - best.pr, ns = s - best.ps;
    if (distance > 0) {
        nr /= distance;
        ns /= distance;
    } else {
        nr = -1;
        ns = 0;
    }
    if (!centre_inside) {
        nr = -nr;
        ns = -ns;
    }
    const double second_distance = std::sqrt(second.d2);
    if (centre_inside && best.interior && second_distance < r && second_distance > 0) {
        // In a concave corner: add the second face's penetration vector.
        const double overlap2 = r - second_distance;
        const double vr = overlap * nr + overlap2 * (rho - second.pr) / second_distance;
        const double vs = overlap * ns + overlap2 * (s - second.ps) / second_distance;
        overlap = std::hypot(vr, vs);
        nr = vr / overlap;
        ns = vs / overlap;
    }
    n = e_r * nr + axis * ns;
    return true;
}

bool Wall::touch_slot_passage(const Vec3& x, double r, double& overlap, Vec3& n) const {
    const SlotContact c = slot_passage_contact(slot, x - point, r);
    overlap = c.centre_in_fluid ? r - c.distance : r + c.distance;
    if (overlap <= 0) return false;
    n = c.normal;
    if (c.corner_count == 0) return true;
    // In a concave corner: the sum of every touched face's penetration vector.
    Vec3 push = c.normal * overlap;
    for (int i = 0; i < c.corner_count; ++i) push += c.corner[i].normal * (r - c.corner[i].distance);
    overlap = norm(push);
    n = push * (1.0 / overlap);
    return true;
}

Wall passage_wall(const std::string& name, const ValveGeometry& v, double margin) {
    Wall w;
    w.name = name;
    w.kind = Wall::Kind::passage;
    w.point = {0, 0, 0};
    w.axis = {0, 0, 1};
    if (v.is_slot()) {
        w.kind = Wall::Kind::slot_passage;
        w.slot = v.slot();
        return w;
    }
    const double rb = v.bore_radius(), rt = v.throat_radius();
    w.profile = {{rb, -v.upstream_length - margin},
                 {rb, v.taper_start_z()},
                 {rt, -0.5 * v.throat_length},
                 {rt, v.throat_end_z()},
                 {rb, v.throat_end_z()},
                 {rb, v.downstream_length + margin}};
    return w;
}

}  // namespace mrjam
