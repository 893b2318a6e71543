// The mrjam executable with a "magnetic" scene block: bad magnetic input is refused before any
// work with exit code 2 and the JSON path of the bad field on stderr; a valid small magnetic scene
// runs and its report carries results.magnetic.
//
// Scenes are written into a fresh temporary directory; the binary is the one CMake built next to
// the tests (MRJAM_BINARY), run as tests/test_cli.cpp runs it.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.hpp"
#include "test_support.hpp"

using mrjam_test::rel;

namespace {

namespace fs = std::filesystem;
using mrjam_test::expect_refused;
using mrjam_test::mrjam;
using mrjam_test::quote;
using mrjam_test::Result;
using mrjam_test::run_scene;
using mrjam_test::slurp;
using mrjam_test::write_text;
using nlohmann::json;

struct TempDir : mrjam_test::TempDir {
    TempDir() : mrjam_test::TempDir("mrjam_magnetic_cli") {}
};

// Iron grains (6.7 um) at volume fraction 0.2 in a 36 um box periodic in x and y between walls,
// in oil, 300 mT along z, two mutual-dipole iterations per step; 200 steps (~50 grains, well under
// a second). The box must exceed twice the magnetic cutoff with skin, 2 x 15.4 um.
json magnetic_scene() {
    return json::parse(R"({
      "description": "cli test: a small magnetic suspension",
      "seed": 3,
      "domain": {"lo": [0, 0, 0], "hi": ["36 um", "36 um", "36 um"], "periodic": "xy"},
      "materials": [{"name": "iron", "density": "7800 kg/m3", "youngs_modulus": "1 GPa", "poisson_ratio": 0.278,
                     "restitution": 0.1, "friction": 0.1, "relative_permeability": 1000,
                     "saturation_magnetisation": "1.7e6 A/m"}],
      "fluid": {"viscosity": "10 mPa s"},
      "magnetic": {"field": {"type": "uniform", "flux_density": [0, 0, "300 mT"]},
                   "mutual": "iterations", "iterations": 2, "cutoff": {"beyond_contact": "8 um"}},
      "walls": [{"name": "bottom", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]},
                {"name": "top", "type": "plane", "point": [0, 0, "36 um"], "normal": [0, 0, -1]}],
      "grains": [{"material": "iron", "size": {"distribution": "single", "diameter": "6.7 um"},
                  "placement": {"method": "random", "volume_fraction": 0.2}}],
      "run": {"steps": 200, "characteristic_speed": "1 m/s"}
    })");
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("cli: a small magnetic scene runs and reports its magnetic results") {
        TempDir dir;
        const Result r = run_scene(dir, "magnetic", magnetic_scene());
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = json::parse(slurp(dir.file("magnetic_report.json")));
        CHECK(rep["status"] == "complete");
        CHECK(rep["results"]["steps"] == 200);
        CHECK(rep["results"]["grains"].get<int>() > 30);  // 0.2 x (36 um)^3 / (pi/6 (6.7 um)^3): ~59
        REQUIRE(rep["results"].contains("magnetic"));
        const json& mag = rep["results"]["magnetic"];
        REQUIRE(mag["mean_iterations_per_step"].is_number());
        // Two field passes per force evaluation, exactly (the `iterations` policy with 2).
        CHECK(mag["mean_iterations_per_step"].get<double>() == 2.0);
        CHECK(mag["policy"] == "iterations");
        CHECK(mag["applied_field"] == "uniform");
        CHECK(mag["mean_moment_A_m2"].get<double>() > 0);
        // Resolved inputs: the defaults of the block are filled in.
        const json& in = rep["inputs"]["magnetic"];
        CHECK(in["mutual"] == "iterations");
        CHECK(in["cutoff"]["beyond_contact"].get<double>() == rel(8e-6));
        CHECK(rep["inputs"]["materials"][0]["relative_permeability"] == 1000);
    }

    TEST_CASE("cli: a magnetic scene with the close-pair correction runs and says which table it used") {
        TempDir dir;
        json s = magnetic_scene();
        s["magnetic"]["close_pairs"] = {{"model", "linear"}, {"min_gap", 0.05}};
        const Result r = run_scene(dir, "close_pairs", s);
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json cp = json::parse(slurp(dir.file("close_pairs_report.json")))["results"]["magnetic"]["close_pairs"];
        CHECK(cp["min_gap_radii"].get<double>() == doctest::Approx(0.05));
        CHECK(cp["range_radii"].get<double>() == doctest::Approx(1.0));
        CHECK(cp["relative_permeability"].get<double>() == doctest::Approx(1000.0).epsilon(1e-9));
    }

    TEST_CASE("cli: bad magnetic input is refused with exit code 2 and the JSON path of the bad field") {
        TempDir dir;
        {
            json s = magnetic_scene();
            s["magnetic"]["mutal"] = "lagged";  // misspelt key
            expect_refused(dir, "unknown_key", s, "/magnetic/mutal");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["field"]["flux_density"] = {0, 0, "600 T"};  // mT mistyped
            expect_refused(dir, "tesla_slip", s, "/magnetic/field/flux_density: 600 T is more than any magnet");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["field"]["flux_densty"] = {0, 0, 1};
            expect_refused(dir, "unknown_key_in_field", s, "/magnetic/field/flux_densty");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["mutual"] = "sometimes";
            const Result r = expect_refused(dir, "bad_policy", s, "/magnetic/mutual");
            CHECK(r.err.find("converged") != std::string::npos);  // names the choices
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["update_interval"] = 0;  // forces never evaluated
            expect_refused(dir, "no_evaluation", s, "/magnetic/update_interval");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["close_pairs"] = {
                {"model", "linear"}, {"min_gap", 0.5}, {"range", 0.3}};  // nothing left between them
            expect_refused(dir, "close_pairs_inverted", s, "/magnetic/close_pairs/range");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = {{"diameters", 1.2}};  // reaches a gap of 0.8 radii
            s["magnetic"]["close_pairs"] = {{"model", "linear"}, {"range", 1.0}};
            const Result r = expect_refused(dir, "close_pairs_beyond_cutoff", s, "/magnetic/close_pairs/range");
            CHECK(r.err.find("cutoff") != std::string::npos);
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["field"]["type"] = "dipole";
            expect_refused(dir, "bad_field_type", s, "/magnetic/field/type");
        }
        {
            json s = magnetic_scene();
            // diameters with beyond_contact is the capped range (accepted); beyond_contact with
            // length names two different ranges.
            s["magnetic"]["cutoff"] = {{"beyond_contact", "8 um"}, {"length", "30 um"}};
            const Result r = expect_refused(dir, "cutoff_two_ways", s, "/magnetic/cutoff");
            CHECK(r.err.find("the shorter range of the two") != std::string::npos);
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = {{"diameters", 3}, {"length", "30 um"}};
            expect_refused(dir, "cutoff_diameters_and_length", s, "/magnetic/cutoff");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = {{"beyond_contact", "1 um"}, {"length", "30 um"}};
            expect_refused(dir, "cutoff_beyond_and_length", s, "/magnetic/cutoff");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = json::object();
            expect_refused(dir, "cutoff_none_given", s, "/magnetic/cutoff");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = {{"length", "5 um"}};  // the grains touch at 6.7 um
            const Result r = expect_refused(dir, "cutoff_shorter_than_contact", s, "/magnetic/cutoff");
            CHECK(r.err.find("shorter than contact") != std::string::npos);
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["cutoff"] = {{"diameters", 0.5}};
            expect_refused(dir, "cutoff_half_a_diameter", s, "/magnetic/cutoff/diameters");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["field"] = {{"type", "map"}, {"file", "no_such_field_map.txt"}};
            const Result r = expect_refused(dir, "missing_field_map", s, "/magnetic/field/file");
            CHECK(r.err.find("no_such_field_map.txt") != std::string::npos);
            // Says what the file should hold and where relative paths start.
            CHECK(r.err.find("no field map at") != std::string::npos);
            CHECK(r.err.find("docs/scene.md") != std::string::npos);  // says where the format is described
        }
        {
            // A map named relative to the scene file is recorded as an absolute path, so a
            // checkpoint resumed from another directory reads the same map, not one of the same
            // name there.
            write_text(
                dir.file("uniform_map.txt"), "mrjam-fieldmap 1\n2 2 2\n0 0 0\n36e-6 36e-6 36e-6\n" + [] {
                    std::string v;
                    for (int k = 0; k < 8; ++k) v += "0 0 0.3\n";
                    return v;
                }());
            json s = magnetic_scene();
            s["magnetic"]["field"] = {{"type", "map"}, {"file", "uniform_map.txt"}};
            mrjam::BuildOptions options;
            options.base_directory =
                std::filesystem::relative(dir.file("")).string();  // a scene named relative to here
            REQUIRE(std::filesystem::path(options.base_directory).is_relative());
            const mrjam::Scene scene = mrjam::build_scene(s, options);
            const std::string file = scene.resolved["magnetic"]["field"]["file"].get<std::string>();
            CHECK(std::filesystem::path(file).is_absolute());
            CHECK(std::filesystem::equivalent(file, dir.file("uniform_map.txt")));
        }
        {
            // A header whose node counts do not match the values (more values than nodes), and a
            // spacing that is not positive: named with the file and the line.
            write_text(
                dir.file("long_map.txt"), "mrjam-fieldmap 1\n2 2 2\n0 0 0\n36e-6 36e-6 36e-6\n" + [] {
                    std::string v;
                    for (int k = 0; k < 9; ++k) v += "0 0 0.3\n";
                    return v;
                }());
            json s = magnetic_scene();
            s["magnetic"]["field"] = {{"type", "map"}, {"file", "long_map.txt"}};
            const Result r = expect_refused(dir, "map_more_values", s, "/magnetic/field/file");
            CHECK(r.err.find("long_map.txt:13") != std::string::npos);
            write_text(dir.file("flat_map.txt"), "mrjam-fieldmap 1\n2 2 2\n0 0 0\n36e-6 0 36e-6\n");
            s["magnetic"]["field"]["file"] = "flat_map.txt";
            const Result flat = expect_refused(dir, "map_zero_spacing", s, "/magnetic/field/file");
            CHECK(flat.err.find("flat_map.txt:4") != std::string::npos);
        }
        {
            // A map scaled past 10 T, as a uniform field would be (a scale of 1e6 ran and blew up).
            std::string nodes;
            for (int k = 0; k < 8; ++k) nodes += "0 0 0.5\n";
            write_text(dir.file("half_tesla.map"), "mrjam-fieldmap 1\n2 2 2\n0 0 0\n1e-5 1e-5 1e-5\n" + nodes);
            json s = magnetic_scene();
            s["magnetic"]["field"] = {{"type", "map"}, {"file", "half_tesla.map"}, {"scale", 1e6}};
            expect_refused(dir, "scaled_map", s, "/magnetic/field/scale: raises the map's strongest node to 500000 T");
        }
        {
            // A damaged map: the message names the file and the line.
            write_text(dir.file("broken_map.txt"), "mrjam-fieldmap 1\n2 2 2\n0 0 0\n1e-5 1e-5 1e-5\n0 0 1\n0 0 one\n");
            json s = magnetic_scene();
            s["magnetic"]["field"] = {{"type", "map"}, {"file", "broken_map.txt"}};
            const Result r = expect_refused(dir, "broken_field_map", s, "/magnetic/field/file");
            CHECK(r.err.find("broken_map.txt:6") != std::string::npos);
        }
        {
            json s = magnetic_scene();
            s["materials"][0]["relative_permeability"] = 0.5;
            expect_refused(dir, "permeability_below_1", s, "/materials/0/relative_permeability");
        }
        {
            json s = magnetic_scene();
            s["materials"][0]["saturation_magnetisation"] = 0;
            expect_refused(dir, "zero_saturation", s, "/materials/0/saturation_magnetisation");
        }
        {
            json s = magnetic_scene();
            s["materials"][0]["remanence_direction"] = {0, 0, 0};
            expect_refused(dir, "zero_remanence_direction", s, "/materials/0/remanence_direction");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["iterations"] = 0;
            expect_refused(dir, "zero_iterations", s, "/magnetic/iterations");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["mutual"] = "converged";
            s["magnetic"].erase("iterations");
            s["magnetic"]["tolerance"] = 0;
            expect_refused(dir, "zero_tolerance", s, "/magnetic/tolerance");
        }
        {
            // Settings of another policy would be ignored without a word.
            json s = magnetic_scene();
            s["magnetic"]["mutual"] = "lagged";  // the scene gives "iterations": 2
            const Result r = expect_refused(dir, "iterations_for_lagged", s, "/magnetic/iterations");
            CHECK(r.err.find("\"iterations\"") != std::string::npos);
            s["magnetic"].erase("iterations");
            s["magnetic"]["max_iterations"] = 50;
            expect_refused(dir, "max_iterations_for_lagged", s, "/magnetic/max_iterations");
        }
        {
            json s = magnetic_scene();
            s["magnetic"]["field"]["switch_on"] = "2 us";
            s["magnetic"]["field"]["switch_off"] = "1 us";
            expect_refused(dir, "switch_off_before_on", s, "/magnetic/field/switch_off");
        }
    }

}  // TEST_SUITE
