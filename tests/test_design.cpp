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
            {"output", {{"directory", output_directory}}}};
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

        // The constrictions are a sweep's points: its table has the row's figures, its pictures are written.
        const std::string table = slurp(dir.file("design/table.csv"));
        CHECK(table.rfind("point,state,constrictions/0,jam_probability,open_flow_ml_min,throat_B_T\n", 0) == 0);
        CHECK(table.find("\n30x,done,30x,") != std::string::npos);
        // The summary figure: both plots; the analytic field has no mid-plane picture to show.
        REQUIRE(report.contains("summary_figure"));
        CHECK(report["summary_figure"]["field_of"].is_null());
        CHECK(std::filesystem::exists(report["summary_figure"]["png"].get<std::string>()));
        CHECK(slurp(report["summary_figure"]["svg"].get<std::string>()).find("Open valve") != std::string::npos);
        REQUIRE(report["plots"].size() == 2);
        for (const json& plot : report["plots"]) {
            CHECK(slurp(plot.get<std::string>()).rfind("<svg", 0) == 0);
            CHECK(std::filesystem::exists(std::filesystem::path(plot.get<std::string>()).replace_extension(".png")));
        }
        const json manifest = json::parse(slurp(dir.file("design/manifest.json")));
        CHECK(manifest["points"][0]["state"] == "done");
        CHECK(manifest["points"][0]["attempts"] == 1);

        // Resumed after it finished: nothing is solved or run again, and the answer is the same.
        req.resume = true;
        req.report_path = dir.file("resumed.json");
        REQUIRE(mrjam::run_design(req, solver) == 0);
        CHECK(solves == 1);
        const json resumed = json::parse(slurp(req.report_path));
        CHECK(resumed["results"]["constrictions"] == report["results"]["constrictions"]);
        CHECK(resumed["resumed"] == true);

        // Run again without --resume into the same folder: a fresh design, which solves and runs again.
        req.resume = false;
        req.report_path = dir.file("again.json");
        REQUIRE(mrjam::run_design(req, solver) == 0);
        CHECK(solves == 2);
        const json again = json::parse(slurp(req.report_path));
        CHECK(again["results"]["constrictions"] == report["results"]["constrictions"]);
        CHECK(json::parse(slurp(dir.file("design/manifest.json")))["points"][0]["attempts"] == 1);
    }

    TEST_CASE("design (library): a constriction that fails does not stop the others, and a resume retries it") {
        TempDir dir;
        int solves = 0;
        // The first solve fails, as a mesh or GetDP failure would.
        const mrjam::FieldSolver solver = [&](const mrjam::magnetics::EpmFieldRequest&) {
            if (solves++ == 0) throw std::runtime_error("the mesher gave up");
            int unused = 0;
            return uniform_field(0.23, unused);
        };
        mrjam::DesignRequest req;
        req.scene_path = dir.file("design.json");
        req.design = brief_design(dir.file("design"));
        req.design["constrictions"] = {"40x", "30x"};
        req.report_path = dir.file("report.json");
        req.progress = false;
        CHECK(mrjam::run_design(req, solver) == 1);  // a fault, not bad input
        const json failed = json::parse(slurp(req.report_path));
        CHECK(failed["status"] == "failed");
        CHECK(failed["stopped"]["constriction"] == "40x");
        CHECK(failed["stopped"]["stage"] == "field solve");
        CHECK(failed["stopped"]["error"].get<std::string>().find("the mesher gave up") != std::string::npos);
        REQUIRE(failed["results"]["constrictions"].size() == 1);
        CHECK(failed["results"]["constrictions"][0]["constriction"] == "30x");

        // Resumed: the finished constriction is kept, the failed one is run again.
        req.resume = true;
        req.report_path = dir.file("resumed.json");
        REQUIRE(mrjam::run_design(req, solver) == 0);
        CHECK(solves == 3);
        const json resumed = json::parse(slurp(req.report_path));
        CHECK(resumed["status"] == "complete");
        REQUIRE(resumed["results"]["constrictions"].size() == 2);
        CHECK(resumed["results"]["constrictions"][0]["constriction"] == "40x");  // in the design's order
        CHECK(resumed["results"]["constrictions"][1] == failed["results"]["constrictions"][0]);
        const json manifest = json::parse(slurp(dir.file("design/manifest.json")));
        CHECK(manifest["points"][0]["attempts"] == 2);
        CHECK(manifest["points"][1]["attempts"] == 1);
    }
}
