// The design chain as a library function (design/design_workflow.hpp), with an analytic field
// in place of the FEM: it runs where GetDP is not installed, and its field is known exactly.
#include <doctest/doctest.h>

#include <filesystem>

#include "design/design_workflow.hpp"
#include "test_support.hpp"

using mrjam_test::slurp;
using mrjam_test::TempDir;
using nlohmann::json;

namespace {

// A uniform B across the valve (y, transverse to the flow along z) on a grid wide enough for
// any constriction's modelled tube, as the FEM's fluid map would give it.
mrjam::magnetics::EpmField uniform_field(double b, int& calls) {
    ++calls;
    mrjam::magnetics::EpmField f;
    f.mean_b_active = f.max_b_active = b;
    f.fluid_map.count = {9, 9, 17};
    f.fluid_map.origin = {-2e-3, -2e-3, -4e-3};
    f.fluid_map.spacing = {0.5e-3, 0.5e-3, 0.5e-3};
    f.fluid_map.values.assign(9 * 9 * 17, mrjam::Vec3{0, b, 0});
    return f;
}

// One constriction, a short tube and a protocol of a few hundred quick steps.
json brief_design(const std::string& output_directory) {
    const json protocol = {{"flow_time", "0.05 ms"}, {"magnetise_time", "0.04 ms"}, {"settle_window", "0.01 ms"},
                           {"max_time", "0.05 ms"},  {"arrest_window", "0.02 ms"},  {"release_time", "0.02 ms"}};
    return {{"constrictions", {"30x"}},
            {"jam",
             {{"model", {{"upstream_length", "1.1 mm"}, {"downstream_length", "0.3 mm"}}},
              {"fluid", {{"flow", "pressure"}}},
              {"protocol", protocol}}},
            {"output_directory", output_directory}};
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("design (library): the chain in an analytic field, its report, and a resume that reruns nothing") {
        TempDir dir;
        const double b = 0.23;
        int solves = 0;
        const mrjam::FieldSolver solver = [&](const mrjam::magnetics::EpmFieldRequest&) {
            return uniform_field(b, solves);
        };
        mrjam::DesignRequest req;
        req.scene_path = dir.file("design.json");
        req.design = brief_design(dir.file("design"));
        req.report_path = dir.file("report.json");
        req.progress = false;
        REQUIRE(mrjam::run_design(req, solver) == 0);
        CHECK(solves == 1);
        const json report = json::parse(slurp(req.report_path));
        CHECK(report["status"] == "complete");
        const json& row = report["results"]["constrictions"][0];
        CHECK(row["constriction"] == "30x");
        // The solver's figures pass through, and the map written and read back is the field
        // exactly on the axis (a uniform field interpolates to itself).
        CHECK(row["mean_B_active_T"].get<double>() == b);
        CHECK(row["B_on_axis"]["throat_centre_T"].get<double>() == doctest::Approx(b).epsilon(1e-12));
        CHECK(row["B_on_axis"]["taper_middle_T"].get<double>() == doctest::Approx(b).epsilon(1e-12));
        CHECK(std::filesystem::exists(dir.file("design/30x/field.map")));
        REQUIRE(row["runs"].size() == 1);
        const json jam = json::parse(slurp(dir.file("design/30x/jam_report.json")));
        CHECK(jam["results"]["outcome"] == row["runs"][0]["outcome"]);
        // The widest reliable constriction is this one exactly when its seed jammed.
        const bool jammed = row["jam_probability"].is_number() && row["jam_probability"].get<double>() >= 1.0;
        CHECK(report["results"]["widest_reliable_constriction"] == (jammed ? json("30x") : json(nullptr)));

        // Resumed after it finished: nothing is solved or run again, and the answer is the same.
        req.resume = true;
        req.report_path = dir.file("resumed.json");
        REQUIRE(mrjam::run_design(req, solver) == 0);
        CHECK(solves == 1);
        const json resumed = json::parse(slurp(req.report_path));
        CHECK(resumed["results"]["constrictions"] == report["results"]["constrictions"]);
        CHECK(resumed["resumed"] == true);
    }
}
