#pragma once
// Rigid walls: infinite planes (optionally moving) and cylinders (grains inside or outside).
// A wall contact is a Hertz-Mindlin contact with a sphere of infinite radius and mass; its
// tangential and rolling history is kept per grain.
#include <string>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "core/vec3.hpp"

namespace mrjam {

struct Wall {
    enum class Kind { plane, cylinder };
    std::string name;
    Kind kind = Kind::plane;
    Vec3 point{};            // plane: a point on it; cylinder: a point on the axis
    Vec3 normal{0, 0, 1};    // plane: unit normal pointing to the grains' side
    Vec3 axis{0, 0, 1};      // cylinder: unit axis
    double radius = 0;       // cylinder radius
    bool inside = true;      // cylinder: grains held inside
    Vec3 velocity{};         // rigid translation (a moving plane; tangential part drives friction)
    std::uint16_t material = 0;
    std::vector<ContactHistory> history;  // per grain
    Vec3 force{};            // force the grains exert on the wall, last step

    // Overlap with a sphere and the contact normal pointing from the wall to the grain.
    // Returns false when not touching.
    bool touch(const Vec3& x, double r, double& overlap, Vec3& n) const;
};

}  // namespace mrjam
