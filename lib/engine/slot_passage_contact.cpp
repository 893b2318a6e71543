#include "slot_passage_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace mrjam {
namespace {

struct Point2 {
    double a, z;  // the bounded transverse coordinate (x or y, sign folded in) and the axial one
};

struct PolygonHit {
    bool inside = false;
    double distance = 0;   // to the boundary
    Point2 direction{};    // unit: outside, from the nearest boundary point to p; inside, the outward normal of the
                           // nearest edge
    bool on_face = false;  // outside: the nearest boundary point lies inside an edge, not at a vertex
};

// A convex polygon with vertices in clockwise order in the (a, z) plane (a right, z up);
// zero-length edges (a taper or slot of no length) are skipped.
template <std::size_t N>
PolygonHit convex_polygon(const std::array<Point2, N>& v, Point2 p) {
    PolygonHit hit;
    bool inside = true;
    double best_out = std::numeric_limits<double>::infinity(), best_in = best_out;
    Point2 dir_out{}, dir_in{};
    bool face_out = false;
    for (std::size_t i = 0; i < N; ++i) {
        const Point2 a = v[i], b = v[(i + 1) % N];
        const double ea = b.a - a.a, ez = b.z - a.z;
        const double len = std::hypot(ea, ez);
        if (len == 0) continue;
        // Clockwise order: the outward normal of edge (ea, ez) is (-ez, ea) / len.
        const Point2 outward{-ez / len, ea / len};
        const double height = -((p.a - a.a) * outward.a + (p.z - a.z) * outward.z);  // > 0 inside the edge's half-plane
        if (height < 0) inside = false;
        if (height < best_in) {
            best_in = height;
            dir_in = outward;
        }
        const double t_free = ((p.a - a.a) * ea + (p.z - a.z) * ez) / (len * len);
        const double t = std::clamp(t_free, 0.0, 1.0);
        const double qa = a.a + t * ea, qz = a.z + t * ez;
        const double d = std::hypot(p.a - qa, p.z - qz);
        if (d < best_out) {
            best_out = d;
            dir_out = d > 0 ? Point2{(p.a - qa) / d, (p.z - qz) / d} : outward;
            face_out = t_free > 0.0 && t_free < 1.0;
        }
    }
    hit.inside = inside;
    hit.distance = inside ? best_in : best_out;
    hit.direction = inside ? dir_in : dir_out;
    hit.on_face = !inside && face_out;
    return hit;
}

}  // namespace

SlotContact slot_passage_contact(const SlotOrifice& s, const Vec3& p, double reach) {
    const double R = s.bore_radius;
    const double rho = std::hypot(p.x, p.y);
    const Vec3 e_r = rho > 0 ? Vec3{p.x / rho, p.y / rho, 0} : Vec3{1, 0, 0};
    double deepest = -1;
    Vec3 n_deepest{};
    // The five pieces as the centre sees them from the fluid: distance, normal, on a face.
    struct Seen {
        double distance;
        Vec3 normal;
        bool on_face;
    };
    std::array<Seen, 5> seen{};
    int count = 0;
    auto piece = [&](bool inside, double distance, const Vec3& normal, bool on_face) {
        if (inside && distance > deepest) {
            deepest = distance;
            n_deepest = normal;
        }
        if (!inside) seen[count++] = {distance, normal, on_face};
    };
    piece(rho >= R, std::abs(R - rho), e_r * -1.0, true);  // the bore: its normal points to the axis either way
    // The plates, cut off at a = 2R: the cut edge is farther from any point of the bore than
    // the bore wall itself, so it is never the nearest wall.
    for (int axis : {0, 1}) {
        const double h = axis == 0 ? s.half_width : s.half_height;
        const std::array<Point2, 5> plate{Point2{2 * R, s.taper_start_z}, Point2{R, s.taper_start_z},
                                          Point2{h, s.throat_start_z}, Point2{h, s.exit_z}, Point2{2 * R, s.exit_z}};
        for (double sign : {1.0, -1.0}) {
            const PolygonHit hit = convex_polygon(plate, Point2{sign * p[axis], p.z});
            Vec3 normal{0, 0, hit.direction.z};
            normal[axis] = sign * hit.direction.a;
            // Inside a plate the outward normal points into the fluid: the way out for the grain.
            piece(hit.inside, hit.distance, normal, hit.on_face);
        }
    }
    SlotContact out;
    if (deepest >= 0) {
        out.centre_in_fluid = false;
        out.distance = deepest;
        out.normal = n_deepest;
        return out;
    }
    int nearest = 0;
    for (int i = 1; i < count; ++i)
        if (seen[i].distance < seen[nearest].distance) nearest = i;
    out.distance = seen[nearest].distance;
    out.normal = seen[nearest].normal;
    // A grain at a convex edge or the lip touches that edge only; on a face, every other face
    // within reach is a concave corner's second (or third) wall. The step plane beyond the
    // slot's corner belongs to both an x and a y plate: a face parallel to one already counted
    // is the same face.
    if (!seen[nearest].on_face) return out;
    auto counted = [&](const Vec3& n) {
        if (dot(n, out.normal) > 1 - 1e-9) return true;
        for (int k = 0; k < out.corner_count; ++k)
            if (dot(n, out.corner[k].normal) > 1 - 1e-9) return true;
        return false;
    };
    for (int i = 0; i < count; ++i)
        if (i != nearest && seen[i].on_face && seen[i].distance < reach && out.corner_count < 4 &&
            !counted(seen[i].normal))
            out.corner[out.corner_count++] = {seen[i].distance, seen[i].normal};
    return out;
}

}  // namespace mrjam
