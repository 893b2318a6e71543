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
bool Wall::touch_passage(const Vec3& x, double r, double& overlap, Vec3& n) const {
    const Vec3 rel = x - point;
    const double s = dot(rel, axis);
    const Vec3 radial = rel - axis * s;
    const double rho = norm(radial);
    double best = std::numeric_limits<double>::infinity(), cr = 0, cs = 0;
    for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
        const double ar = profile[i][0], as = profile[i][1];
        const double dr = profile[i + 1][0] - ar, ds = profile[i + 1][1] - as;
        const double len2 = dr * dr + ds * ds;
        double t = len2 > 0 ? ((rho - ar) * dr + (s - as) * ds) / len2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        const double pr = ar + t * dr, ps = as + t * ds;
        const double d2 = (rho - pr) * (rho - pr) + (s - ps) * (s - ps);
        if (d2 < best) { best = d2; cr = pr; cs = ps; }
    }
    const double distance = std::sqrt(best);
    const bool centre_inside = rho < passage_radius(s);
    overlap = centre_inside ? r - distance : r + distance;
    if (overlap <= 0) return false;
    const Vec3 e_r = rho > 0 ? radial * (1.0 / rho) : Vec3{1, 0, 0};
    // From the wall point towards the centre (reversed if the centre went through the wall).
    double nr = rho - cr, ns = s - cs;
    if (distance > 0) { nr /= distance; ns /= distance; } else { nr = -1; ns = 0; }
    if (!centre_inside) { nr = -nr; ns = -ns; }
    n = e_r * nr + axis * ns;
    return true;
}

bool Wall::touch_slot_passage(const Vec3& x, double r, double& overlap, Vec3& n) const {
    const SlotContact c = slot_passage_contact(slot, x - point);
    overlap = c.centre_in_fluid ? r - c.distance : r + c.distance;
    if (overlap <= 0) return false;
    n = c.normal;
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
