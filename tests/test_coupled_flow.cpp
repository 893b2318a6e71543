// The two-way coupled carrier flow: the radial Brinkman solve against its analytic solutions,
// and the coupled grid's continuity and circuit with grains packed in the throat, moving with the
// fluid, or resting in the step's corner.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "flow_quadrature.hpp"
#include "fluid/brinkman_slice.hpp"
#include "fluid/coupled_valve_flow.hpp"
#include "fluid/valve_flow.hpp"
#include "jam/coupled_flow.hpp"
#include "rel_approx.hpp"
#include "terms/drag_term.hpp"

using namespace mrjam;

namespace {

double max_error(const std::vector<double>& u, double radius, double (*exact)(double, double)) {
    double e = 0;
    for (std::size_t j = 0; j < u.size(); ++j) {
        const double r = (j + 0.5) * radius / static_cast<double>(u.size());
        e = std::max(e, std::abs(u[j] - exact(r, radius)));
    }
    return e;
}

constexpr double mu = 0.16, G = 1e6;

double poiseuille(double r, double R) { return G * (R * R - r * r) / (4 * mu); }

// Lattice of grains at rest filling the cylinder r < rc between z0 and z1 at fraction ~0.6,
// optionally outside r_in (an annulus).
void pack(System& s, double a, double r_in, double rc, double z0, double z1) {
    const double pitch = std::cbrt(4.0 / 3.0 * M_PI * a * a * a / 0.6);
    for (double z = z0 + 0.5 * pitch; z < z1; z += pitch)
        for (double x = -rc; x <= rc; x += pitch)
            for (double y = -rc; y <= rc; y += pitch) {
                const double r = std::hypot(x, y);
                if (r < rc - a && (r_in == 0 || r > r_in + a)) {
                    s.particles.position.push_back({x, y, z});
                    s.particles.radius.push_back(a);
                    s.particles.velocity.push_back({0, 0, 0});
                }
            }
}

CoupledFlowSettings settings(const ValveGeometry& v, double cell, int rings) {
    CoupledFlowSettings c;
    c.z_lo = -v.upstream_length;
    c.z_hi = v.downstream_length;
    c.cell_length = cell;
    c.rings = rings;
    c.feed_fraction = 0.345;
    c.supply_pressure = 105e3;
    c.viscosity = mu;
    c.bore_speed = 0.273;
    c.wall_gap = 20e-6;  // the grains packed below
    c.jet_length = 0.2e-3;
    return c;
}

ValveGeometry valve_20x() {
    ValveGeometry v;
    v.constriction_diameter = 0.88e-3;
    v.upstream_length = 1.0e-3;
    v.downstream_length = 0.5e-3;
    return v;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("brinkman slice: clear fluid is Poiseuille's parabola, second order in the ring width") {
        const double R = 0.5e-3;
        double previous = 0;
        for (int n : {8, 16, 32, 64}) {
            BrinkmanRings clear{R, mu, std::vector<double>(n, 0.0), std::vector<double>(n, 0.0)};
            const auto u = brinkman_profile(clear, G);
            const double e = max_error(u, R, poiseuille) / poiseuille(0, R);
            CAPTURE(n);
            CAPTURE(e);
            CHECK(e < 2.0 / (n * n));                       // the wall's half ring: O(dr^2)
            if (previous > 1e-12) CHECK(e < previous / 3);  // halving dr: ~4x
            previous = e;
            // Flow rate against pi R^4 G / (8 mu): the midpoint sum of a parabola is off by O(dr^2).
            CHECK(ring_flow_rate(u, R) == mrjam_test::rel(M_PI * R * R * R * R * G / (8 * mu)).epsilon(4.0 / (n * n)));
        }
    }

    TEST_CASE("brinkman slice: a uniform bed at rest is the Bessel profile of the Brinkman layer") {
        // -mu (1/r)(r u')' + beta u = G: u = (G / beta)(1 - I0(r / L) / I0(R / L)), L = sqrt(mu / beta).
        const double R = 0.5e-3, L = R / 10, beta = mu / (L * L);
        const int n = 400;  // 40 rings per Brinkman length
        BrinkmanRings bed{R, mu, std::vector<double>(n, beta), std::vector<double>(n, 0.0)};
        const auto u = brinkman_profile(bed, G);
        double e = 0;
        for (int j = 0; j < n; ++j) {
            const double r = (j + 0.5) * R / n;
            e = std::max(e,
                         std::abs(u[j] - G / beta * (1 - std::cyl_bessel_i(0, r / L) / std::cyl_bessel_i(0, R / L))));
        }
        CHECK(e < 1e-3 * G / beta);
        CHECK(u[0] == mrjam_test::rel(G / beta).epsilon(1e-3));  // Darcy's speed far from the wall
    }

    TEST_CASE("brinkman slice: grains moving through a dense bed carry the fluid with them") {
        const double R = 0.5e-3, L = R / 50, beta = mu / (L * L), v = 0.1;
        const int n = 200;
        BrinkmanRings bed{R, mu, std::vector<double>(n, beta), std::vector<double>(n, v)};
        const auto u = brinkman_profile(bed, 0.0);
        CHECK(u[0] == doctest::Approx(v).epsilon(1e-6));
        CHECK(u[n / 2] == doctest::Approx(v).epsilon(1e-6));
        CHECK(u[n - 1] < 0.5 * v);  // the no-slip wall, within the Brinkman layer
    }

    TEST_CASE("coupled flow: without grains, Poiseuille in every slice, one flow rate, the circuit at Q0") {
        const ValveGeometry v = valve_20x();
        CoupledFlowSettings c = settings(v, 50e-6, 16);
        c.wall_gap = 0;  // no grains
        const CoupledFlow cf(v, c);
        System s;
        s.terms.add(std::make_unique<DragTerm>(mu, 1));
        const AxialResistanceState st = cf.update(s);
        CHECK(st.scale == doctest::Approx(1.0));
        const double q0 = ValveFlow(v, 0.273).reference_flow_rate();
        CHECK(cf.reference_flow_rate() == mrjam_test::rel(q0));
        // The grid's clear pressure against Poiseuille's integral: the taper's slices take R at their
        // centre (midpoint rule on R^-4 with 50 um slices: < 0.5 %).
        const double exact = clear_stretch_pressure(v, -v.upstream_length, v.downstream_length, 0.2e-3, mu, q0);
        CHECK(cf.clear_stretch_pressure() == doctest::Approx(exact).epsilon(0.01));
        CHECK(st.stretch_pressure == doctest::Approx(exact).epsilon(0.01));
        // Continuity through bore, taper (between slice centres too), throat, jet and bore past it; the
        // ring profile read between centres is linear in r, 2 % from the ring sum at 16 rings.
        for (double z : {-0.95e-3, -0.5e-3, -0.33e-3, -0.27e-3, -0.12e-3, 0.0, 0.05e-3, 0.15e-3, 0.22e-3, 0.4e-3}) {
            CAPTURE(z);
            CHECK(mrjam_test::section_flow_rate(*cf.field(), v, z, 2000) == mrjam_test::rel(q0).epsilon(0.02));
        }
        // No flow through the wall; in the cone the stream runs along it (u_r / u_z = r R' / R).
        const double z = -0.5e-3, R = v.passage_radius(z);
        CHECK(cf.field()->velocity({1.001 * R, 0, z}, 0).z == 0.0);
        const Vec3 u = cf.field()->velocity({0.5 * R, 0, z}, 0);
        CHECK(u.x / u.z == mrjam_test::rel(0.5 * (v.throat_radius() - v.bore_radius()) / v.taper_length));
        // Past the exit the jet's edge is the stream's, and the corner outside it is still.
        const double zj = v.throat_end_z() + 0.1e-3, rf = cf.field()->stream_radius(zj);
        CHECK(rf == mrjam_test::rel(0.5 * (v.throat_radius() + v.bore_radius())));
        CHECK(cf.field()->velocity({0.5 * rf, 0, zj}, 0).z > 0);
        CHECK(cf.field()->velocity({1.01 * rf, 0, zj}, 0).z == 0.0);
        CHECK(cf.field()->ring_at({1.01 * rf, 0, zj}) == -1);
        // A raised supply (protocol/hold_pressure) through the same circuit: clear fluid is linear,
        // Q0 times the pressure ratio.
        CHECK(cf.update(s, 2.5 * c.supply_pressure).scale == doctest::Approx(2.5));
    }

    TEST_CASE(
        "coupled flow: a packed plug at rest in the throat throttles the flow; moving with the fluid it does not") {
        const ValveGeometry v = valve_20x();
        const CoupledFlow cf(v, settings(v, 100e-6, 8));
        System s;
        s.terms.add(std::make_unique<DragTerm>(mu, 1));
        pack(s, 20e-6, 0.0, v.throat_radius(), -0.5 * v.throat_length, 0.5 * v.throat_length);
        REQUIRE(s.particles.size() > 1000);
        const AxialResistanceState at_rest = cf.update(s);
        CAPTURE(at_rest.max_fraction);
        CHECK(at_rest.max_fraction > 0.45);
        // Darcy through the plug: Q0 over the throat's section (1.15 m/s) x beta (6 pi mu a x n x the
        // Kozeny-Carman factor: ~5e9 Pa s/m^2 at 0.6 for these grains) x its 0.2 mm, with the lattice's
        // layers filling the second half less: ~0.8 MPa, so the scale ~ P / (P + 0.8 MPa).
        CHECK(at_rest.arrested_pressure > 5 * 105e3);
        CHECK(at_rest.scale < 0.2);
        CHECK(cf.field()->drag_factor({0, 0, -50e-6}) > 1.5);
        // The same grains at the clear fluid's speed where they sit: the drag-weighted ring means
        // differ from the ring centres' speed by the parabola's curvature inside a ring, so the flow is
        // within a few per cent of the open one, not exactly it.
        const CoupledFlow open(v, settings(v, 100e-6, 8));
        for (std::size_t i = 0; i < s.particles.size(); ++i)
            s.particles.velocity[i] = open.field()->velocity(s.particles.position[i], 0);
        CHECK(cf.update(s).scale > 0.97);
    }

    TEST_CASE("coupled flow: a ring of grains resting along the bore wall: the fluid goes round it") {
        // An annulus of grains at rest packed at ~0.6 over 0.3 mm of the upstream bore, r > 0.6 r_b:
        // a Darcy-Brinkman slice sends the flow through the open core (its axis speeds up) and
        // nearly none through the bed, so the circuit hardly notices it. The one-profile option
        // charges the bed as if the source's profile ran through it: beta ~ 5e9 Pa s/m^2 for these
        // grains x ~0.07 m/s (the ramp's mean speed there) x 0.3 mm x the bed's 0.64 of the section
        // ~ 70 kPa, so its scale ~ P / (P + 70 kPa) ~ 0.6.
        const ValveGeometry v = valve_20x();
        const CoupledFlow cf(v, settings(v, 100e-6, 10));
        const CoupledFlow clear(v, settings(v, 100e-6, 10));
        System s;
        s.terms.add(std::make_unique<DragTerm>(mu, 1));
        pack(s, 20e-6, 0.6 * v.bore_radius(), v.bore_radius(), -0.9e-3, -0.6e-3);
        REQUIRE(s.particles.size() > 1000);
        const AxialResistanceState st = cf.update(s);
        CHECK(st.scale > 0.95);
        const AxialResistance one(v, 0.0, -v.upstream_length, v.downstream_length, 100e-6, 0.345, 105e3);
        ValveFlow source(v, 0.273);
        CHECK(one.update(s, source, true).scale < 0.8);
        const double z = -0.75e-3;
        const double axis = cf.field()->velocity({0, 0, z}, 0).z;
        CHECK(axis > 1.5 * clear.field()->velocity({0, 0, z}, 0).z);  // the core carries the flow
        CHECK(cf.field()->velocity({0.8 * v.bore_radius(), 0, z}, 0).z < 0.05 * axis);
    }
}

TEST_SUITE("unit") {
    // The drag pass asks for velocity and drag factor together (drag_at, locating a grain once); it
    // must give exactly what the two separate calls give, everywhere: bore, taper, throat, jet and
    // its still corner, beyond the grid's ends and outside the stream.
    TEST_CASE("coupled flow: drag_at is velocity and drag_factor, bit for bit") {
        const ValveGeometry v = valve_20x();
        const double cell = 50e-6;
        CoupledValveFlow flow(v, -v.upstream_length, v.downstream_length, cell, 16, 0.2e-3);
        // A field with no symmetry to hide a wrong index: speeds and factors varying by slice and ring.
        std::vector<double> speed(flow.axial_speed().size()), factor(speed.size());
        for (std::size_t m = 0; m < speed.size(); ++m) {
            speed[m] = 0.1 + 0.01 * static_cast<double>(m % 37);
            factor[m] = 1.0 + 0.5 * static_cast<double>(m % 11);
        }
        flow.set_field(speed, factor);
        long compared = 0, off_grid = 0, still_corner = 0;
        for (int a = 0; a < 4000; ++a) {
            const double z = -1.2e-3 + 1.9e-3 * ((a * 0.6180339887) - std::floor(a * 0.6180339887));
            const double r = 1.05 * v.bore_radius() * ((a * 0.7548776662) - std::floor(a * 0.7548776662));
            const double phi = 0.37 * a;
            const Vec3 x{r * std::cos(phi), r * std::sin(phi), z};
            const FlowField::Drag d = flow.drag_at(x, 0.0);
            const Vec3 u = flow.velocity(x, 0.0);
            CHECK((d.velocity.x == u.x && d.velocity.y == u.y && d.velocity.z == u.z));
            CHECK(d.factor == flow.drag_factor(x));
            ++compared;
            off_grid += z < -v.upstream_length || z >= v.downstream_length;
            still_corner += flow.ring_at(x) == -1 && z >= -v.upstream_length && z < v.downstream_length;
        }
        // The points reached every kind of place.
        CHECK(off_grid > 100);
        CHECK(still_corner > 10);
        MESSAGE(compared << " points, " << off_grid << " off the grid, " << still_corner
                         << " in the jet's still corner");
    }

    // slice_at starts from a table and walks to the slice; it must name the slice a binary search
    // over the slices names, for every z: each slice's ends and their neighbouring doubles (where a
    // rounded bin index would start on the wrong side), the grid's ends, far outside it, and NaN.
    TEST_CASE("coupled flow: slice_at is the binary search's slice, at every slice end") {
        const ValveGeometry v = valve_20x();
        for (double cell : {50e-6, 88e-6, 23e-6}) {
            CoupledValveFlow flow(v, -v.upstream_length, v.downstream_length, cell, 8, 0.2e-3);
            const auto& slices = flow.slices();
            auto searched = [&](double z) {
                const auto it = std::upper_bound(slices.begin(), slices.end(), z,
                                                 [](double value, const FlowSlice& s) { return value < s.z_hi; });
                return it == slices.end() ? slices.size() - 1 : static_cast<std::size_t>(it - slices.begin());
            };
            std::vector<double> zs{-1.0, 1.0, -1e300, 1e300, std::nan("")};
            for (const FlowSlice& s : slices)
                for (double end : {s.z_lo, s.z_hi, s.centre()})
                    for (double z : {std::nextafter(end, -1.0), end, std::nextafter(end, 1.0)}) zs.push_back(z);
            for (int a = 0; a < 20000; ++a)
                zs.push_back(-1.3e-3 + 2.0e-3 * ((a * 0.6180339887) - std::floor(a * 0.6180339887)));
            long wrong = 0;
            for (double z : zs) wrong += flow.slice_at(z) != searched(z);
            CHECK(wrong == 0);
            CHECK(slices.size() > 10);
        }
    }
}
