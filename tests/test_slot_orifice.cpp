// The rectangular slot orifice: its geometry (section, exact fluid volume, description checks),
// the passage wall's contacts with a slot (faces, edges, lip, step with a rectangular hole) and
// the slot's flow profile (one flow rate through every section).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "fluid/slot_valve_flow.hpp"
#include "geometry/valve.hpp"
#include "jam/throat_span.hpp"
#include "walls.hpp"

using namespace mrjam;

// Every Approx below is relative (scale 0): doctest's default adds 1 to the scale, which for
// SI lengths and volumes (1e-3, 1e-9) would accept anything.

namespace {

// A 20x-like slot: 0.6 mm across the field by 0.88 mm along it, in the 2.6 mm bore.
ValveGeometry slot_valve() {
    ValveGeometry v;
    v.orifice = Orifice::slot;
    v.slot_width = 0.6e-3;
    v.constriction_diameter = 0.88e-3;
    return v;
}

void check_contact(const Wall& wall, const Vec3& x, double r, double expected_overlap, const Vec3& expected_normal) {
    CAPTURE(x);
    double overlap = 0;
    Vec3 n;
    REQUIRE(wall.touch(x, r, overlap, n));
    CHECK(overlap == doctest::Approx(expected_overlap).epsilon(1e-9).scale(0));
    CHECK(norm(n - expected_normal) < 1e-9);
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("slot orifice: section areas and the fluid volume in closed form") {
        const double R = 1.0;
        // Limits of the disc cut by a rectangle.
        CHECK(SlotOrifice::disc_rectangle_area(R, 2, 3) == doctest::Approx(std::numbers::pi).epsilon(1e-12).scale(0));
        CHECK(SlotOrifice::disc_rectangle_area(R, 0.3, 0.4) == doctest::Approx(4 * 0.3 * 0.4).epsilon(1e-12).scale(0));
        // Corners outside: against 4 * integral_0^X min(Y, sqrt(R^2 - x^2)) dx by the midpoint rule
        // (its error ~ (X/n)^2 times the curvature: below 1e-10 for n = 2e5).
        for (auto [X, Y] : {std::pair{0.9, 0.6}, std::pair{0.5, 0.95}, std::pair{0.99, 0.99}}) {
            CAPTURE(X);
            CAPTURE(Y);
            const int n = 200000;
            double a = 0;
            for (int i = 0; i < n; ++i) {
                const double x = (i + 0.5) * X / n;
                a += 4 * std::min(Y, std::sqrt(R * R - x * x)) * X / n;
            }
            CHECK(SlotOrifice::disc_rectangle_area(R, X, Y) == doctest::Approx(a).epsilon(1e-9).scale(0));
        }
        // The exact volume against Simpson's rule over the sections (the section is C1 in z, so
        // Simpson's error with 2e4 intervals is far below the 1e-9 asked).
        for (double taper : {0.8e-3, 0.0}) {
            CAPTURE(taper);
            ValveGeometry v = slot_valve();
            v.taper_length = taper;
            const double z0 = -v.upstream_length, z1 = v.downstream_length;
            const int n = 20000;
            const double h = (v.throat_end_z() - v.taper_start_z()) / n;
            double constriction = 0;
            for (int i = 0; i <= n; ++i) {
                const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                constriction += w * v.section_area(v.taper_start_z() + i * h) * h / 3;
            }
            const double rb = v.bore_radius();
            const double bore = std::numbers::pi * rb * rb * ((z1 - z0) - (v.throat_end_z() - v.taper_start_z()));
            CHECK(v.fluid_volume() == doctest::Approx(bore + constriction).epsilon(1e-9).scale(0));
        }
        // In the fluid: the slot's rectangle in the throat, the bore outside.
        const ValveGeometry v = slot_valve();
        CHECK(v.in_fluid({0.29e-3, 0.43e-3, 0}));
        CHECK_FALSE(v.in_fluid({0.31e-3, 0, 0}));
        CHECK_FALSE(v.in_fluid({0, 0.45e-3, 0}));
        CHECK(v.in_fluid({1.0e-3, 0.8e-3, 1e-3}));
        CHECK(v.passage_half_height(0.0) == doctest::Approx(0.44e-3).epsilon(1e-12).scale(0));
        CHECK(v.passage_half_height(-3e-3) == doctest::Approx(v.bore_radius()).epsilon(1e-12).scale(0));
    }

    TEST_CASE("slot orifice: the description is refused when the slot does not fit or is half given") {
        auto first_field = [](const ValveGeometry& v) {
            const auto p = v.problems();
            return p.empty() ? std::string() : p.front().substr(0, p.front().find(':'));
        };
        ValveGeometry v = slot_valve();
        CHECK(v.problems().empty());
        v.slot_width = 2.4e-3;  // 2.4 x 0.88 mm: its diagonal 2.56 mm fits the 2.6 mm bore
        CHECK(v.problems().empty());
        v.slot_width = 2.5e-3;  // diagonal 2.65 mm: the corners would cut the bore
        CHECK(first_field(v) == "slot_width");
        v.slot_width = 0;
        CHECK(first_field(v) == "slot_width");
        ValveGeometry circle;
        circle.slot_width = 0.5e-3;  // a width without a slot
        CHECK(first_field(circle) == "slot_width");
    }

    TEST_CASE("slot passage wall: overlap and normal on the faces, edges, lip and step") {
        const ValveGeometry v = slot_valve();
        const Wall wall = passage_wall("valve", v, 0);
        REQUIRE(wall.kind == Wall::Kind::slot_passage);
        const double r = 20e-6, delta = 1e-7, d = r - delta;
        const double R = v.bore_radius(), hw = 0.3e-3, hh = 0.44e-3;
        const double zts = v.taper_start_z(), zth = -0.5 * v.throat_length, ze = v.throat_end_z(), L = v.taper_length;
        for (double side : {1.0, -1.0}) {
            CAPTURE(side);
            // The slot's straight faces: across the field (x) and along it (y).
            check_contact(wall, {side * (hw - d), 0.1e-3, 0.03e-3}, r, delta, {-side, 0, 0});
            check_contact(wall, {0.05e-3, side * (hh - d), -0.02e-3}, r, delta, {0, -side, 0});
            // The tapered flat faces, 30 % of the way from the slot to the bore: the face runs from
            // (h, throat start) to (R, taper start) in the (x or y, z) plane; its normal points to
            // the axis and upstream.
            for (int axis : {0, 1}) {
                CAPTURE(axis);
                const double h = axis == 0 ? hw : hh;
                const double len = std::hypot(L, R - h);
                const double a_face = h + 0.3 * (R - h), z_face = zth - 0.3 * L;
                Vec3 centre{0, 0, z_face - d * (R - h) / len}, normal{0, 0, -(R - h) / len};
                centre[axis] = side * (a_face - d * L / len);
                centre[1 - axis] = 0.1e-3;
                normal[axis] = -side * L / len;
                check_contact(wall, centre, r, delta, normal);
            }
            // The orifice lip (the edge at the slot's exit), reached from downstream and inside.
            const double c = std::cos(0.6), s = std::sin(0.6);
            check_contact(wall, {side * (hw - d * c), 0.2e-3, ze + d * s}, r, delta, {-side * c, 0, s});
            check_contact(wall, {0.1e-3, side * (hh - d * c), ze + d * s}, r, delta, {0, -side * c, s});
            // The step face with the rectangular hole: beside the slot, above it, and off its corner.
            for (auto [x, y] : {std::pair{0.8e-3, 0.0}, std::pair{0.1e-3, 0.7e-3}, std::pair{0.6e-3, 0.7e-3}})
                check_contact(wall, {side * x, y, ze + d}, r, delta, {0, 0, 1});
        }
        // The bore, upstream and downstream, and in the taper near its start where the cutting
        // rectangle is wider than the disc along the diagonal (the bore is the wall there).
        for (double phi : {0.3, 2.2, -1.0, std::numbers::pi / 4}) {
            CAPTURE(phi);
            const Vec3 e_r{std::cos(phi), std::sin(phi), 0};
            check_contact(wall, e_r * (R - d) + Vec3{0, 0, -2e-3}, r, delta, e_r * -1.0);
            check_contact(wall, e_r * (R - d) + Vec3{0, 0, 2e-3}, r, delta, e_r * -1.0);
        }
        const Vec3 diagonal{std::sqrt(0.5), std::sqrt(0.5), 0};
        check_contact(wall, diagonal * (R - d) + Vec3{0, 0, zts + 0.1 * L}, r, delta, diagonal * -1.0);
        // In the slot's concave corner (the x face meeting the y face) a grain pressed into both by
        // delta and delta / 2 is pushed out of both: the sum of the two penetration vectors.
        check_contact(wall, {hw - d, hh - (r - 0.5 * delta), 0}, r, delta * std::sqrt(1.25),
                      Vec3{-1, -0.5, 0} * (1.0 / std::sqrt(1.25)));
        // The step meeting the bore downstream (beside the slot, on the x axis): delta into the
        // bore and 2 delta into the step face.
        check_contact(wall, {R - d, 0, ze + (r - 2 * delta)}, r, delta * std::sqrt(5.0),
                      Vec3{-1, 0, 2} * (1.0 / std::sqrt(5.0)));
        // The bore meeting the x plate's tapered face, just downstream of the taper's start: the
        // face's penetration adds to the bore's.
        {
            const double len = std::hypot(L, R - hw);
            const Vec3 face_normal{-L / len, 0, -(R - hw) / len};  // into the fluid: to the axis, upstream
            const Vec3 centre{R - d, 0, zts + 0.2 * r};
            // Depth into the tapered face: r minus the centre's height above the face's plane.
            const double height = dot(centre - Vec3{R, 0, zts}, face_normal);
            REQUIRE(height < r);
            const Vec3 push = Vec3{-1, 0, 0} * delta + face_normal * (r - height);
            check_contact(wall, centre, r, norm(push), push * (1.0 / norm(push)));
        }
        // A centre pushed 5 um into the x face: overlap r + 5 um, pushed back into the slot.
        check_contact(wall, {hw + 5e-6, 0, 0}, r, r + 5e-6, {-1, 0, 0});
        // No contact in the middle of the slot, of the taper and of the bore.
        double overlap;
        Vec3 n;
        CHECK_FALSE(wall.touch({0, 0, 0}, r, overlap, n));
        CHECK_FALSE(wall.touch({0.2e-3, -0.3e-3, zth - 0.5 * L}, r, overlap, n));
        CHECK_FALSE(wall.touch({R - 2 * r, 0, -3e-3}, r, overlap, n));

        // Without a taper the slot starts with a step: a plate facing upstream with the hole in it.
        ValveGeometry abrupt = slot_valve();
        abrupt.taper_length = 0;
        const Wall step = passage_wall("valve", abrupt, 0);
        check_contact(step, {0.8e-3, 0.1e-3, abrupt.taper_start_z() - d}, r, delta, {0, 0, -1});
        check_contact(step, {0.1e-3, -0.9e-3, abrupt.taper_start_z() - d}, r, delta, {0, 0, -1});
    }

    TEST_CASE("slot valve flow: the source's profile in the bore and one flow rate through every section") {
        const ValveGeometry v = slot_valve();
        const double U = 0.273, R = v.bore_radius(), hh = v.throat_radius();
        const SlotValveFlow flow(v.slot(), U);
        // In the bore: U inside the slot's half height (the constriction's 'diameter' along the
        // field), linear to 0 at the wall: the circular valve's profile.
        CHECK(flow.velocity({0, 0, -3e-3}, 0).z == doctest::Approx(U).epsilon(1e-12).scale(0));
        CHECK(flow.velocity({hh, 0, -3e-3}, 0).z == doctest::Approx(U).epsilon(1e-12).scale(0));
        CHECK(flow.velocity({0, 0.5 * (hh + R), 3e-3}, 0).z == doctest::Approx(0.5 * U).epsilon(1e-12).scale(0));
        CHECK(flow.velocity({R * 1.0001, 0, -3e-3}, 0).z == 0.0);
        CHECK(flow.velocity({0.31e-3, 0, 0}, 0).z == 0.0);  // beside the slot: in the plate
        // The flow rate by the midpoint rule over a quadrant of the section (symmetric profile).
        // The integrand is continuous and vanishes at the wall, so the rule's error is O((R/n)^2),
        // about 1e-6 for n = 1000: checked to 1e-5, while a wrong normalisation is off by percent.
        // Sections: the bore, the taper with the rectangle's corners outside and inside the disc,
        // and the straight slot.
        const double zts = v.taper_start_z(), L = v.taper_length;
        for (double z : {-3e-3, zts + 0.1 * L, zts + 0.85 * L, 0.0}) {
            CAPTURE(z);
            const int n = 1000;
            const double h = R / n;
            double q = 0;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) q += 4 * flow.velocity({(i + 0.5) * h, (j + 0.5) * h, z}, 0).z * h * h;
            CHECK(q == doctest::Approx(flow.flow_rate()).epsilon(1e-5).scale(0));
        }
        // The same reference flow rate as a circular orifice of the slot's height (same bore profile).
        CHECK(flow.flow_rate() == doctest::Approx(std::numbers::pi * U * (R * R * R - hh * hh * hh) / (3 * (R - hh)))
                                      .epsilon(1e-12)
                                      .scale(0));
    }

    TEST_CASE("throat span: a cluster across the slot's gap spans it, one between its side faces does not") {
        const double r = 20e-6;
        auto grains = [&](std::initializer_list<Vec3> at) {
            System s;
            for (const Vec3& x : at) s.particles.add(x, r, 7800, 0);
            return s;
        };
        auto one_cluster = [](std::size_t n) { return ContactClusters{std::vector<std::uint32_t>(n, 0), {n}}; };
        const ValveGeometry v = slot_valve();
        const Wall wall = passage_wall("valve", v, 0);
        const double hw = 0.5 * v.slot_width, hh = v.throat_radius();
        // Touching the upper (y = +hh) and the lower face of the straight slot, and a grain between.
        const System across = grains({{0, hh - r, 0}, {0.1e-3, -(hh - r), 0}, {0, 0, 0}});
        CHECK(cluster_spans_throat(across, one_cluster(3), v, wall));
        // The lower grain in another cluster: the largest touches one side only.
        CHECK_FALSE(cluster_spans_throat(across, ContactClusters{{0, 1, 0}, {2, 1}}, v, wall));
        // Touching the two side faces (x = +-hw), one grain above the axis and one below: the
        // circular rule (the sign of y) would call this an arch; across the slot it is not.
        const System sides = grains({{hw - r, 0.1e-3, 0}, {-(hw - r), -0.1e-3, 0}});
        CHECK_FALSE(cluster_spans_throat(sides, one_cluster(2), v, wall));
        // The circular orifice: touching its throat above and below the axis.
        const ValveGeometry circle;
        const Wall round = passage_wall("valve", circle, 1e-3);
        const double rt = circle.throat_radius();
        CHECK(cluster_spans_throat(grains({{0, rt - r, 0}, {0, -(rt - r), 0}}), one_cluster(2), circle, round));
        CHECK_FALSE(cluster_spans_throat(grains({{0, rt - r, 0}, {0, 0, 0}}), one_cluster(2), circle, round));
    }

}  // TEST_SUITE
