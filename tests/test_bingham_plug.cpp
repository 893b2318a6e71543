// The continuum tier's Bingham plug (lib/jam/bingham_plug.hpp): the holding pressure against
// closed forms (straight pipe, cone), the quadrature's order, the yield-stress table's
// interpolation and refusals, and the table read from what the shear mode writes.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "jam/bingham_plug.hpp"
#include "rel_approx.hpp"
#include "scene/scene_node.hpp"
#include "shear/shear_analysis.hpp"
#include "shear/shear_spec.hpp"

using mrjam_test::rel;

using namespace mrjam;
using json = nlohmann::json;

namespace {

// A straight pipe: no taper, no throat, the constriction as wide as the bore.
ValveGeometry straight_pipe(double diameter, double upstream, double downstream) {
    ValveGeometry v;
    v.tube_inner_diameter = diameter;
    v.constriction_diameter = diameter;
    v.taper_length = 0;
    v.throat_length = 0;
    v.upstream_length = upstream;
    v.downstream_length = downstream;
    return v;
}

// tau_y = slope B exactly for |B| up to 1 T: the integrand is then as smooth as B(z).
YieldStressTable linear_table(double slope) { return YieldStressTable({{0.0, 0.0, ""}, {1.0, slope, ""}}, "/t"); }

std::function<double(double)> gaussian(double peak, double centre, double width) {
    return [=](double z) { return peak * std::exp(-0.5 * (z - centre) * (z - centre) / (width * width)); };
}

std::string error_path(const std::function<void()>& f) {
    try {
        f();
    } catch (const SceneError& e) {
        return e.path();
    }
    return "(no SceneError)";
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("bingham plug: a uniform field in a straight pipe holds 4 tau L / d") {
        const double d = 2.6e-3, L = 4e-3 + 3e-3, tau = 30e3;
        const ValveGeometry pipe = straight_pipe(d, 4e-3, 3e-3);
        const YieldStressTable table({{0.5, tau, ""}}, "/t");
        const double expected = 4.0 * tau * L / d;
        for (int samples : {2, 10, 1000}) {
            // The field's sign does not matter: the table is read at |B|.
            const auto e = bingham_plug_hold(
                pipe, [](double) { return -0.5; }, table, 100e3, samples);
            CHECK(std::abs(e.hold_pressure - expected) <= 1e-12 * expected);
            CHECK(e.margin == rel(expected / 100e3).epsilon(1e-12));
            CHECK(e.plug_length == rel(L).epsilon(1e-12));  // uniform: the plug is the whole passage
            CHECK(e.peak_yield_stress == tau);
            CHECK_FALSE(e.table_extrapolated);
        }
        // It jams when the hold exceeds the supply, and not otherwise.
        auto field = [](double) { return 0.5; };
        CHECK(bingham_plug_hold(pipe, field, table, 0.99 * expected, 10).jams);
        CHECK_FALSE(bingham_plug_hold(pipe, field, table, 1.01 * expected, 10).jams);
    }

    TEST_CASE("bingham plug: a cone with uniform tau holds (2 tau L / (r1 - r0)) ln(r1 / r0), within Simpson's bound") {
        ValveGeometry v;  // the 30x valve: bore, cone, throat, step back to the bore
        const double tau = 40e3, rb = v.bore_radius(), rt = v.throat_radius();
        const double up_bore = v.upstream_length + v.taper_start_z(),
                     down_bore = v.downstream_length - v.throat_end_z();
        const double exact =
            2.0 * tau *
            ((up_bore + down_bore) / rb + v.taper_length / (rt - rb) * std::log(rt / rb) + v.throat_length / rt);
        const YieldStressTable table({{0.6, tau, ""}}, "/t");
        const int samples = 400;
        const auto e = bingham_plug_hold(
            v, [](double) { return 0.6; }, table, 1e5, samples);
        CHECK(e.pieces == 4);
        // Only the cone is not integrated exactly: f = 2 tau / r with r linear of slope s has
        // f'''' = 48 tau s^4 / r^5, largest at the throat; the cone holds at least
        // samples * taper / total - 1 intervals (an even number, rounded from its share).
        const double s = (rb - rt) / v.taper_length;
        const double n_cone = samples * v.taper_length / (v.upstream_length + v.downstream_length) - 1.0;
        const double h = v.taper_length / n_cone;
        const double bound = v.taper_length * std::pow(h, 4) * 48.0 * tau * std::pow(s, 4) / std::pow(rt, 5) / 180.0;
        CHECK(std::abs(e.hold_pressure - exact) <= bound);
        CHECK(std::abs(e.hold_pressure - exact) <= 1e-8 * exact);
    }

    TEST_CASE("bingham plug: Simpson's error falls as samples^-4 on a Gaussian field in a straight pipe") {
        const double d = 1.32e-3, up = 4e-3, down = 4e-3, k = 50e3, B0 = 0.5, zc = 0.3e-3, w = 1e-3;
        const ValveGeometry pipe = straight_pipe(d, up, down);
        // Exact: 4 k / d times the Gaussian's integral over [-up, down].
        const double exact =
            4.0 * k / d * B0 * w * std::sqrt(std::numbers::pi / 2.0) *
            (std::erf((down - zc) / (w * std::sqrt(2.0))) + std::erf((up + zc) / (w * std::sqrt(2.0))));
        std::vector<double> err;
        for (int samples : {32, 64, 128, 256})
            err.push_back(std::abs(
                bingham_plug_hold(pipe, gaussian(B0, zc, w), linear_table(k), 1e5, samples).hold_pressure - exact));
        for (std::size_t i = 1; i < err.size(); ++i) {
            const double order = std::log2(err[i - 1] / err[i]);
            CHECK(order > 3.8);
            CHECK(order < 4.2);
        }
        CHECK(err.back() < 1e-6 * exact);
    }

    TEST_CASE("bingham plug: split at the taper's ends and the exit, the valve keeps fourth order") {
        // Pieces of 2, 1, 1 and 3 mm: samples = 14 m gives them 4m, 2m, 2m and 6m intervals,
        // so doubling m halves every h exactly.
        ValveGeometry v;
        v.taper_length = 1e-3;
        v.throat_length = 1e-3;
        v.upstream_length = 3.5e-3;
        v.downstream_length = 3.5e-3;
        const auto field = gaussian(0.5, 0.2e-3, 1.5e-3);
        auto hold = [&](int samples) { return bingham_plug_hold(v, field, linear_table(50e3), 1e5, samples); };
        const double reference = hold(14 * 2048).hold_pressure;  // h 64 times finer than m = 32's
        std::vector<double> err;
        for (int m : {4, 8, 16, 32}) {
            const auto e = hold(14 * m);
            CHECK(e.pieces == 4);
            err.push_back(std::abs(e.hold_pressure - reference));
        }
        for (std::size_t i = 1; i < err.size(); ++i) {
            const double order = std::log2(err[i - 1] / err[i]);
            CHECK(order > 3.8);
            CHECK(order < 4.2);
        }
    }

    TEST_CASE("bingham plug: the plug length of a Gaussian yield-stress profile is its full width at half maximum") {
        const double w = 0.5e-3;
        const ValveGeometry pipe = straight_pipe(1.32e-3, 4e-3, 4e-3);
        const auto e = bingham_plug_hold(pipe, gaussian(0.5, 0.1e-3, w), linear_table(50e3), 1e5, 4000);
        // Linear interpolation between samples locates the crossings to O(h^2).
        CHECK(e.plug_length == rel(2.0 * w * std::sqrt(2.0 * std::log(2.0))).epsilon(1e-4));
        CHECK(e.peak_flux_density == rel(0.5).epsilon(1e-4));
        CHECK(e.peak_yield_stress == rel(25e3).epsilon(1e-4));
    }

    TEST_CASE("bingham plug: a slot's hydraulic diameter is 4 A / P of the disc cut by the rectangle") {
        ValveGeometry v;
        v.orifice = Orifice::slot;
        v.slot_width = 0.6e-3;
        const double w = v.slot_width, hgt = v.constriction_diameter, R = v.bore_radius();
        CHECK(passage_hydraulic_diameter(v, 0.0) == rel(2.0 * w * hgt / (w + hgt)).epsilon(1e-12));  // straight slot
        CHECK(passage_hydraulic_diameter(v, -3e-3) == rel(2.0 * R).epsilon(1e-12));                  // bore
        // In the taper, near its start, the rectangle's corners lie outside the bore: compare with
        // a polygon of the boundary rho(theta) = min(R, X / |cos|, Y / |sin|) (independent of
        // SlotOrifice's closed form).
        const double z = v.taper_start_z() + 0.1 * v.taper_length;
        const SlotOrifice s = v.slot();
        const double X = s.half_x(z), Y = s.half_y(z);
        REQUIRE(X * X + Y * Y > R * R);
        const int n = 200000;
        double area = 0, perimeter = 0;
        auto point = [&](int i) {
            const double t = 2.0 * std::numbers::pi * i / n;
            const double c = std::abs(std::cos(t)), sn = std::abs(std::sin(t));
            const double rho = std::min({R, c > 0 ? X / c : std::numeric_limits<double>::infinity(),
                                         sn > 0 ? Y / sn : std::numeric_limits<double>::infinity()});
            return std::pair{rho * std::cos(t), rho * std::sin(t)};
        };
        for (int i = 0; i < n; ++i) {
            const auto [x0, y0] = point(i);
            const auto [x1, y1] = point(i + 1);
            area += 0.5 * (x0 * y1 - x1 * y0);
            perimeter += std::hypot(x1 - x0, y1 - y0);
        }
        CHECK(passage_hydraulic_diameter(v, z) == rel(4.0 * area / perimeter).epsilon(1e-6));
    }

    TEST_CASE(
        "bingham plug: the slot, split where its corners cross the bore and graded at its taper start, converges at "
        "fourth order") {
        ValveGeometry v;
        v.orifice = Orifice::slot;
        v.slot_width = 0.6e-3;
        const YieldStressTable table({{0.6, 40e3, ""}}, "/t");
        auto hold = [&](int samples) {
            return bingham_plug_hold(
                       v, [](double) { return 0.6; }, table, 1e5, samples)
                .hold_pressure;
        };
        CHECK(bingham_plug_hold(
                  v, [](double) { return 0.6; }, table, 1e5, 100)
                  .pieces == 5);
        // Finer still, the sum's rounding (n eps) would pass the rule's error.
        const double reference = hold(1 << 15);
        // The pieces' shares are rounded to even counts, so h does not halve exactly: fit the
        // slope of log error against log samples over a factor 16.
        std::vector<double> x, y;
        for (int samples : {400, 800, 1600, 3200, 6400}) {
            x.push_back(std::log(samples));
            y.push_back(std::log(std::abs(hold(samples) - reference)));
        }
        double mx = 0, my = 0;
        for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / x.size(), my += y[i] / y.size();
        double sxy = 0, sxx = 0;
        for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
        const double slope = sxy / sxx;
        CHECK(slope < -3.5);
        CHECK(slope > -4.5);
    }

    TEST_CASE("bingham plug: the yield stress is linear in |B| between points, from 0 below them, held beyond") {
        const YieldStressTable t({{0.2, 10e3, ""}, {0.4, 30e3, ""}, {0.6, 40e3, ""}}, "/t");
        CHECK(t.yield_stress(0.0) == 0.0);
        CHECK(t.yield_stress(0.1) == rel(5e3));  // from (0, 0) to the first point
        CHECK(t.yield_stress(0.2) == rel(10e3));
        CHECK(t.yield_stress(0.3) == rel(20e3));
        CHECK(t.yield_stress(-0.3) == rel(20e3));
        CHECK(t.yield_stress(0.5) == rel(35e3));
        CHECK(t.yield_stress(0.6) == rel(40e3));
        CHECK_FALSE(t.extrapolated(0.6));
        CHECK(t.yield_stress(0.9) == rel(40e3));
        CHECK(t.extrapolated(0.9));
        // A table that starts at B = 0 keeps its value there.
        const YieldStressTable z({{0.0, 2e3, ""}, {0.2, 10e3, ""}}, "/t");
        CHECK(z.yield_stress(0.0) == rel(2e3));
        CHECK(z.yield_stress(0.1) == rel(6e3));
        // The estimate says when the field went beyond the table.
        const auto e = bingham_plug_hold(straight_pipe(1e-3, 1e-3, 1e-3), gaussian(0.8, 0, 0.3e-3), t, 1e5, 100);
        CHECK(e.table_extrapolated);
        CHECK(e.table_last_flux_density == 0.6);
    }

    TEST_CASE("bingham plug: a bad yield-stress table is refused naming the JSON path of the point") {
        CHECK(error_path([] { YieldStressTable({}, "/continuum/yield_stress"); }) == "/continuum/yield_stress");
        CHECK(error_path([] { YieldStressTable({{0.3, 1e3, ""}, {0.2, 2e3, ""}}, "/y"); }) == "/y/1/0");
        CHECK(error_path([] { YieldStressTable({{0.3, 1e3, ""}, {0.3, 2e3, ""}}, "/y"); }) == "/y/1/0");
        CHECK(error_path([] { YieldStressTable({{-0.1, 1e3, ""}}, "/y"); }) == "/y/0/0");
        CHECK(error_path([] { YieldStressTable({{0.1, -1e3, ""}}, "/y"); }) == "/y/0/1");
        CHECK(error_path([] { YieldStressTable({{0.1, 1e3, ""}, {0.2, std::nan(""), ""}}, "/y"); }) == "/y/1/1");
        const YieldStressTable ok({{0.1, 1e3, ""}}, "/y");
        const ValveGeometry v;
        CHECK_THROWS_AS(bingham_plug_hold(
                            v, [](double) { return 0.1; }, ok, 1e5, 1),
                        std::invalid_argument);
        CHECK_THROWS_AS(bingham_plug_hold(
                            v, [](double) { return 0.1; }, ok, 0.0, 10),
                        std::invalid_argument);
        CHECK_THROWS_AS(bingham_plug_hold(
                            v, [](double) { return std::nan(""); }, ok, 1e5, 10),
                        std::invalid_argument);
    }

    TEST_CASE("bingham plug: the table is read from what the shear mode writes (Bingham intercept and field sweep)") {
        json scene = {{"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
                      {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}}},
                      {"fluid", {{"viscosity", "10 mPa s"}}},
                      {"field", {{"flux_density", "600 mT"}}},
                      {"field_sweep", {{"flux_densities", {"200 mT", "600 mT"}}}}};
        const ShearSpec spec = read_shear_spec(scene, "quick");
        // A main flow curve on an exact Bingham line, and one measured rate per sweep cell (after its pre-shear).
        const double tau_y = 45e3, eta = 2.0;
        json rates = json::array();
        for (double rate : {1164.0, 582.0, 291.0, 100.0})
            rates.push_back({{"rate_1_s", rate},
                             {"stress_Pa", tau_y + eta * rate},
                             {"error_Pa", 100.0},
                             {"strain", 0.1},
                             {"series_upper_Pa", json::array()}});
        auto sweep_field = [](double b, double stress) {
            return json{
                {"flux_density_T", b}, {"rate_1_s", 100.0}, {"stress_Pa", stress}, {"error_Pa", 1.0}, {"strain", 0.05}};
        };
        const json cells = {{{"rates", rates}, {"grains", 500}, {"timestep_s", 1e-9}}};
        const json fields = {sweep_field(0.2, 5e3), sweep_field(0.6, 48e3)};
        json report = {
            {"mode", "shear"}, {"inputs", spec.resolved}, {"results", summarise(spec, cells, nullptr, fields)}};

        const YieldStressTable t = yield_stress_table_from_shear_report(report, "/shear_report");
        REQUIRE(t.points().size() == 2);
        CHECK(t.points()[0].flux_density == rel(0.2));
        CHECK(t.points()[0].yield_stress == rel(5e3));
        CHECK(t.points()[0].source == "results.field_sweep[0].stress_Pa");
        CHECK(t.points()[1].flux_density == rel(0.6));  // the intercept wins over the sweep's 48 kPa
        CHECK(t.points()[1].yield_stress == rel(tau_y).epsilon(1e-9));
        CHECK(t.points()[1].source == "results.yield_stress_Pa");
        // Without the sweep: the intercept alone.
        CHECK(yield_stress_table_from_shear_report(report, "/r", false).points().size() == 1);

        // A partial report's intercept is not used: the sweep's cells are finished ones.
        json partial = report;
        partial["results"]["flow_curve_complete"] = false;
        const YieldStressTable p = yield_stress_table_from_shear_report(partial, "/r");
        CHECK(p.points().back().yield_stress == rel(48e3));
        CHECK(error_path([&] { yield_stress_table_from_shear_report(partial, "/r", false); }) == "/r");
        // A negative value, another mode: refused at the caller's path, the message naming the key.
        json negative = report;
        negative["results"]["field_sweep"][0]["stress_Pa"] = -1.0;
        try {
            yield_stress_table_from_shear_report(negative, "/shear_report");
            FAIL("no SceneError");
        } catch (const SceneError& e) {
            CHECK(e.path() == "/shear_report");
            CHECK(e.message().find("/results/field_sweep/0/stress_Pa") != std::string::npos);
        }
        json calibration = report;
        calibration["mode"] = "shear-calibrate";
        CHECK(error_path([&] { yield_stress_table_from_shear_report(calibration, "/r"); }) == "/r");
    }
}  // TEST_SUITE
