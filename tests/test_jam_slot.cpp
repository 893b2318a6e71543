// A slot orifice end to end: `mrjam jam` runs it (walls, flow, insertion, observers), refuses the
// impossible slots with the field to fix, and `mrjam magnetics` refuses a slot rather than model
// a circle in its place.
#include <doctest/doctest.h>

#include "test_support.hpp"

using namespace mrjam_test;
using nlohmann::json;

TEST_SUITE("cli") {
    TEST_CASE("jam with a slot orifice: a short run, and the slots that cannot be run") {
        TempDir dir;
        const json slot = {{"orifice", "slot"},
                           {"constriction_diameter", "0.88 mm"},
                           {"slot_width", "0.6 mm"},
                           {"taper_length", "0.3 mm"},
                           {"throat_length", "0.1 mm"}};
        const json scene = {
            {"valve", slot},
            {"model",
             {{"upstream_length", "0.45 mm"}, {"downstream_length", "0.2 mm"}, {"slab_thickness_diameters", 2}}},
            {"field", {{"type", "uniform"}, {"flux_density", "230 mT"}}},
            {"protocol",
             {{"order", "open_first"},
              {"flow_time", "0.02 ms"},
              {"max_time", "0.02 ms"},
              {"arrest_window", "0.008 ms"},
              {"release_time", "0.01 ms"},
              {"observe_every_steps", 20}}},
            {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "slot", scene, "--fidelity quick");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("slot_report.json")));
        CHECK(report["inputs_jam"]["valve"]["orifice"] == "slot");
        CHECK(report["inputs"]["walls"][0]["valve"]["orifice"] == "slot");  // the engine got the slot, not a circle
        const json& res = report["results"];
        CHECK(res["grains"].get<long>() > 100);
        CHECK(res["flux_history"]["rows"].size() > 2);
        // The fluid carries grains through the slot during the no-field flow.
        CHECK(res["no_field_flux_grains_per_s"].get<double>() > 0);
        CHECK(res["arrested_bed_drag_pressure_Pa"].is_null());  // the pressure controller is for circles
        CHECK(std::filesystem::exists(dir.file("slot_report_throat.png")));

        auto refused = [&](const std::string& label, const json& valve, const std::string& path,
                           json extra = json::object()) {
            json s = scene;
            s["valve"] = valve;
            s.update(extra);
            const Result bad = expect_mode_refused(dir, "jam", label, s, path);
            return bad.err;
        };
        json wide = slot;
        wide["slot_width"] = "2.5 mm";  // with 0.88 mm its diagonal (2.65 mm) exceeds the 2.6 mm bore
        CHECK(refused("wide_slot", wide, "/valve/slot_width").find("does not fit inside the bore") !=
              std::string::npos);
        json no_width = slot;
        no_width.erase("slot_width");
        refused("no_width", no_width, "/valve/slot_width");
        json thin = slot;
        thin["slot_width"] = "40 um";  // the 44 um grains cannot pass
        refused("thin_slot", thin, "/valve/slot_width");
        json circle = {{"constriction", "30x"}, {"slot_width", "0.6 mm"}};
        refused("width_without_slot", circle, "/valve/slot_width");
        refused("slot_pressure", slot, "/fluid/flow", {{"fluid", {{"flow", "pressure"}}}});
    }

    TEST_CASE("magnetics refuses a slot orifice rather than model a circle") {
        TempDir dir;
        const json scene = {
            {"variant", "rectangular"},
            {"model", "circuit"},
            {"valve", {{"orifice", "slot"}, {"constriction_diameter", "0.88 mm"}, {"slot_width", "0.6 mm"}}}};
        const Result r = expect_mode_refused(dir, "magnetics", "slot", scene, "/valve/orifice");
        CHECK(r.err.find("magnetics models circular orifices only") != std::string::npos);
    }

}  // TEST_SUITE
