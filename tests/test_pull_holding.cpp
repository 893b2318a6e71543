// The contact stiffness that holds the magnetic pull on the finest grain (shear/pull_holding.hpp)
// and the mass scaling that keeps the time step when it is applied (a grain batch's
// `mass_scaling`, lib/scene/scene_builder.cpp; the step's limits, lib/engine/timestep.cpp).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "shear/pull_holding.hpp"
#include "shear/shear_spec.hpp"
#include "test_support.hpp"

using mrjam_test::rel;
using namespace mrjam;
using json = nlohmann::json;

namespace {

PullHoldingInput trendler_pair() {
    PullHoldingInput in;
    in.min_diameter = 0.67e-6;  // the 33:67 fluid's finest and largest classes
    in.max_diameter = 24.44e-6;
    in.flux_density = 0.6;
    in.relative_permeability = 1000;
    in.saturation_magnetisation = std::numeric_limits<double>::infinity();
    in.youngs_modulus = 1e9;
    in.poisson_ratio = 0.278;
    return in;
}

// Two sizes, 0.5 um and 10 um, in a cell a few large grains wide: the finest grain cannot hold the
// large pair's pull at 1 GPa and 600 mT.
json bimodal_scene() {
    return {{"size",
             {{"distribution", "table"},
              {"basis", "number"},
              {"diameters", {"0.5 um", "10 um"}},
              {"frequencies", {0.9, 0.1}}}},
            {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}, {"poisson_ratio", 0.278}}},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "600 mT"}}},
            {"cell", {{"size", {"40 um", "40 um", "40 um"}}, {"raft_thickness", "10 um"}}}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("pull holding: the pull of two linear dipoles through the finest grain against its Hertz contact") {
        const PullHoldingInput in = trendler_pair();
        const PullHolding p = pull_holding(in);
        // By hand: m = 4 pi R^3 beta B0 / mu0 with beta = 999/1002; F = 2.25 * 3 mu0 m^2 / (2 pi d^4).
        const double mu0 = 4e-7 * M_PI, rl = 12.22e-6, rs = 0.335e-6;
        const double m = 4 * M_PI * rl * rl * rl * (999.0 / 1002.0) * 0.6 / mu0;
        const double d = 2 * (rl + rs);
        CHECK(p.pull == rel(2.25 * 3 * mu0 * m * m / (2 * M_PI * d * d * d * d)).epsilon(1e-12));
        // Hertz: 4/3 E* sqrt(R*) delta^1.5, E* = E / (2 (1 - nu^2)), delta = 0.3 rs.
        const double ystar = 1e9 / (2 * (1 - 0.278 * 0.278)), rstar = rs * rl / (rs + rl);
        CHECK(p.hold == rel(4.0 / 3.0 * ystar * std::sqrt(rstar) * std::pow(0.3 * rs, 1.5)).epsilon(1e-12));
        CHECK(p.factor == rel(p.pull / p.hold).epsilon(1e-12));
        CHECK(p.factor > 10);  // the 1 GPa blow-up of docs/notes/shear_3367.md
        CHECK(p.heavier_below == rel(in.min_diameter * std::sqrt(p.factor)).epsilon(1e-12));
        // A grain's Stokes number: tau = m / (6 pi mu R) = rho d^2 / (18 mu), times the rate.
        const double tau = 7800 * (4.0 / 3.0) * M_PI * 1e-18 / (6 * M_PI * 0.01 * 1e-6);  // d = 2 um
        CHECK(stokes_number(2e-6, 7800, 0.01, 1164) == rel(tau * 1164).epsilon(1e-12));
        CHECK(stokes_number(2e-6, 7800, 0.0, 1164) == 0.0);
    }

    TEST_CASE("pull holding: scale-free in size, inverse in the modulus, capped by saturation") {
        const PullHoldingInput base = trendler_pair();
        const PullHolding p = pull_holding(base);
        // Pull and hold both grow as the square of the size: the same fluid ten times coarser
        // needs the same stiffening.
        PullHoldingInput coarse = base;
        coarse.min_diameter *= 10;
        coarse.max_diameter *= 10;
        CHECK(pull_holding(coarse).factor == rel(p.factor).epsilon(1e-12));
        // Twice the modulus holds twice the load at the same overlap.
        PullHoldingInput stiff = base;
        stiff.youngs_modulus *= 2;
        CHECK(pull_holding(stiff).factor == rel(p.factor / 2).epsilon(1e-12));
        // Moments capped at a tenth of the induced magnetisation pull a hundredth as hard.
        PullHoldingInput capped = base;
        capped.saturation_magnetisation = 0.1 * 3 * (999.0 / 1002.0) * 0.6 / (4e-7 * M_PI);
        CHECK(pull_holding(capped).pull == rel(p.pull / 100).epsilon(1e-9));
        // Equal grains in a weak field: the contact holds, nothing changes.
        PullHoldingInput weak = base;
        weak.min_diameter = weak.max_diameter;
        weak.flux_density = 0.01;
        const PullHolding w = pull_holding(weak);
        CHECK(w.factor == 1.0);
        CHECK(w.heavier_below == 0.0);
    }

    TEST_CASE("shear scene: hold_magnetic_pull stiffens the grains, makes the fine ones heavier, keeps the step") {
        json s = bimodal_scene();
        const ShearSpec plain = read_shear_spec(s, "quick");
        s["scaling"] = {{"hold_magnetic_pull", true}};
        const ShearSpec held = read_shear_spec(s, "quick");
        const double factor = held.pull_holding.factor;
        REQUIRE(factor > 2);
        CHECK(plain.pull_holding.factor == 1.0);
        CHECK(held.material["youngs_modulus"].get<double>() == rel(factor * 1e9).epsilon(1e-12));

        Scene a = build_scene(engine_scene(plain, 0.6), BuildOptions{});
        Scene b = build_scene(engine_scene(held, 0.6), BuildOptions{});
        choose_timestep(a);
        choose_timestep(b);
        REQUIRE(a.system.particles.size() == b.system.particles.size());
        REQUIRE(a.system.particles.size() > 20);
        int heavier = 0, as_before = 0;
        for (std::size_t i = 0; i < a.system.particles.size(); ++i) {
            const double r = a.system.particles.radius[i];
            REQUIRE(b.system.particles.radius[i] == r);  // the same packing
            const double ratio = b.system.particles.mass[i] / a.system.particles.mass[i];
            const double inertia = b.system.particles.inertia[i] / a.system.particles.inertia[i];
            // Finer than D: the Stokes time of a D grain, m x (D / d)^2 (the finest: x factor).
            const double d_heavy = held.pull_holding.heavier_below;
            const bool fine = 2 * r < d_heavy;
            CHECK(ratio == rel(fine ? d_heavy * d_heavy / (4 * r * r) : 1.0).epsilon(1e-12));
            if (std::fabs(2 * r - 0.5e-6) < 1e-12) CHECK(ratio == rel(factor).epsilon(1e-9));
            CHECK(inertia == rel(ratio).epsilon(1e-12));
            (fine ? heavier : as_before) += 1;
        }
        CHECK(heavier > 0);
        CHECK(as_before > 0);
        // The Rayleigh time R sqrt(rho / G) of the finest grain is what it was: E and its mass
        // both x factor. The step is set by it in both (Stokes and Hertz times are longer).
        CHECK(a.limits.limiting == "Rayleigh time of the smallest grain");
        CHECK(b.limits.limiting == a.limits.limiting);
        CHECK(b.system.dt == rel(a.system.dt).epsilon(1e-9));
    }

    TEST_CASE("shear scene: scaling/heavier_below alone lengthens the step, the modulus as given") {
        json s = bimodal_scene();
        const ShearSpec plain = read_shear_spec(s, "quick");
        s["scaling"] = {{"heavier_below", "5 um"}};
        const ShearSpec heavy = read_shear_spec(s, "quick");
        CHECK(heavy.material["youngs_modulus"].get<double>() == rel(1e9));
        CHECK(heavy.heavier_below == rel(5e-6));
        // A 5 um grain's Stokes number at the quick ladder's fastest rate.
        CHECK(heavy.heavier_stokes_number == rel(stokes_number(5e-6, 7800, 0.01, heavy.rates.front())).epsilon(1e-12));
        Scene a = build_scene(engine_scene(plain, 0.6), BuildOptions{});
        Scene b = build_scene(engine_scene(heavy, 0.6), BuildOptions{});
        choose_timestep(a);
        choose_timestep(b);
        // The 0.5 um grains no longer set the step: their Rayleigh time is a 5 um grain's, ten
        // times theirs, unless the Hertz or Stokes time binds first; either way much longer.
        CHECK(b.system.dt > 3 * a.system.dt);
    }

    TEST_CASE("shear scene: a pull no modulus in the engine's range can hold is refused at hold_magnetic_pull") {
        json s = bimodal_scene();
        s["size"]["diameters"] = {"0.05 um", "10 um"};
        s["material"]["youngs_modulus"] = "9e12 Pa";
        s["field"]["flux_density"] = "5 T";
        s["magnetic"] = {{"saturation", "none"}};  // linear moments: the pull grows as B^2
        s["scaling"] = {{"hold_magnetic_pull", true}};
        try {
            (void)read_shear_spec(s, "quick");
            FAIL("a modulus past 1e13 Pa was accepted");
        } catch (const SceneError& e) {
            CHECK(e.path() == "/scaling/hold_magnetic_pull");
            CHECK(std::string(e.what()).find("past the engine's range") != std::string::npos);
        }
    }

    TEST_CASE("grain batch: mass_scaling is checked by path") {
        auto refused = [](const json& mass_scaling) {
            json engine = engine_scene(read_shear_spec(bimodal_scene(), "quick"), 0.6);
            engine["grains"][0]["mass_scaling"] = mass_scaling;
            try {
                (void)build_scene(engine, BuildOptions{});
            } catch (const SceneError& e) {
                return e.path();
            }
            return std::string("accepted");
        };
        CHECK(refused(json::object()) == "/grains/0/mass_scaling/below_diameter");
        CHECK(refused({{"below_diameter", "-1 um"}}) == "/grains/0/mass_scaling/below_diameter");
        CHECK(refused({{"below_diameter", "2 um"}, {"factor", 4}}) == "/grains/0/mass_scaling/factor");
        CHECK(refused({{"below_diameter", "2 um"}}) == "accepted");
    }
}
