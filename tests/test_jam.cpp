// The jam predictor's pieces: flux counting through the throat plane, contact clusters, and the
// command's refusals and report.
#include <doctest/doctest.h>

#include "jam/contact_clusters.hpp"
#include "jam/throat_flux.hpp"
#include "magnetics/getdp_problem.hpp"
#include "test_support.hpp"

using namespace mrjam;
using namespace mrjam_test;
using nlohmann::json;

TEST_SUITE("unit") {

TEST_CASE("throat flux: crossings counted with sign, periodic wraps ignored") {
    System s;
    s.domain.lo = {-1, -1, -1};
    s.domain.hi = {1, 1, 1};
    s.particles.position = {{0, 0, -0.1}, {0, 0, 0.2}, {0, 0, 0.9}};
    ThroatFlux flux(0.0);
    flux.observe(s);
    s.time = 1;
    s.particles.position = {{0, 0, 0.05}, {0, 0, -0.05}, {0, 0, -0.95}};  // +1, -1, and a wrap (no crossing)
    flux.observe(s);
    CHECK(flux.passed() == 0);
    s.time = 2;
    s.particles.position = {{0, 0, 0.1}, {0, 0, 0.01}, {0, 0, -0.5}};  // grain 1 crosses forward
    flux.observe(s);
    CHECK(flux.passed() == 1);
    CHECK(flux.rate_between(1, 2) == doctest::Approx(1.0));
    CHECK(flux.rate(1.0) == doctest::Approx(1.0));
    CHECK(flux.rate(5.0) == 0.0);  // history shorter than the window
}

}  // TEST_SUITE

TEST_SUITE("cli") {

TEST_CASE("jam: impossible or meaningless scenes are refused before the run") {
    TempDir dir;
    auto refused = [&](const std::string& label, const json& scene, const std::string& path) {
        expect_mode_refused(dir, "jam", label, scene, path);
    };
    refused("narrow_throat", {{"valve", {{"constriction_diameter", "40 um"}}}}, "/valve/constriction_diameter");
    refused("zero_threshold", {{"protocol", {{"arrest_fraction", 0}}}}, "/protocol/arrest_fraction");
    refused("dense", {{"grains", {{"volume_fraction", 0.7}}}}, "/grains/volume_fraction");
    refused("empty_table", {{"grains", {{"diameters", json::array()}, {"mass_fractions", json::array()}}}}, "/grains/diameters");
    // A field map that covers only part of the valve.
    const std::string map = dir.file("small.map");
    write_text(map, "mrjam-fieldmap 1\n2 2 2\n-1e-4 -1e-4 -1e-4\n2e-4 2e-4 2e-4\n" + std::string(8 * 1, ' ') +
                        "0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n");
    refused("small_map", {{"field", {{"type", "map"}, {"file", map}}}}, "/field/file");
    refused("typo", {{"protocol", {{"max_tme", "1 ms"}}}}, "/protocol/max_tme");
}

TEST_CASE("jam: a short run reports the outcome keys, a flux history and a throat picture") {
    TempDir dir;
    const json scene = {{"valve", {{"constriction", "30x"}}},
                        {"model", {{"upstream_length", "1.1 mm"}, {"downstream_length", "0.3 mm"}}},
                        {"protocol", {{"flow_time", "0.05 ms"}, {"max_time", "0.05 ms"}, {"arrest_window", "0.02 ms"},
                                      {"release_time", "0.02 ms"}}},
                        {"output", {{"directory", dir.file("out")}}}};
    write_text(dir.file("jam.json"), scene.dump());
    const Result r = mrjam_test::mrjam(dir, "jam " + quote(dir.file("jam.json")) + " --report " + quote(dir.file("jam_report.json")) +
                                    " --fidelity quick --quiet");
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(slurp(dir.file("jam_report.json")));
    const json& res = report["results"];
    for (const char* key : {"jammed", "time_to_arrest_s", "grains_passed_before_arrest", "released", "outcome",
                            "largest_cluster", "largest_cluster_spans_throat", "flux_history", "jam_probability"}) {
        CAPTURE(key);
        CHECK(res.contains(key));
    }
    CHECK(res["grains"].get<long>() > 100);
    CHECK(res["flux_history"]["rows"].size() > 2);
    CHECK(std::filesystem::exists(dir.file("jam_report_throat.png")));
    CHECK(report["fidelity"]["jam_tier"] == "quick");
}

}  // TEST_SUITE

TEST_SUITE("cli") {

// The design chain end to end on one constriction with a coarse field mesh and a short run:
// the field map written for the constriction must drive the jam run, and the report must name
// the jam probability and the open-state flow estimate.
TEST_CASE("design: magnetics -> field map -> jam predictor -> report") {
    if (mrjam::magnetics::find_getdp().empty()) { MESSAGE("getdp not installed: skipped"); return; }
    TempDir dir;
    const json design = {
        {"constrictions", {"30x"}},
        {"magnetics", {{"mesh", {{"fluid_size", "0.4 mm"}, {"device_size", "1 mm"}, {"far_size", "5 mm"}}}}},
        {"jam", {{"model", {{"upstream_length", "1.1 mm"}, {"downstream_length", "0.3 mm"}}},
                 {"fluid", {{"flow", "pressure"}}},
                 {"protocol", {{"flow_time", "0.05 ms"}, {"max_time", "0.05 ms"}, {"arrest_window", "0.02 ms"},
                               {"release_time", "0.02 ms"}}}}},
        {"output_directory", dir.file("design")}};
    write_text(dir.file("design.json"), design.dump());
    const Result r = mrjam_test::mrjam(dir, "design " + quote(dir.file("design.json")) + " --report " +
                                                quote(dir.file("design_report.json")) + " --fidelity quick --quiet");
    CAPTURE(r.err);
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(slurp(dir.file("design_report.json")));
    const json& row = report["results"]["constrictions"][0];
    CHECK(row["constriction"] == "30x");
    CHECK(row["mean_B_active_T"].get<double>() > 0.05);
    CHECK(row["jam_probability"].is_number());
    CHECK(row["open_flow_rate_m3_s"].get<double>() > 0);
    CHECK(std::filesystem::exists(dir.file("design/30x/field.map")));
    CHECK(report["results"].contains("widest_reliable_constriction"));

    write_text(dir.file("bad.json"), json{{"constrictions", {"30x"}}, {"magnet", json::object()}}.dump());
    const Result bad = mrjam_test::mrjam(dir, "design " + quote(dir.file("bad.json")) + " --quiet");
    CHECK(bad.exit_code == 2);
    CHECK(bad.err.find("/magnet") != std::string::npos);
}

}  // TEST_SUITE
