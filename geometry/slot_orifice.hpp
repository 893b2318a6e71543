#pragma once
// A rectangular slot orifice in the valve's round bore (geometry/valve.hpp, orifice "slot").
//
// Frame as the valve's: axis z, flow towards +z, origin at the throat centre. The slot is
// 2 half_width along x (across the field) by 2 half_height along y (along the field, the gap the
// chains must bridge). Over the taper, four flat faces close in linearly from the bore to the
// slot: at axial position z the passage is the bore's disc cut by the rectangle
// |x| <= X(z), |y| <= Y(z), with X = Y = the bore radius at the taper start (the rectangle then
// circumscribes the disc, so the faces meet the bore without a step) and X, Y = the slot's
// half sizes where the straight slot begins. The slot ends in an abrupt step back to the bore
// (a plate with a rectangular hole), as the circular orifice does.
#include <limits>

#include "core/vec3.hpp"

namespace mrjam {

struct SlotOrifice {
    double bore_radius = 0;
    double half_width = 0;      // along x
    double half_height = 0;     // along y
    double taper_start_z = 0;   // bore -> taper
    double throat_start_z = 0;  // taper -> straight slot
    double exit_z = 0;          // straight slot -> step back to the bore

    static constexpr double unbounded = std::numeric_limits<double>::infinity();
    // Half sizes of the cutting rectangle at z (unbounded outside the constriction).
    double half_x(double z) const { return half_size(z, half_width); }
    double half_y(double z) const { return half_size(z, half_height); }
    bool contains(const Vec3& p) const;   // inside the fluid passage (any z)
    double section_area(double z) const;  // area of the passage's cross-section at z
    double constriction_volume() const;   // fluid volume from taper_start_z to exit_z, exact

    // Area of the disc of radius R cut by the rectangle |x| <= X, |y| <= Y (closed form).
    static double disc_rectangle_area(double R, double X, double Y);

private:
    double half_size(double z, double slot_half) const;
};

}  // namespace mrjam
