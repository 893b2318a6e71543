// The valve in the engine: the passage wall's contact geometry (bore, cone, orifice lip) and the
// source's flow profile (values, and the same flow rate through every section).
#include <doctest/doctest.h>

#include <cmath>

#include "flow_quadrature.hpp"
#include "fluid/valve_flow.hpp"
#include "rel_approx.hpp"
#include "walls.hpp"

using mrjam_test::rel;

using namespace mrjam;

namespace {

// A grain of radius r whose centre sits at distance (r - overlap) from the surface point
// (rho_w, z_w) of the generatrix along the in-plane unit direction (nr, nz), at azimuth phi.
Vec3 place(double rho_w, double z_w, double nr, double nz, double r, double overlap, double phi) {
    const double d = r - overlap;
    const double rho = rho_w + d * nr;
    return {rho * std::cos(phi), rho * std::sin(phi), z_w + d * nz};
}

void check_contact(const Wall& wall, const Vec3& x, double r, double expected_overlap, const Vec3& expected_normal) {
    double overlap = 0;
    Vec3 n;
    REQUIRE(wall.touch(x, r, overlap, n));
    CHECK(overlap == rel(expected_overlap).epsilon(1e-9));
    CHECK(norm(n - expected_normal) < 1e-9);
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("passage wall: overlap and normal on the bore, the cone and the orifice lip") {
        ValveGeometry v;  // bore 2.6 mm, throat 1.32 mm, taper 0.8 mm, throat 0.2 mm
        const Wall wall = passage_wall("valve", v, 1e-3);
        const double r = 20e-6, delta = 1e-7;
        const double rb = v.bore_radius(), rt = v.throat_radius();
        for (double phi : {0.0, 0.7, 2.0, -2.5}) {
            CAPTURE(phi);
            const Vec3 e_r{std::cos(phi), std::sin(phi), 0};
            // Bore, upstream: the normal points to the axis.
            check_contact(wall, place(rb, -3e-3, -1, 0, r, delta, phi), r, delta, -e_r);
            // Cone: the inward normal of the generatrix from (rb, zs) to (rt, zt).
            const double zs = v.taper_start_z(), zt = -0.5 * v.throat_length;
            const double len = std::hypot(rb - rt, zt - zs);
            const double nr = -(zt - zs) / len, nz = -(rb - rt) / len;
            const double t = 0.4;
            check_contact(wall, place(rb + t * (rt - rb), zs + t * (zt - zs), nr, nz, r, delta, phi), r, delta,
                          e_r * nr + Vec3{0, 0, nz});
            // Orifice lip (the corner at the throat exit): the normal runs from the corner to the centre.
            const double a = std::cos(0.6), b = std::sin(0.6);
            check_contact(wall, place(rt, v.throat_end_z(), -a, b, r, delta, phi), r, delta,
                          e_r * (-a) + Vec3{0, 0, b});
            // The step face downstream of the lip: the normal points downstream.
            check_contact(wall, place(0.5 * (rt + rb), v.throat_end_z(), 0, 1, r, delta, phi), r, delta, Vec3{0, 0, 1});
            // The concave corner where the step face meets the bore: a grain pressed into both faces
            // (overlap d1 with the bore, d2 with the step) is pushed out of both, by the sum of the
            // two penetration vectors, not by the nearer face alone.
            const double d1 = 3e-7, d2 = 2e-7;
            const double cr = rb - (r - d1), cz = v.throat_end_z() + (r - d2);
            check_contact(wall, {cr * std::cos(phi), cr * std::sin(phi), cz}, r, std::hypot(d1, d2),
                          (e_r * (-d1) + Vec3{0, 0, d2}) * (1.0 / std::hypot(d1, d2)));
            // The bore meeting the cone (about 133 degrees inside): the same sum of the two faces.
            const double zs2 = v.taper_start_z();
            const Vec3 bore_in{-1, 0, 0};                           // (radial, axial) inward normal of the bore
            const Vec3 cone_in{nr, nz, 0};                          // and of the cone
            const Vec3 centre_2d{rb - (r - d1), zs2 - 0.3 * r, 0};  // d1 into the bore, just upstream of the corner
            const double cone_distance = dot(centre_2d - Vec3{rb, zs2, 0}, cone_in);
            REQUIRE(cone_distance < r);
            const Vec3 push = bore_in * d1 + cone_in * (r - cone_distance);
            check_contact(wall, {centre_2d.x * std::cos(phi), centre_2d.x * std::sin(phi), centre_2d.y}, r, norm(push),
                          (e_r * push.x + Vec3{0, 0, push.y}) * (1.0 / norm(push)));
        }
        // Clear of every surface: no contact.
        double overlap;
        Vec3 n;
        CHECK_FALSE(wall.touch({0, 0, 0}, r, overlap, n));
        CHECK_FALSE(wall.touch({rb - 2 * r, 0, -3e-3}, r, overlap, n));
        CHECK(wall.passage_radius(0.0) == rel(rt));
        CHECK(wall.passage_radius(-3e-3) == rel(rb));
    }

    TEST_CASE("valve flow, conserving reading: the source's shape and one flow rate through every section") {
        ValveGeometry v;
        const double U = 0.273;
        const ValveFlow flow(v, U, ValveFlow::Profile::conserving);
        const double rb = v.bore_radius(), rt = v.throat_radius();
        // In the bore: U inside the constriction's diameter, linear to 0 at the bore wall.
        CHECK(flow.velocity({0, 0, -3e-3}, 0).z == rel(U));
        CHECK(flow.velocity({rt, 0, -3e-3}, 0).z == rel(U));
        CHECK(flow.velocity({0, 0.5 * (rt + rb), -3e-3}, 0).z == rel(0.5 * U));
        CHECK(flow.velocity({rb * 1.0001, 0, -3e-3}, 0).z == 0.0);
        // In the throat: raised by (D/d)^2.
        CHECK(flow.velocity({0, 0, 0}, 0).z == rel(U * (rb / rt) * (rb / rt)));
        // Flow rate by midpoint quadrature over the section, at the bore, mid-taper and throat.
        for (double z : {-3e-3, v.taper_start_z() + 0.5 * v.taper_length, 0.0, 2e-3}) {
            CAPTURE(z);
            CHECK(mrjam_test::section_flow_rate(flow, v, z, 20000) == rel(flow.reference_flow_rate()).epsilon(1e-6));
            CHECK(flow.flow_rate_at(z) == rel(flow.reference_flow_rate()).epsilon(1e-6));
        }
    }

    TEST_CASE("valve flow, source reading: the bore profile up to the orifice, the raised plug in the throat") {
        ValveGeometry v;
        const double U = 0.273;
        const ValveFlow flow(v, U);  // the default reading
        CHECK(flow.profile() == ValveFlow::Profile::source);
        const double rb = v.bore_radius(), rt = v.throat_radius();
        const double mid_taper = v.taper_start_z() + 0.5 * v.taper_length;
        const double R = v.passage_radius(mid_taper);
        // In the taper the bore's profile holds unchanged, cut off by the cone wall.
        CHECK(flow.velocity({0, 0, mid_taper}, 0).z == rel(U));
        const double r = 0.5 * (rt + R);
        CHECK(flow.velocity({0, r, mid_taper}, 0).z == rel(U * (rb - r) / (rb - rt)));
        CHECK(flow.velocity({0, R * 1.0001, mid_taper}, 0).z == 0.0);
        // In the straight throat, a plug raised by the area ratio.
        for (double rho : {0.0, 0.5 * rt, 0.99 * rt})
            CHECK(flow.velocity({rho, 0, 0}, 0).z == rel(U * (rb / rt) * (rb / rt)));
        // Flow rates: the bore's is the reference; the taper carries less (the cone cuts the ramp);
        // the throat carries U pi r_b^2, more than the bore (the ramp's deficit): the source's
        // field is not a conserving one, and the report says so.
        CHECK(flow.flow_rate_at(-3e-3) == rel(flow.reference_flow_rate()).epsilon(1e-6));
        CHECK(flow.flow_rate_at(mid_taper) < flow.reference_flow_rate());
        CHECK(flow.flow_rate_at(0.0) == rel(U * M_PI * rb * rb).epsilon(1e-6));
        CHECK(flow.flow_rate_at(0.0) > flow.reference_flow_rate());
    }

    TEST_CASE(
        "valve flow, source reading with the mean throat: the source's field, the throat carrying the bore's flow") {
        ValveGeometry v;
        const double U = 0.273;
        const ValveFlow flow(v, U, valve_flow_profile("source_mean_throat"));
        const ValveFlow source(v, U);
        CHECK(valve_flow_profile_name(flow.profile()) == "source_mean_throat");
        const double rt = v.throat_radius();
        const double mid_taper = v.taper_start_z() + 0.5 * v.taper_length;
        // Up to the orifice, the source's field point for point.
        for (double z : {-3e-3, mid_taper})
            for (double rho : {0.0, 0.5 * rt, rt, 0.5 * (rt + v.passage_radius(z)), 0.999 * v.passage_radius(z)})
                CHECK(flow.velocity({0, rho, z}, 0).z == source.velocity({0, rho, z}, 0).z);
        // In the straight throat a plug that carries the bore's flow rate (by quadrature), slower
        // than the source's (r_b / r_t)^2 U, which carries more than the bore.
        CHECK(flow.velocity({0, 0, 0}, 0).z == flow.velocity({0.99 * rt, 0, 0}, 0).z);
        CHECK(flow.flow_rate_at(0.0) == rel(flow.reference_flow_rate()).epsilon(1e-6));
        CHECK(flow.reference_flow_rate() == rel(source.reference_flow_rate()));
        CHECK(flow.velocity({0, 0, 0}, 0).z < source.velocity({0, 0, 0}, 0).z);
    }

}  // TEST_SUITE

namespace {
// Divergence of the flow by central differences in x, y, z (the profile is piecewise smooth, so
// points are kept away from its kinks).
double divergence(const mrjam::FlowField& f, const mrjam::Vec3& x, double h) {
    using mrjam::Vec3;
    const double dx = (f.velocity(x + Vec3{h, 0, 0}, 0).x - f.velocity(x - Vec3{h, 0, 0}, 0).x) / (2 * h);
    const double dy = (f.velocity(x + Vec3{0, h, 0}, 0).y - f.velocity(x - Vec3{0, h, 0}, 0).y) / (2 * h);
    const double dz = (f.velocity(x + Vec3{0, 0, h}, 0).z - f.velocity(x - Vec3{0, 0, h}, 0).z) / (2 * h);
    return dx + dy + dz;
}
}  // namespace

TEST_CASE(
    "valve flow, converging reading: divergence-free, one flow rate, along the cone, a mirrored jet past the exit") {
    ValveGeometry v;
    const double U = 0.273;
    const ValveFlow flow(v, U, ValveFlow::Profile::converging);
    const double rb = v.bore_radius(), rt = v.throat_radius();
    const double exit = v.throat_end_z();
    const double mid_taper = v.taper_start_z() + 0.5 * v.taper_length;
    const double mid_jet = exit + 0.5 * v.taper_length;
    // Continuity: |div u| against the velocity gradient's own scale U / r_t, at points in the
    // plug and in the ramp of the taper and of the jet (the difference step 1e-7 m; the
    // central difference's error is O(h^2) where the field is smooth: ~1e-7 relative).
    const double scale = U / rt;
    for (double z : {mid_taper, mid_taper + 0.2e-3, mid_jet, mid_jet - 0.2e-3}) {
        const double Rf = flow.stream_radius(z);
        for (double xi : {0.2, 0.35, 0.7, 0.9}) {
            CAPTURE(z);
            CAPTURE(xi);
            const Vec3 x{0.6 * xi * Rf, 0.8 * xi * Rf, z};
            CHECK(std::abs(divergence(flow, x, 1e-7)) < 1e-5 * scale);
        }
    }
    // The conserving reading, same shape, is not divergence-free in the taper: the check can fail.
    const ValveFlow axial_only(v, U, ValveFlow::Profile::conserving);
    CHECK(std::abs(divergence(axial_only, {0.3 * v.passage_radius(mid_taper), 0, mid_taper}, 1e-7)) > 0.1 * scale);
    // In the taper a streamline at r = xi R runs at u_r / u_z = xi dR/dz: along the cone at the wall.
    const double R = v.passage_radius(mid_taper);
    const Vec3 near_wall = flow.velocity({0, 0.99 * R, mid_taper}, 0);
    CHECK(near_wall.y / near_wall.z == rel(-0.99 * (rb - rt) / v.taper_length));
    // Past the exit the stream grows from r_t back to r_b over one taper length; the step's
    // corner outside it is at rest, and the jet's axis runs faster than the bore's plug.
    CHECK(flow.stream_radius(mid_jet) == rel(0.5 * (rb + rt)));
    CHECK(flow.velocity({0, 0.5 * (rb + rt) * 1.001, mid_jet}, 0).z == 0.0);
    CHECK(flow.velocity({0, 0, mid_jet}, 0).z == rel(U * std::pow(rb / (0.5 * (rb + rt)), 2)));
    CHECK(flow.stream_radius(exit + 1.01 * v.taper_length) == rel(rb));
    // One flow rate through every section (z-component quadrature over the stream).
    for (double z : {-3e-3, mid_taper, 0.0, exit + 1e-6, mid_jet, 2e-3}) {
        CAPTURE(z);
        CHECK(flow.flow_rate_at(z) == rel(flow.reference_flow_rate()).epsilon(1e-6));
    }
}
