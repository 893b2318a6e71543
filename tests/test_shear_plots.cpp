// The shear report's flow-curve picture: rates spanning more than a factor 20 go on log axes
// with the local slopes d ln stress / d ln rate in the legend; a narrow ladder stays linear.
#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "shear/shear_plots.hpp"
#include "test_support.hpp"

using namespace mrjam_test;
using json = nlohmann::json;

namespace {

json report_with(const std::vector<std::pair<double, double>>& rate_stress) {
    json curve = json::array();
    for (const auto& [rate, stress] : rate_stress)
        curve.push_back({{"rate_1_s", rate}, {"stress_Pa", stress}, {"error_Pa", 0.02 * stress}});
    return {{"fidelity", {{"tier", "quick"}}},
            {"results",
             {{"flow_curve", curve},
              {"fits", {{"bingham", {{"ok", true}, {"yield_stress_Pa", 1e4}, {"plastic_viscosity_Pa_s", 1.0}}}}},
              {"experiment", {{"yield_stress_Pa", 9e3}}}}}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("shear plots: a flow curve over decades of rate is drawn on log axes with its local slopes") {
        TempDir dir;
        // A plateau from 10 to 100 1/s (slope 0), then stress doubling over a decade (slope log10 2).
        const json wide = report_with({{1000, 20000}, {100, 10000}, {10, 10000}});
        const json paths = mrjam::write_shear_plots(dir.file("wide.json"), wide);
        const std::string svg = slurp(paths["flow_curve"].get<std::string>());
        CHECK(svg.find("high to low rates: 0.30, 0.00") != std::string::npos);
        CHECK(svg.find(">1e3<") != std::string::npos);  // a decade tick on the rate axis
        // Three decades of rate on linear axes would have no decade labels and no slopes.
        const json narrow = report_with({{1000, 20000}, {500, 15000}, {100, 10000}});
        const std::string lin =
            slurp(mrjam::write_shear_plots(dir.file("narrow.json"), narrow)["flow_curve"].get<std::string>());
        CHECK(lin.find("d ln stress") == std::string::npos);
        CHECK(lin.find(">1e3<") == std::string::npos);
        // A stress that is not positive cannot go on a log axis: the rates stay logarithmic, no slopes.
        const json negative = report_with({{1000, 20000}, {100, -500}, {10, 10000}});
        const std::string neg =
            slurp(mrjam::write_shear_plots(dir.file("neg.json"), negative)["flow_curve"].get<std::string>());
        CHECK(neg.find("d ln stress") == std::string::npos);
        CHECK(neg.find(">1e3<") != std::string::npos);
    }
}  // TEST_SUITE
