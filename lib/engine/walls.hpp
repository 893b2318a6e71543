#pragma once
// Rigid walls: infinite planes (optionally moving), cylinders (grains inside or outside),
// passages (a surface of revolution: a valve bore with its constriction, grains inside) and
// slot passages (a valve bore with a rectangular slot orifice, geometry/slot_orifice.hpp).
// A wall contact is a Hertz-Mindlin contact with a sphere of infinite radius and mass; its
// tangential and rolling history is kept per grain.
#include <array>
#include <string>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "core/vec3.hpp"
#include "geometry/slot_orifice.hpp"

namespace mrjam {

struct Wall {
    enum class Kind { plane, cylinder, passage, slot_passage };
    std::string name;
    Kind kind = Kind::plane;
    Vec3 point{};          // plane: a point on it; cylinder: a point on the axis
    Vec3 normal{0, 0, 1};  // plane: unit normal pointing to the grains' side
    Vec3 axis{0, 0, 1};    // cylinder: unit axis
    double radius = 0;     // cylinder radius
    bool inside = true;    // cylinder: grains held inside
    // passage: the wall's generatrix in the (radius, axial position) half-plane as a polyline
    // with non-decreasing axial positions, about the axis through `point` along `axis`.
    std::vector<std::array<double, 2>> profile;
    SlotOrifice slot;  // slot_passage: bore and slot in the valve's frame (axis z through the origin)
    Vec3 velocity{};   // rigid translation (a moving plane; tangential part drives friction)
    std::uint16_t material = 0;
    std::vector<ContactHistory> history;  // per grain
    Vec3 force{};                         // force the grains exert on the wall, last step

    // The grains that may touch the wall before the next neighbour rebuild, found at each rebuild
    // with their radii grown by a margin longer than any grain moves between rebuilds, so the
    // contact pass tests these few instead of every grain (in a valve, ~2 % of the grains lie
    // near its bore). Used only while the wall is where it was then and does not move; a
    // removal or a checkpoint load drops it until the next rebuild. Ascending grain order keeps
    // the force sums in the order of a pass over every grain, so results do not change.
    struct NearGrains {
        std::vector<std::uint32_t> index;
        Vec3 point{};
        std::size_t grains = 0;
        bool valid = false;
    } near;
    void find_near_grains(const std::vector<Vec3>& positions, const std::vector<double>& radii, double margin);
    bool near_grains_hold(std::size_t grains) const {
        return near.valid && near.grains == grains && norm2(velocity) == 0 && point.x == near.point.x &&
               point.y == near.point.y && point.z == near.point.z;
    }

    // Overlap with a sphere and the contact normal pointing from the wall to the grain.
    // Returns false when not touching.
    bool touch(const Vec3& x, double r, double& overlap, Vec3& n) const;

    // The passage's radius at axial position s (the narrowest where a step face sits at s).
    double passage_radius(double s) const;

private:
    bool touch_passage(const Vec3& x, double r, double& overlap, Vec3& n) const;
    bool touch_slot_passage(const Vec3& x, double r, double& overlap, Vec3& n) const;
};

// The valve body's bore and constriction as a passage wall (geometry/valve.hpp's frame: axis z
// through the origin); the ends are extended by `margin` so periodic images see no end. A slot
// orifice gives a slot_passage (its bore is unbounded along z, so it needs no margin).
struct ValveGeometry;
Wall passage_wall(const std::string& name, const ValveGeometry& valve, double margin);

}  // namespace mrjam
