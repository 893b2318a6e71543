#include "magnetics/epm_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "magnetics/gmsh_api.hpp"

namespace mrjam::magnetics {

namespace occ = gmsh::model::occ;

namespace {

struct Point2 {
    double x, y;
};

// A bracket's side profile (x-y plane, upper bracket, y >= gap/2) as a closed polygon, with an
// optional half-disc cutout in its inner face. Built at z = z0; `sign` = -1 mirrors it to the
// lower bracket.
int bracket_surface(const EpmModel& m, double z0, double sign) {
    const auto& b = m.bracket;
    const double g = 0.5 * m.gap(), t = b.thickness;
    const double x0 = m.magnet_back_x(), x1 = m.bracket_tip_x();
    const bool chamfered = b.variant == BracketVariant::rectangular || b.variant == BracketVariant::curved ||
                           b.variant == BracketVariant::insert;
    const double c = chamfered ? b.chamfer : 0.0;

    std::vector<int> points;
    auto point = [&](double x, double y) { return occ::addPoint(x, sign * y, z0); };
    std::vector<int> curves;
    // Outer outline: back, top, tip (with chamfer), then the inner face back to the start.
    points.push_back(point(x0, g));
    points.push_back(point(x0, g + t));
    if (c > 0) {
        points.push_back(point(x1 - c, g + t));
        points.push_back(point(x1, g + t - c));
    } else {
        points.push_back(point(x1, g + t));
    }
    points.push_back(point(x1, g));
    for (std::size_t i = 0; i + 1 < points.size(); ++i) curves.push_back(occ::addLine(points[i], points[i + 1]));
    int last = points.back();
    if (b.variant == BracketVariant::curved) {
        // Half-disc notch in the inner face starting at the magnets' front face: it lengthens the
        // flux path through the inactive air gap (section 3.2.3, Fig. 3.4c).
        const double r = b.cutout_radius, xc = m.magnet_front_x() + r;
        const int right = point(xc + r, g), top = point(xc, g + r), left = point(xc - r, g), centre = point(xc, g);
        curves.push_back(occ::addLine(last, right));
        curves.push_back(occ::addCircleArc(right, centre, top));
        curves.push_back(occ::addCircleArc(top, centre, left));
        last = left;
    }
    curves.push_back(occ::addLine(last, points.front()));
    const int loop = occ::addCurveLoop(curves);
    return occ::addPlaneSurface({loop});
}

DimTags bracket_pieces(const EpmModel& m, int dim) {
    const auto& b = m.bracket;
    DimTags out;
    if (b.variant == BracketVariant::unguided) {
        // Flat plates with the magnets' footprint (Fig. 3.4a).
        const double x0 = m.magnet_back_x(), g = 0.5 * m.gap(), span = m.magnets_z_span();
        for (double s : {1.0, -1.0}) {
            const double ylo = s > 0 ? g : -g - b.thickness;
            if (dim == 3)
                out.push_back({3, occ::addBox(x0, ylo, -0.5 * span, m.magnets.width, b.thickness, span)});
            else
                out.push_back({2, occ::addRectangle(x0, ylo, 0.0, m.magnets.width, b.thickness)});
        }
        return out;
    }
    const double z0 = dim == 3 ? -0.5 * b.width : 0.0;
    for (double s : {1.0, -1.0}) {
        const int surface = bracket_surface(m, z0, s);
        if (dim == 2) {
            out.push_back({2, surface});
            continue;
        }
        DimTags extruded;
        occ::extrude({{2, surface}}, 0, 0, b.width, extruded);
        for (const auto& e : extruded)
            if (e.first == 3) out.push_back(e);
    }
    return out;
}

// The fluid passage: bore, taper, throat, bore (3D); the bore disc at the throat section is
// used in 2D (the planar model cannot represent an axial constriction).
int fluid_solid(const ValveGeometry& v) {
    const double rb = v.bore_radius(), rt = v.throat_radius();
    const double z_taper = v.taper_start_z(), z_throat = -0.5 * v.throat_length, z_exit = v.throat_end_z();
    DimTags parts;
    parts.push_back({3, occ::addCylinder(0, 0, -v.upstream_length, 0, 0, z_taper + v.upstream_length, rb)});
    if (v.taper_length > 0) parts.push_back({3, occ::addCone(0, 0, z_taper, 0, 0, v.taper_length, rb, rt)});
    if (v.throat_length > 0) parts.push_back({3, occ::addCylinder(0, 0, z_throat, 0, 0, v.throat_length, rt)});
    parts.push_back({3, occ::addCylinder(0, 0, z_exit, 0, 0, v.downstream_length - z_exit, rb)});
    DimTags fused;
    std::vector<DimTags> map;
    occ::fuse({parts.front()}, DimTags(parts.begin() + 1, parts.end()), fused, map);
    return fused.front().second;
}

DimTags cut(const DimTags& object, const DimTags& tool, bool remove_tool) {
    DimTags out;
    std::vector<DimTags> map;
    occ::cut(object, tool, out, map, -1, true, remove_tool);
    return out;
}

DimTags intersect(const DimTags& object, const DimTags& tool) {
    DimTags out;
    std::vector<DimTags> map;
    occ::intersect(object, tool, out, map, -1, false, false);
    return out;
}

}  // namespace

std::vector<RegionPieces> add_epm_pieces(const EpmModel& m, int dim) {
    const auto& mg = m.magnets;
    const double g = 0.5 * m.gap(), x0 = m.magnet_back_x();
    const double w = m.bracket.width;
    std::vector<RegionPieces> regions;

    if (dim == 3) {
        const double zn = -0.5 * mg.spacing - mg.depth, za = 0.5 * mg.spacing;
        regions.push_back({region::alnico, {{3, occ::addBox(x0, -g, za, mg.width, 2 * g, mg.depth)}}});
        regions.push_back({region::ndfeb, {{3, occ::addBox(x0, -g, zn, mg.width, 2 * g, mg.depth)}}});
    } else {
        regions.push_back({region::magnet_pair, {{2, occ::addRectangle(x0, -g, 0.0, mg.width, 2 * g)}}});
    }
    DimTags iron = bracket_pieces(m, dim);

    const ValveGeometry& v = m.valve;
    const double rb = v.bore_radius(), ro = 0.5 * v.outer_diameter();
    const double x_inactive = m.magnet_front_x();
    // A rectangle of the x-y section, extruded over the bracket width in 3D.
    auto section_box = [&](double x, double y, double dx, double dy) {
        return dim == 3 ? std::pair{3, occ::addBox(x, y, -0.5 * w, dx, dy, w)}
                        : std::pair{2, occ::addRectangle(x, y, 0.0, dx, dy)};
    };
    auto joined = [](DimTags a, const DimTags& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };
    // 3D: the passage with its constriction; 2D: the bore disc of the section through the throat.
    const DimTags fluid{dim == 3 ? std::pair{3, fluid_solid(v)} : std::pair{2, occ::addDisk(0, 0, 0, rb, rb)}};
    DimTags inserts;
    if (m.bracket.variant == BracketVariant::insert) {
        // Iron blocks through the valve wall, from the brackets' inner faces down to the fluid.
        const double iw = m.bracket.insert_width;
        inserts = cut({section_box(-0.5 * iw, 0.0, iw, g), section_box(-0.5 * iw, -g, iw, g)}, fluid, false);
    }
    // The valve body (non-magnetic plastic) is its own region: the tube's wall and the
    // constriction's cone, whose outline the fluid is cut from.
    const DimTags body_outline{dim == 3 ? std::pair{3, occ::addCylinder(0, 0, -v.upstream_length, 0, 0,
                                                                        v.upstream_length + v.downstream_length, ro)}
                                        : std::pair{2, occ::addDisk(0, 0, 0, ro, ro)}};
    // The inactive air: between the brackets, from the magnets' face to the tube axis plane,
    // outside the valve body and the inserts.
    const DimTags inactive =
        cut({section_box(x_inactive, -g, -x_inactive, 2 * g)}, joined(body_outline, inserts), false);
    const DimTags body = cut(body_outline, joined(fluid, inserts), false);
    regions.push_back({region::iron, joined(iron, inserts)});
    if (dim == 3) {
        // The active fluid lies between the brackets (|z| <= width / 2); the rest is passive.
        const DimTags slab{{3, occ::addBox(-ro - 1e-3, -ro - 1e-3, -0.5 * w, 2 * ro + 2e-3, 2 * ro + 2e-3, w)}};
        regions.push_back({region::fluid_active, intersect(fluid, slab)});
        regions.push_back({region::fluid_passive, cut(fluid, slab, true)});
    } else {
        regions.push_back({region::fluid_active, fluid});
    }
    regions.push_back({region::inactive_air, inactive});
    regions.push_back({region::valve_body, body});
    return regions;
}

EpmLayout epm_layout(const EpmModel& m) {
    const double g = 0.5 * m.gap(), t = m.bracket.thickness, ro = 0.5 * m.valve.outer_diameter();
    EpmLayout layout;
    layout.device_lo = {m.magnet_back_x(), -g - t, -std::max(m.valve.upstream_length, 0.5 * m.bracket.width)};
    layout.device_hi = {ro, g + t, std::max(m.valve.downstream_length, 0.5 * m.bracket.width)};
    return layout;
}

MeshRequest epm_mesh_request(const EpmModel& m, int dim, const MeshSettings& mesh) {
    MeshRequest request;
    request.dimension = dim;
    const double half = 0.5 * mesh.air_box;
    const EpmLayout layout = epm_layout(m);
    const Vec3 centre = 0.5 * (layout.device_lo + layout.device_hi);
    request.air_lo = {centre.x - half, centre.y - half, dim == 3 ? -half : 0.0};
    request.air_hi = {centre.x + half, centre.y + half, dim == 3 ? half : 0.0};
    request.far_size = mesh.far_size;
    request.air_region = region::air;
    request.boundary_region = region::boundary;
    const double rb = m.valve.bore_radius(), w = 0.5 * m.bracket.width;
    const double pad = 2.0 * mesh.device_size;
    // Fine elements in the active fluid (and the gap either side of it), medium over the device.
    request.refinements.push_back({{-rb - pad, -0.5 * m.gap(), -w - pad},
                                   {rb + pad, 0.5 * m.gap(), w + pad},
                                   mesh.fluid_size,
                                   4.0 * mesh.device_size});
    request.refinements.push_back({layout.device_lo - Vec3{pad, pad, pad}, layout.device_hi + Vec3{pad, pad, pad},
                                   mesh.device_size, 0.25 * mesh.air_box});
    return request;
}

}  // namespace mrjam::magnetics
