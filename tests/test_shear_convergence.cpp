// The convergence study's statistics: a size's seeds averaged rate by rate with the larger of the
// seed spread's and the block errors' standard error, the Bingham yield of the mean curve, and the
// verdict over sizes (converged where each step changes less than its combined error).
#include <doctest/doctest.h>

#include <cmath>

#include "rel_approx.hpp"
#include "scene/scene_node.hpp"
#include "shear/convergence.hpp"
#include "shear/shear_spec.hpp"

using mrjam_test::rel;
using nlohmann::json;

namespace {

// A shear report's results as `mrjam shear` writes them: an exact Bingham line tau_y + eta g,
// every rate shifted by `offset`, with block error `error`.
json report_of(double tau_y, double eta, double offset, double error) {
    json curve = json::array();
    for (double g : {1164.0, 582.0, 291.0})
        curve.push_back({{"rate_1_s", g}, {"stress_Pa", tau_y + eta * g + offset}, {"error_Pa", error}});
    return {{"results", {{"flow_curve", curve}, {"yield_stress_Pa", tau_y + offset}, {"cell", {{"grains", 500}}}}}};
}

mrjam::ShearSpec spec_of() {
    return mrjam::read_shear_spec({{"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
                                   {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}}},
                                   {"fluid", {{"viscosity", "10 mPa s"}}},
                                   {"field", {{"flux_density", "600 mT"}}},
                                   {"fit", {{"bingham_min_rate", "200 1/s"}}}},
                                  "quick");
}

json size_with(double edge, double y, double e) {
    return {{"edge_m", edge}, {"yield_stress_Pa", y}, {"yield_stress_error_Pa", e}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("shear convergence: a size's seeds are averaged with the larger of their spread and block errors") {
        const mrjam::ShearSpec spec = spec_of();
        // Three seeds 1 kPa apart with 100 Pa block errors: the spread wins, sd 1000 / sqrt(3).
        const json size = mrjam::size_summary(
            spec, 90e-6, {report_of(45e3, 2, -1000, 100), report_of(45e3, 2, 0, 100), report_of(45e3, 2, 1000, 100)});
        REQUIRE(size["flow_curve"].size() == 3);
        const json& q = size["flow_curve"][0];
        CHECK(q["stress_Pa"].get<double>() == rel(45e3 + 2 * 1164));
        CHECK(q["seed_sd_Pa"].get<double>() == rel(1000));
        CHECK(q["error_Pa"].get<double>() == rel(1000 / std::sqrt(3.0)));
        CHECK(q["block_error_Pa"].get<double>() == rel(std::sqrt(3 * 100.0 * 100.0) / 3));
        // The mean curve is the exact line: the fit recovers 45 kPa. Its intercept's error is the
        // points' errors propagated to the extrapolation, sigma sqrt(S_xx / (n S_xx - S_x^2)), here
        // larger than the seeds' Bingham values' standard error (1000 / sqrt 3), so it is quoted.
        CHECK(size["yield_stress_Pa"].get<double>() == rel(45e3));
        const double sx = 1164 + 582 + 291, sxx = 1164.0 * 1164 + 582.0 * 582 + 291.0 * 291;
        const double propagated = 1000 / std::sqrt(3.0) * std::sqrt(sxx / (3 * sxx - sx * sx));
        CHECK(size["yield_stress_error_Pa"].get<double>() == rel(propagated));
        CHECK(size["seed_yield_error_Pa"].get<double>() == rel(1000 / std::sqrt(3.0)));
        CHECK(size["error_from"] == "the fit of the mean curve");

        // Seeds that agree: the block errors, propagated, are the error.
        const json calm = mrjam::size_summary(spec, 90e-6, {report_of(45e3, 2, 0, 900), report_of(45e3, 2, 0, 900)});
        CHECK(calm["flow_curve"][1]["error_Pa"].get<double>() == rel(900 / std::sqrt(2.0)));
        // No finished seed: no figure, not a zero.
        CHECK(mrjam::size_summary(spec, 90e-6, {})["yield_stress_Pa"].is_null());
    }

    TEST_CASE("shear convergence: the verdict finds the plateau, or says it was not reached") {
        // 50 -> 45 moves by more than sqrt(2) kPa; 45 -> 44.5 by less: converged from the second
        // size, the mean of the last two weighted by their errors.
        const json v = mrjam::convergence_verdict(
            {size_with(90e-6, 50e3, 1e3), size_with(112e-6, 45e3, 1e3), size_with(135e-6, 44.5e3, 1e3)});
        CHECK(v["converged"] == true);
        CHECK(v["converged_from_edge_m"].get<double>() == rel(112e-6));
        CHECK(v["yield_stress_Pa"].get<double>() == rel(44.75e3));
        CHECK(v["yield_stress_error_Pa"].get<double>() == rel(1e3 / std::sqrt(2.0)));
        REQUIRE(v["steps"].size() == 2);
        CHECK(v["steps"][0]["change_Pa"].get<double>() == rel(-5e3));

        // Still falling at the largest size: not converged, the largest cell's value.
        const json falling = mrjam::convergence_verdict(
            {size_with(90e-6, 50e3, 1e3), size_with(112e-6, 45e3, 1e3), size_with(135e-6, 40e3, 1e3)});
        CHECK(falling["converged"] == false);
        CHECK(falling["converged_from_edge_m"].is_null());
        CHECK(falling["yield_stress_Pa"].get<double>() == rel(40e3));

        // A plateau broken by the last step is no plateau: only the last size would be left.
        const json late = mrjam::convergence_verdict(
            {size_with(90e-6, 45e3, 1e3), size_with(112e-6, 45.2e3, 1e3), size_with(135e-6, 52e3, 1e3)});
        CHECK(late["converged"] == false);
    }

    TEST_CASE("shear convergence: the block's sizes and seeds are checked by their keys") {
        json scene = {{"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
                      {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}}},
                      {"fluid", {{"viscosity", "10 mPa s"}}},
                      {"field", {{"flux_density", "600 mT"}}}};
        // By default the cell's edge and 1.25 and 1.5 times it, three seeds.
        const mrjam::ShearSpec d = mrjam::read_shear_spec(scene, "quick");
        REQUIRE(d.converge_cell_sizes.size() == 3);
        CHECK(d.converge_cell_sizes[2] == rel(1.5 * d.cell.x));
        CHECK(d.converge_seeds == 3);
        for (const auto& [block, path] : std::vector<std::pair<json, std::string>>{
                 {{{"cell_sizes", {"90 um", "100 um"}}}, "/convergence/cell_sizes"},
                 {{{"cell_sizes", {"90 um", "120 um", "100 um"}}}, "/convergence/cell_sizes/2"},
                 {{{"seeds", 1}}, "/convergence/seeds"},
                 {{{"sizes", 3}}, "/convergence/sizes"}}) {
            json s = scene;
            s["convergence"] = block;
            CAPTURE(path);
            try {
                (void)mrjam::read_shear_spec(s, "quick");
                FAIL("accepted");
            } catch (const mrjam::SceneError& e) {
                CHECK(std::string(e.what()).find(path) != std::string::npos);
            }
        }
    }
}
