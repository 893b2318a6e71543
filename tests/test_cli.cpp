// The mrjam executable end to end: `--version`, a small scene run and its report, refusals of bad
// scenes (exit code 2 and the JSON path of the bad field on stderr), a missing file, invalid
// JSON, unit strings, and checkpoint/resume continuing a two-stage run exactly.
//
// Scenes are written from this file into a fresh temporary directory; the binary is the one
// CMake built next to the tests (MRJAM_BINARY).
#include <doctest/doctest.h>
#include <omp.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "test_support.hpp"

using mrjam_test::rel;

namespace {

using mrjam_test::expect_refused;
using mrjam_test::mrjam;
using mrjam_test::quote;
using mrjam_test::Result;
using mrjam_test::run_scene;
using mrjam_test::slurp;
using mrjam_test::write_text;
struct TempDir : mrjam_test::TempDir {
    TempDir() : mrjam_test::TempDir("mrjam_cli") {}
};

namespace fs = std::filesystem;
using nlohmann::json;

json read_report(const TempDir& dir, const std::string& name) {
    const std::string text = slurp(dir.file(name + "_report.json"));
    REQUIRE_FALSE(text.empty());
    return json::parse(text);
}

// A small valid scene: 1 mm glass beads at volume fraction 0.3 in a periodic 6 mm box, 100 steps.
json small_scene() {
    return json::parse(R"({
      "description": "cli test: small periodic gas",
      "seed": 17,
      "domain": {"lo": [0, 0, 0], "hi": ["6 mm", "6 mm", "6 mm"], "periodic": "xyz"},
      "materials": [{"name": "glass", "density": "2500 kg/m3", "youngs_modulus": "10 MPa",
                     "restitution": 0.6, "friction": 0.4}],
      "grains": [{"material": "glass", "size": {"distribution": "single", "diameter": "1 mm"},
                  "placement": {"method": "random", "volume_fraction": 0.3},
                  "random_velocity": "0.1 m/s"}],
      "run": {"steps": 100}
    })");
}

// Two stages in a column with walls: settle under gravity in a fluid flowing along x, then the
// lid moves down (the flow goes on: a stage without "flow" keeps the current one). Checkpoint
// every `every` steps.
json two_stage_scene(long every, const std::string& checkpoint_path, const std::string& output_dir) {
    json scene = json::parse(R"({
      "description": "cli test: two stages with a checkpoint",
      "seed": 23,
      "domain": {"lo": [0, 0, 0], "hi": ["6 mm", "6 mm", "12 mm"], "periodic": "xy"},
      "materials": [{"name": "glass", "density": "2500 kg/m3", "youngs_modulus": "10 MPa",
                     "restitution": 0.5, "friction": 0.5, "rolling_friction": 0.1, "rolling_damping": 0.3}],
      "contact": {"rolling": "epsd"},
      "fluid": {"viscosity": "1 mPa s", "density": "1000 kg/m3"},
      "gravity": [0, 0, "-9.81 m/s2"],
      "walls": [{"name": "floor", "type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1]},
                {"name": "lid", "type": "plane", "point": [0, 0, "12 mm"], "normal": [0, 0, -1]}],
      "grains": [{"material": "glass",
                  "size": {"distribution": "lognormal", "median_diameter": "0.8 mm", "sigma_ln": 0.15},
                  "placement": {"method": "random", "volume_fraction": 0.3}, "random_velocity": "0.05 m/s"}],
      "run": {"characteristic_speed": "0.5 m/s"},
      "stages": [
        {"name": "settle", "steps": 150, "flow": {"type": "uniform", "velocity": ["20 mm/s", 0, 0]}},
        {"name": "press", "steps": 100, "wall_velocities": [{"name": "lid", "velocity": [0, 0, "-0.2 m/s"]}]}
      ]
    })");
    scene["output"] = {{"directory", output_dir}, {"checkpoint", {{"every_steps", every}, {"path", checkpoint_path}}}};
    return scene;
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("cli: --version exits 0 and names the version") {
        TempDir dir;
        const Result r = mrjam(dir, "--version");
        CHECK(r.exit_code == 0);
        CHECK(r.out.find("mrjam") != std::string::npos);
        CHECK(r.out.find(MRJAM_VERSION) != std::string::npos);
    }

    TEST_CASE("cli: no subcommand, or an unknown option, is a command-line error") {
        TempDir dir;
        CHECK(mrjam(dir, "").exit_code == 2);
        CHECK(mrjam(dir, "run --no-such-option x.json").exit_code == 2);
        CHECK(mrjam(dir, "run").exit_code == 2);  // neither a scene nor --resume
    }

    // A run that completes leaves no checkpoint behind, nor the temporary file of one a killed
    // run left half written in the same place.
    TEST_CASE("cli: a completed run removes its checkpoint and a stale temporary one") {
        TempDir dir;
        json scene = small_scene();
        scene["output"] = {{"directory", dir.file("out")}};
        std::filesystem::create_directories(dir.file("out"));
        write_text(dir.file("out/checkpoint.mrjam.tmp"), "half written by a run that was killed");
        const Result r = run_scene(dir, "small", scene);
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        CHECK_FALSE(std::filesystem::exists(dir.file("out/checkpoint.mrjam")));
        CHECK_FALSE(std::filesystem::exists(dir.file("out/checkpoint.mrjam.tmp")));
    }

    TEST_CASE("cli: a small scene runs and reports its inputs with defaults, seed and timing") {
        TempDir dir;
        const Result r = run_scene(dir, "small", small_scene());
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = read_report(dir, "small");
        CHECK(rep["status"] == "complete");
        CHECK(rep["partial"] == false);
        CHECK(rep["seed"] == 17);
        CHECK(rep["mode"] == "run");
        REQUIRE(rep["wall_time_s"].is_number());
        CHECK(rep["wall_time_s"].get<double>() >= 0);
        CHECK(rep["results"]["steps"] == 100);
        CHECK(rep["results"]["grains"].get<int>() > 50);
        const json& in = rep["inputs"];
        // Defaults are filled in.
        CHECK(in["run"]["timestep_safety"] == 0.1);
        CHECK(in["run"]["timestep"] == "auto");
        CHECK(in["run"]["skin"] == 0.1);
        CHECK(in["run"]["max_overlap_fraction"] == 0.1);
        CHECK(in["materials"][0]["poisson_ratio"] == 0.3);
        CHECK(in["contact"]["model"] == "hertz_mindlin");
        CHECK(in["grains"][0]["placement"]["overlap_tolerance"] == 1e-3);
        // Unit strings are resolved to SI.
        CHECK(in["materials"][0]["youngs_modulus"].get<double>() == rel(1e7));
        CHECK(in["grains"][0]["size"]["diameter"].get<double>() == rel(1e-3));
        // The step actually used and its limits.
        const double dt = rep["timestep"]["used_s"].get<double>();
        CHECK(dt > 0);
        CHECK(dt == rel(0.1 * rep["timestep"]["critical_s"].get<double>()));
        CHECK(rep["results"]["simulated_time_s"].get<double>() == rel(100 * dt));
        // The report conforms to schemas/report_run.schema.json (mrjam() checked the file), and
        // the check fails where a key goes missing or changes type.
        CHECK(mrjam_test::report_schema_errors(rep).empty());
        json broken = rep;
        broken.erase("status");
        broken["results"]["steps"] = "100";
        std::string errors;
        for (const std::string& e : mrjam_test::report_schema_errors(broken)) errors += e + "\n";
        CAPTURE(errors);
        CHECK(errors.find("status") != std::string::npos);
        CHECK(errors.find("/results/steps:") != std::string::npos);
    }

    TEST_CASE("cli: --threads 2 runs the same scene to the same state within round-off") {
        TempDir dir;
        REQUIRE(run_scene(dir, "one", small_scene(), "--threads 1").exit_code == 0);
        REQUIRE(run_scene(dir, "two", small_scene(), "--threads 2").exit_code == 0);
        const json a = read_report(dir, "one"), b = read_report(dir, "two");
        CHECK(b["threads"] == 2);
        CHECK(a["results"]["grains"] == b["results"]["grains"]);
        CHECK(a["results"]["simulated_time_s"] == b["results"]["simulated_time_s"]);
        CHECK(b["results"]["kinetic_energy_J"].get<double>() ==
              rel(a["results"]["kinetic_energy_J"].get<double>()).epsilon(1e-6));
    }

    TEST_CASE(
        "cli: without --threads a run takes a thread per 800 grains up to the machine's cores, or OMP_NUM_THREADS") {
        TempDir dir;
        const char* before = std::getenv("OMP_NUM_THREADS");
        const std::string saved = before ? before : "";
        unsetenv("OMP_NUM_THREADS");
        // 124 grains: one thread, whatever the machine (a second one would only wait).
        REQUIRE(run_scene(dir, "small", small_scene()).exit_code == 0);
        CHECK(read_report(dir, "small")["threads"] == 1);
        // About 4,600 grains: five threads' worth, as many as the machine has up to that.
        json big = small_scene();
        big["domain"]["hi"] = {"20 mm", "20 mm", "20 mm"};
        big["run"]["steps"] = 20;
        REQUIRE(run_scene(dir, "cores", big).exit_code == 0);
        const json cores = read_report(dir, "cores");
        const long grains = cores["results"]["grains"].get<long>();
        REQUIRE(grains >= 1600);
        CHECK(cores["threads"] == std::min<long>(omp_get_num_procs(), grains / 800));
        // A resumed run without --threads goes on with its checkpoint's count (3, more than the
        // automatic one here), so it stays bit for bit whatever its grains have become.
        json three = big;
        three["output"] = {{"directory", dir.file("three")},
                           {"checkpoint", {{"every_steps", 10}, {"path", dir.file("three.mrjam")}}}};
        REQUIRE(run_scene(dir, "three", three, "--threads 3").exit_code == 0);
        const Result resumed = mrjam(dir, "run --resume " + quote(dir.file("three.mrjam")) + " --report " +
                                              quote(dir.file("resumed_report.json")) + " --quiet");
        REQUIRE(resumed.exit_code == 0);
        CHECK(read_report(dir, "resumed")["threads"] == 3);
        setenv("OMP_NUM_THREADS", "3", 1);
        REQUIRE(run_scene(dir, "env", small_scene()).exit_code == 0);
        CHECK(read_report(dir, "env")["threads"] == 3);
        REQUIRE(run_scene(dir, "option", small_scene(), "--threads 1").exit_code == 0);
        CHECK(read_report(dir, "option")["threads"] == 1);  // the option wins
        if (before)
            setenv("OMP_NUM_THREADS", saved.c_str(), 1);
        else
            unsetenv("OMP_NUM_THREADS");
    }

    TEST_CASE("cli: unit strings are accepted and resolved to SI") {
        TempDir dir;
        json scene = small_scene();
        scene["domain"]["hi"] = {"60 um", "60 um", "60 um"};
        scene["materials"][0]["density"] = "7800 kg/m3";
        scene["materials"][0]["youngs_modulus"] = "1 GPa";
        scene["grains"][0]["size"]["diameter"] = "6.7 um";
        scene["fluid"] = {{"viscosity", "10 mPa s"}, {"density", "1.2 g/cm3"}};
        scene["gravity"] = {0, 0, "-9.81 m/s2"};
        scene["run"] = {{"duration", "0.2 us"}, {"characteristic_speed", "10 cm/s"}};
        const Result r = run_scene(dir, "units", scene);
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json in = read_report(dir, "units")["inputs"];
        CHECK(in["domain"]["hi"][0].get<double>() == rel(60e-6));
        CHECK(in["materials"][0]["density"].get<double>() == rel(7800));
        CHECK(in["materials"][0]["youngs_modulus"].get<double>() == rel(1e9));
        CHECK(in["grains"][0]["size"]["diameter"].get<double>() == rel(6.7e-6));
        CHECK(in["fluid"]["viscosity"].get<double>() == rel(0.01));
        CHECK(in["fluid"]["density"].get<double>() == rel(1200));
        CHECK(in["gravity"][2].get<double>() == rel(-9.81));
        CHECK(in["run"]["duration"].get<double>() == rel(2e-7));
        CHECK(in["run"]["characteristic_speed"].get<double>() == rel(0.1));
    }

    TEST_CASE("cli: bad scenes are refused with exit code 2 and the JSON path of the bad field") {
        TempDir dir;
        {
            json s = small_scene();
            s["materials"][0]["densty"] = 7800;  // an extra, misspelt key
            expect_refused(dir, "unknown_key", s, "/materials/0/densty");
        }
        {
            json s = small_scene();
            s["materials"][0].erase("density");
            s["materials"][0]["densty"] = "2500 kg/m3";  // the required key misspelt
            const Result r = expect_refused(dir, "misspelt_required_key", s, "/materials/0/densty");
            CHECK(r.err.find("/materials/0/density") != std::string::npos);
        }
        {
            json s = small_scene();
            s["grains"][0]["sizes"] = s["grains"][0]["size"];
            expect_refused(dir, "unknown_key_in_grains", s, "/grains/0/sizes");
        }
        {
            json s = small_scene();
            s["materials"][0]["restitution"] = "high";
            expect_refused(dir, "wrong_type_string", s, "/materials/0/restitution");
        }
        {
            json s = small_scene();
            s["materials"][0]["friction"] = true;
            expect_refused(dir, "wrong_type_bool", s, "/materials/0/friction");
        }
        {
            // A per-pair friction must name two defined materials and a friction that is not negative.
            json s = small_scene();
            s["material_pairs"] = {{{"materials", {"glass", "steel"}}, {"friction", 0}}};
            expect_refused(dir, "pair_unknown_material", s, "/material_pairs/0/materials");
            s["material_pairs"] = {{{"materials", "glass"}}};
            expect_refused(dir, "pair_not_two", s, "/material_pairs/0/materials");
            s["material_pairs"] = {{{"materials", {"glass", "glass"}}, {"friction", -0.1}}};
            expect_refused(dir, "pair_negative_friction", s, "/material_pairs/0/friction");
            s["material_pairs"] = {{{"materials", {"glass", "glass"}}, {"cohesion_energy_density", "-5 kJ/m3"}}};
            expect_refused(dir, "pair_negative_cohesion", s, "/material_pairs/0/cohesion_energy_density");
        }
        {
            json s = small_scene();
            s["seed"] = 1.5;
            expect_refused(dir, "wrong_type_seed", s, "/seed");
        }
        {
            // A duration past any run's reach (here 1e30 s) once wrapped the step count round to a
            // one-step run reported as complete.
            json s = small_scene();
            s["run"] = {{"duration", 1e30}};
            const Result r = expect_refused(dir, "duration_overflow", s, "/run/duration");
            CHECK(r.err.find("steps") != std::string::npos);
            s["run"] = {{"duration", "1 ms"}, {"timestep", "1e-30 s"}};
            expect_refused(dir, "timestep_tiny", s, "/run/duration");
            // Nothing sets a time scale: no contact law, drag or damping.
            s = small_scene();
            s["contact"] = {{"model", "none"}};
            expect_refused(dir, "no_step_limit", s, "/run/timestep");
        }
        {
            // Grains placed where they cannot stay: a region reaching past a closed face, a plane
            // wall through the region; both ended as a blow-up at the first step.
            json s = small_scene();
            s["domain"]["periodic"] = "xy";
            s["grains"][0]["placement"]["volume_fraction"] = 0.1;
            s["grains"][0]["placement"]["region"] = {{"lo", {0, 0, "-2 mm"}}, {"hi", {"6 mm", "6 mm", "3 mm"}}};
            expect_refused(dir, "region_past_closed_face", s, "/grains/0/placement/region");
            s["grains"][0]["placement"]["region"] = {{"lo", {"-2 mm", 0, 0}},
                                                     {"hi", {"6 mm", "6 mm", "3 mm"}}};  // x is periodic: fine
            s["walls"] = {{{"name", "shelf"}, {"type", "plane"}, {"point", {0, 0, "1.5 mm"}}, {"normal", {0, 0, 1}}}};
            const Result r = expect_refused(dir, "wall_through_grains", s, "/walls/0");
            CHECK(r.err.find("shelf") != std::string::npos);
        }
        {
            // Names that something else refers to must be given, and once.
            json s = small_scene();
            s["domain"]["periodic"] = "xx";
            expect_refused(dir, "axis_twice", s, "/domain/periodic");
            s = small_scene();
            s["materials"][0]["name"] = "";
            expect_refused(dir, "material_unnamed", s, "/materials/0/name");
            s = small_scene();
            s["domain"]["periodic"] = "xy";
            s["walls"] = {{{"name", "lid"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
                          {{"name", "lid"}, {"type", "plane"}, {"point", {0, 0, "6 mm"}}, {"normal", {0, 0, -1}}}};
            expect_refused(dir, "wall_name_twice", s, "/walls/1/name");
        }
        {
            // A lattice period longer than the periodic box (an internal error, exit 1, before).
            json s = small_scene();
            s["grains"][0]["placement"] = {{"method", "lattice"}, {"spacing", "1 m"}};
            expect_refused(dir, "lattice_longer_than_box", s, "/grains/0/placement/spacing");
        }
        {
            // Where the run writes: an output directory a file is in the way of, and a checkpoint
            // that could not be saved (found out only at Ctrl-C, it lost the whole run).
            write_text(dir.file("a_file"), "x");
            json s = small_scene();
            s["output"] = {{"directory", dir.file("a_file")}};
            expect_refused(dir, "output_is_a_file", s, "/output/directory");
            s["output"] = {{"directory", dir.file("out")},
                           {"checkpoint", {{"path", dir.file("a_file") + "/ck.mrjam"}}}};
            expect_refused(dir, "checkpoint_under_a_file", s, "/output/checkpoint/path");
            s["output"] = {{"directory", dir.file("out")}, {"checkpoint", {{"path", dir.file("out")}}}};
            expect_refused(dir, "checkpoint_is_a_directory", s, "/output/checkpoint/path");
        }
        {
            // Rafts: two of one name in one stage would be one raft at the second's velocity; a
            // release or a velocity must name a raft formed by then.
            json s = small_scene();
            s["run"].erase("steps");
            const json region = {{"lo", {0, 0, 0}}, {"hi", {"6 mm", "6 mm", "1 mm"}}};
            s["stages"] = {
                {{"name", "a"},
                 {"steps", 10},
                 {"form_rafts", {{{"name", "lower"}, {"region", region}}, {{"name", "lower"}, {"region", region}}}}}};
            expect_refused(dir, "raft_twice", s, "/stages/0/form_rafts/1/name");
            s["stages"] = {{{"name", "a"}, {"steps", 10}, {"release", {"lower"}}}};
            expect_refused(dir, "release_unformed", s, "/stages/0/release");
            s["stages"] = {
                {{"name", "a"}, {"steps", 10}, {"raft_velocities", {{{"name", "lower"}, {"velocity", {0, 0, 0}}}}}}};
            expect_refused(dir, "velocity_unformed", s, "/stages/0/raft_velocities/0/name");
            s["stages"] = {{{"name", "a"}, {"steps", 10}, {"form_rafts", {{{"name", "lower"}, {"region", region}}}}},
                           {{"name", "b"}, {"duration", 1e30}, {"release", {"lower"}}}};
            expect_refused(dir, "stage_duration_overflow", s, "/stages/1/duration");
        }
        {
            json s = small_scene();
            s["domain"]["hi"] = {"6 mm", "6 mm"};
            expect_refused(dir, "wrong_type_vector", s, "/domain/hi");
        }
        {
            json s = small_scene();
            s["grains"] = {{"material", "glass"}};  // an object, not an array
            expect_refused(dir, "wrong_type_array", s, "/grains");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"]["diameter"] = "-1 mm";
            expect_refused(dir, "negative_diameter", s, "/grains/0/size/diameter");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"]["diameter"] = 0;
            expect_refused(dir, "zero_diameter", s, "/grains/0/size/diameter");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"] = {
                {"distribution", "table"}, {"diameters", {"1 mm", "-0.5 mm"}}, {"frequencies", {1, 1}}};
            expect_refused(dir, "negative_table_diameter", s, "/grains/0/size/diameters");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"] = {{"distribution", "lognormal"}, {"median_diameter", "-1 mm"}, {"sigma_ln", 0.2}};
            expect_refused(dir, "negative_median", s, "/grains/0/size/median_diameter");
        }
        {
            // A min_diameter above the defaulted max (1 mm e^0.6 = 1.82 mm) is the min's fault, not max's.
            json s = small_scene();
            s["grains"][0]["size"] = {{"distribution", "lognormal"},
                                      {"median_diameter", "1 mm"},
                                      {"sigma_ln", 0.2},
                                      {"min_diameter", "2 mm"}};
            expect_refused(dir, "min_above_default_max", s, "/grains/0/size/min_diameter: must be below max_diameter");
        }
        {
            json s = small_scene();
            s["materials"][0]["restitution"] = 0;
            expect_refused(dir, "restitution_0", s, "/materials/0/restitution");
        }
        {
            json s = small_scene();
            s["materials"][0]["restitution"] = 1.5;
            expect_refused(dir, "restitution_1.5", s, "/materials/0/restitution");
        }
        {
            json s = small_scene();
            s["grains"][0]["placement"]["volume_fraction"] = 0.7;
            const Result r = expect_refused(dir, "volume_fraction_0.7", s, "/grains/0/placement/volume_fraction");
            CHECK(r.err.find("0.64") != std::string::npos);
        }
        {
            json s = small_scene();
            s["grains"][0]["size"]["diameter"] = "7 mm";  // the box is 6 mm
            expect_refused(dir, "grain_larger_than_box", s, "/grains/0/size");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"]["diameter"] = "2.8 mm";  // fits, but a 6 mm period is < 2 cutoffs
            expect_refused(dir, "period_too_short", s, "/domain/hi");
        }
        {
            json s = small_scene();
            s["grains"][0]["size"]["diameter"] = "6.7 parsecs";
            const Result r = expect_refused(dir, "bad_unit", s, "/grains/0/size/diameter");
            CHECK(r.err.find("parsecs") != std::string::npos);
        }
        {
            json s = small_scene();
            s["materials"][0]["youngs_modulus"] = "10 MPa s";  // a viscosity, not a modulus
            expect_refused(dir, "wrong_dimension", s, "/materials/0/youngs_modulus");
        }
        {
            json s = small_scene();
            s["materials"][0]["youngs_modulus"] = 1e-300;  // blew up (exit 3) before the range was checked
            expect_refused(dir, "absurd_modulus", s, "/materials/0/youngs_modulus");
        }
        {
            json s = small_scene();
            s["materials"][0]["density"] = "2500 mg/m3";  // 2.5e-3 kg/m3, less than air
            expect_refused(dir, "absurd_density", s, "/materials/0/density");
        }
        {
            json s = small_scene();
            s["run"]["timestep"] = "1 ms";
            const Result r = expect_refused(dir, "timestep_above_limit", s, "/run/timestep");
            CHECK(r.err.find("stable limit") != std::string::npos);
        }
        // A step of 0 quietly meant the automatic one; the automatic step is asked for by name.
        for (const json& zero : {json(0), json("0 s"), json("0 ns")}) {
            json s = small_scene();
            s["run"]["timestep"] = zero;
            expect_refused(dir, "timestep_zero", s, "/run/timestep");
        }
        {
            json s = small_scene();
            s["run"].erase("steps");
            expect_refused(dir, "no_length", s, "/run/steps");
        }
        {
            json s = small_scene();
            s["grains"][0]["material"] = "steel";
            expect_refused(dir, "unknown_material", s, "/grains/0/material");
        }
        {
            json s = small_scene();
            s["domain"]["periodic"] = "xw";
            expect_refused(dir, "bad_axis", s, "/domain/periodic");
        }
        {
            json s = small_scene();
            s["domain"]["hi"] = {"6 mm", "-6 mm", "6 mm"};
            expect_refused(dir, "inverted_box", s, "/domain/hi");
        }
        {
            // Listed grains: a bad unit names the component; a centre outside a closed axis and two
            // grains on top of each other are refused before the run (they used to stop it at step
            // 0 or 1 as a "blow-up" blaming the time step, exit code 3).
            json s = small_scene();
            s["domain"]["periodic"] = "xy";
            s["grains"][0]["placement"] = {{"method", "list"},
                                           {"positions", {{"1 mm", "1 mm", "1 mm"}, {"3 mm", "3 mm", "5 parsecs"}}}};
            expect_refused(dir, "list_bad_unit", s, "/grains/0/placement/positions/1/2");
            s["grains"][0]["placement"]["positions"][1] = {"3 mm", "3 mm", "9 mm"};
            expect_refused(dir, "list_outside_closed_axis", s, "/grains/0/placement/positions/1");
            s["grains"][0]["placement"]["positions"][1] = {"1 mm", "1 mm", "1.5 mm"};
            const Result r = expect_refused(dir, "list_overlapping", s, "/grains/0/placement");
            CHECK(r.err.find("overlap") != std::string::npos);
            s["grains"][0]["placement"]["positions"][1] = {"1 mm", "1 mm",
                                                           "-3 mm"};  // x, y periodic: fine in x, y only
            expect_refused(dir, "list_below_closed_axis", s, "/grains/0/placement/positions/1");
        }
        {
            // Two random batches in the same region are packed independently and overlap.
            json s = small_scene();
            s["materials"].push_back({{"name", "steel"}, {"density", "7800 kg/m3"}, {"youngs_modulus", "10 MPa"}});
            s["grains"][0]["placement"]["volume_fraction"] = 0.2;
            json second = s["grains"][0];
            second["material"] = "steel";
            s["grains"].push_back(second);
            const Result r = expect_refused(dir, "overlapping_batches", s, "/grains/1/placement");
            CHECK(r.err.find("/grains/0") != std::string::npos);
            // In disjoint regions they are fine.
            s["grains"][0]["placement"]["region"] = {{"lo", {0, 0, 0}}, {"hi", {"6 mm", "6 mm", "3 mm"}}};
            s["grains"][1]["placement"]["region"] = {{"lo", {0, 0, "3 mm"}}, {"hi", {"6 mm", "6 mm", "6 mm"}}};
            s["domain"]["periodic"] = "xy";
            s["walls"] = {{{"name", "floor"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
                          {{"name", "lid"}, {"type", "plane"}, {"point", {0, 0, "6 mm"}}, {"normal", {0, 0, -1}}}};
            const Result ok = run_scene(dir, "disjoint_batches", s);
            CAPTURE(ok.err);
            CHECK(ok.exit_code == 0);
        }
    }

    TEST_CASE("cli: a missing scene file and invalid JSON are refused with exit code 2") {
        TempDir dir;
        const Result missing =
            mrjam(dir, "run " + quote(dir.file("no_such_scene.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(missing.exit_code == 2);
        CHECK(missing.err.find("no_such_scene.json") != std::string::npos);
        CHECK(missing.err.find("cannot open") != std::string::npos);

        write_text(dir.file("broken.json"), "{\"seed\": 1, \"domain\": {\"lo\": [0, 0, 0],,}");
        const Result broken =
            mrjam(dir, "run " + quote(dir.file("broken.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(broken.exit_code == 2);
        CHECK(broken.err.find("broken.json") != std::string::npos);
        CHECK(broken.err.find("not valid JSON") != std::string::npos);

        // A key given twice: the parser kept the last one without a word. Named by its path, also
        // inside arrays; the same key in two different objects is fine.
        write_text(dir.file("twice.json"),
                   R"({"seed": 1, "grains": [{"size": 1}, {"material": "a", "material": "b"}]})");
        const Result twice =
            mrjam(dir, "run " + quote(dir.file("twice.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(twice.exit_code == 2);
        CHECK(twice.err.find("/grains/1/material") != std::string::npos);
        CHECK(twice.err.find("twice") != std::string::npos);
        write_text(dir.file("same_key_apart.json"), R"({"a": {"x": 1}, "b": [{"x": 1}, {"x": 2}]})");
        const Result apart =
            mrjam(dir, "run " + quote(dir.file("same_key_apart.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(apart.exit_code == 2);
        CHECK(apart.err.find("twice") == std::string::npos);  // refused for its missing keys, not for x

        // Nesting that only a hostile file has: 400 kB of "[[[[..." took 21 GB before it was
        // bounded. Refused at the depth limit, quickly, naming the file.
        write_text(dir.file("deep.json"), "{\"a\": " + std::string(400000, '[') + std::string(400000, ']') + "}");
        const Result deep =
            mrjam(dir, "run " + quote(dir.file("deep.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(deep.exit_code == 2);
        CHECK(deep.err.find("nested deeper than 64 levels") != std::string::npos);
        CHECK(deep.err.find("deep.json") != std::string::npos);

        // "--report --quiet": the option was taken as the report's file name.
        const Result as_option = mrjam(dir, "run " + quote(dir.file("twice.json")) + " --report --quiet");
        CHECK(as_option.exit_code == 2);
        CHECK(as_option.err.find("looks like an option") != std::string::npos);
        CHECK_FALSE(fs::exists("--quiet"));
        // A mistyped subcommand is named, with the known ones.
        const Result typo = mrjam(dir, "jamm " + quote(dir.file("twice.json")));
        CHECK(typo.exit_code == 2);
        CHECK(typo.err.find("unknown subcommand 'jamm'") != std::string::npos);
        CHECK(typo.err.find("jam, design") != std::string::npos);

        write_text(dir.file("array.json"), "[1, 2, 3]");
        const Result array =
            mrjam(dir, "run " + quote(dir.file("array.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(array.exit_code == 2);
        CHECK(array.err.find("expected a JSON object") != std::string::npos);
        CHECK_FALSE(fs::exists(dir.file("r.json")));

        const Result bad_checkpoint =
            mrjam(dir, "run --resume " + quote(dir.file("broken.json")) + " --report " + quote(dir.file("r.json")));
        CHECK(bad_checkpoint.exit_code != 0);
        CHECK(bad_checkpoint.err.find("not an mrjam checkpoint") != std::string::npos);
    }

    TEST_CASE("cli: resuming from a checkpoint ends where the uninterrupted run ends") {
        TempDir dir;
        // Stages of 150 and 100 steps. The reference run checkpoints only at step 200 (every 200),
        // inside the second stage, whose flow was set by the first (a resume used to lose it: the
        // checkpoint does not store the flow); the second run only at step 130 (every 130; 260 is
        // past the end), inside the first stage, so its resume crosses the stage boundary.
        for (const long every : {200L, 130L}) {
            CAPTURE(every);
            const std::string name = "two_stage_" + std::to_string(every);
            const std::string ck = dir.file(name + ".mrjam");
            const Result full = run_scene(dir, name, two_stage_scene(every, ck, dir.file("out")));
            CAPTURE(full.err);
            REQUIRE(full.exit_code == 0);
            REQUIRE(fs::exists(ck));
            const json a = read_report(dir, name);
            REQUIRE(a["status"] == "complete");
            REQUIRE(a["results"]["steps"] == 250);

            const Result resumed = mrjam(
                dir, "run --resume " + quote(ck) + " --report " + quote(dir.file(name + "_resumed.json")) + " --quiet");
            CAPTURE(resumed.err);
            REQUIRE(resumed.exit_code == 0);
            const json b = json::parse(slurp(dir.file(name + "_resumed.json")));
            CHECK(b["status"] == "complete");
            CHECK(b["performance"]["steps_run"] == 250 - every);
            const json& ra = a["results"];
            const json& rb = b["results"];
            CHECK(rb["steps"] == 250);
            CHECK(rb["simulated_time_s"].get<double>() == ra["simulated_time_s"].get<double>());
            CHECK(rb["kinetic_energy_J"].get<double>() == rel(ra["kinetic_energy_J"].get<double>()).epsilon(1e-12));
            CHECK(rb["rotational_energy_J"].get<double>() ==
                  rel(ra["rotational_energy_J"].get<double>()).epsilon(1e-12));
            CHECK(rb["elastic_energy_J"].get<double>() == rel(ra["elastic_energy_J"].get<double>()).epsilon(1e-12));
            CHECK(rb["contacts"] == ra["contacts"]);
            CHECK(rb["walls"] == ra["walls"]);  // forces and positions of floor and the moving lid
            // The report of the resumed run still lists both stages, and its inputs are the scene's.
            CHECK(rb["stages"].size() == 2);
            CHECK(rb["stages"] == ra["stages"]);
            CHECK(b["inputs"] == a["inputs"]);
            CHECK(b["seed"] == a["seed"]);
            if (every != 200) continue;
            // An older format (7: the term state laid out by the checkpoint code) is refused by
            // name, with what to do, not read as garbage.
            std::string v7 = slurp(ck);
            v7[7] = '7';  // "MRJAMCK7"
            mrjam_test::reseal_checkpoint(v7);
            write_text(dir.file("v7.mrjam"), v7);
            const Result old = mrjam(dir, "run --resume " + quote(dir.file("v7.mrjam")) + " --report " +
                                              quote(dir.file("v7.json")) + " --quiet");
            CAPTURE(old.err);
            CHECK(old.exit_code == 2);
            CHECK(old.err.find("format 7") != std::string::npos);
            CHECK(old.err.find("older mrjam") != std::string::npos);
            CHECK(old.err.find("v7.mrjam") != std::string::npos);
            // Damaged copies are bad input to --resume, named, whatever the damage: a length field
            // that promises more than the file holds (it asked for a huge allocation), and a cut file.
            std::string bytes = slurp(ck);
            const std::size_t scene_text = bytes.find('{');
            REQUIRE(scene_text != std::string::npos);
            REQUIRE(scene_text >= 8);
            const std::uint64_t huge = 1ull << 50;
            std::memcpy(bytes.data() + scene_text - 8, &huge, sizeof huge);  // the scene's length
            mrjam_test::reseal_checkpoint(bytes);  // past the checksum, to the length's own check
            write_text(dir.file("long_length.mrjam"), bytes);
            write_text(dir.file("cut.mrjam"), slurp(ck).substr(0, slurp(ck).size() / 2));
            // One bit flipped in the grains' state: without the checksum it ran, from the wrong state.
            std::string flipped = slurp(ck);
            flipped[flipped.size() / 2] ^= 1;
            write_text(dir.file("flipped.mrjam"), flipped);
            for (const char* damaged : {"long_length.mrjam", "cut.mrjam", "flipped.mrjam"}) {
                CAPTURE(damaged);
                const Result r = mrjam(dir, "run --resume " + quote(dir.file(damaged)) + " --report " +
                                                quote(dir.file("d.json")) + " --quiet");
                CHECK(r.exit_code == 2);
                CHECK(r.err.find("--resume") != std::string::npos);
                CHECK(r.err.find(damaged) != std::string::npos);
                if (std::string(damaged) == "flipped.mrjam") CHECK(r.err.find("checksum") != std::string::npos);
                if (std::string(damaged) == "long_length.mrjam")
                    CHECK(r.err.find("longer than the rest") != std::string::npos);
            }
        }
    }

    // A long set-up (packing a million grains takes minutes) answered Ctrl-C only at the first step.
    TEST_CASE("cli: SIGINT while the grains are being packed stops at once with 130, saying nothing was run") {
        TempDir dir;
        json scene = small_scene();
        scene["domain"]["hi"] = {"60 mm", "60 mm", "60 mm"};  // about 1.2 million grains of 1 mm at 0.3
        write_text(dir.file("big.json"), scene.dump(2));
        const auto t0 = std::chrono::steady_clock::now();
        const Result cut =
            mrjam(dir, "run " + quote(dir.file("big.json")) + " --report " + quote(dir.file("big_report.json")),
                  " & pid=$!; sleep 1; kill -INT $pid; wait $pid");
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        CAPTURE(cut.err);
        CHECK(cut.exit_code == 130);
        CHECK(cut.err.find("interrupted while placing the grains") != std::string::npos);
        CHECK(seconds < 10);  // the packing alone takes far longer
        CHECK_FALSE(fs::exists(dir.file("big_report.json")));
    }

    TEST_CASE("cli: SIGINT writes a checkpoint and exits 130; resuming it ends where the full run ends") {
        TempDir dir;
        // About 2300 grains for 10000 steps: ~1 s of work on one core, interrupted after 0.4 s.
        json scene = small_scene();
        scene["seed"] = 31;
        scene["domain"]["hi"] = {"16 mm", "16 mm", "16 mm"};
        scene["run"]["steps"] = 10000;
        scene["output"] = {{"directory", dir.file("out")}, {"checkpoint", {{"path", dir.file("interrupted.mrjam")}}}};
        const Result full = run_scene(dir, "full", scene);
        REQUIRE(full.exit_code == 0);
        const json a = read_report(dir, "full");

        write_text(dir.file("interrupt.json"), scene.dump(2));
        const Result cut = mrjam_test::mrjam_interrupted(
            dir, "run " + quote(dir.file("interrupt.json")) + " --report " + quote(dir.file("cut.json")) + " --quiet",
            0.4, [&](const Result&) { return fs::exists(dir.file("cut.json")); });
        CAPTURE(cut.err);
        REQUIRE(cut.exit_code == 130);
        const json c = json::parse(slurp(dir.file("cut.json")));
        CHECK(c["status"] == "interrupted");
        CHECK(c["partial"] == true);
        CHECK(c["checkpoint"] == dir.file("interrupted.mrjam"));
        CHECK(c["resume_with"].get<std::string>().find("--resume") != std::string::npos);
        const long stopped = c["results"]["steps"].get<long>();
        CHECK(stopped < 10000);
        REQUIRE(fs::exists(dir.file("interrupted.mrjam")));

        const Result resumed = mrjam(dir, "run --resume " + quote(dir.file("interrupted.mrjam")) + " --report " +
                                              quote(dir.file("resumed.json")) + " --quiet");
        CAPTURE(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        const json b = json::parse(slurp(dir.file("resumed.json")));
        CHECK(b["status"] == "complete");
        CHECK(b["performance"]["steps_run"] == 10000 - stopped);
        CHECK(b["results"]["steps"] == 10000);
        CHECK(b["results"]["simulated_time_s"].get<double>() == a["results"]["simulated_time_s"].get<double>());
        CHECK(b["results"]["kinetic_energy_J"].get<double>() ==
              rel(a["results"]["kinetic_energy_J"].get<double>()).epsilon(1e-12));
        CHECK(b["results"]["contacts"] == a["results"]["contacts"]);
    }

    TEST_CASE("cli: a raft over the whole periodic box takes every grain, also those that crossed a face") {
        // All grains drift at 0.1 m/s along x for 0.4 ms (40 um, less than half the skin, so no list
        // rebuild wraps them back); the grains that crossed x = 16 mm sit just beyond the box until
        // the next rebuild. A raft whose region is the whole box must still take them all (it used
        // to miss them: 10 of 2347 grains).
        TempDir dir;
        json scene = small_scene();
        scene["domain"]["hi"] = {"16 mm", "16 mm", "16 mm"};
        scene["grains"][0].erase("random_velocity");
        scene["grains"][0]["velocity"] = {"0.1 m/s", 0, 0};
        scene["run"] = json::object();
        scene["stages"] = {
            {{"name", "drift"}, {"duration", "0.4 ms"}},
            {{"name", "freeze"},
             {"steps", 1},
             {"form_rafts",
              {{{"name", "all"}, {"region", {{"lo", {0, 0, 0}}, {"hi", {"16 mm", "16 mm", "16 mm"}}}}}}}}};
        const Result r = run_scene(dir, "raft", scene);
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = read_report(dir, "raft");
        const json& drift = rep["results"]["stages"][0]["state"];
        CHECK(drift["neighbour_builds"] == 1);  // the premise: nothing wrapped the grains back
        REQUIRE(rep["results"]["rafts"].size() == 1);
        CHECK(rep["results"]["rafts"][0]["grains"] == rep["results"]["grains"]);
    }

    // Benchmarks take their options as a command does its scene: a value with no meaning (a grain
    // of permeability 1 tabled NaN ratios with exit 0), too few grains, and an output path that
    // cannot be written (found after the whole benchmark) are refused at once, naming the option.
    TEST_CASE("cli: bench options that cannot give a result are refused before the benchmark") {
        TempDir dir;
        write_text(dir.file("a_file"), "x");
        for (const auto& [args, option] : std::vector<std::pair<std::string, std::string>>{
                 {"sphere-pair --permeability 1", "--permeability"},
                 {"sphere-pair --permeability nan", "--permeability"},
                 {"sphere-pair --gap 1e-300", "--gap"},
                 {"sphere-pair --gap 1e308", "--gap"},
                 {"contact --grains 20 --steps 1 --json " + quote(dir.file("")), "--json"},
                 {"contact --grains 20 --steps 1 --write-data " + quote(dir.file("a_file") + "/d.data"),
                  "--write-data"},
                 {"flow --json " + quote(dir.file("a_file") + "/f.json"), "--json"},
                 {"magnetic-accuracy --grains 16", "--grains"}}) {
            CAPTURE(args);
            const Result r = mrjam_test::mrjam_bench(dir, args);
            CAPTURE(r.err);
            CHECK(r.exit_code == 2);
            CHECK(r.err.find(option) != std::string::npos);
        }
    }

}  // TEST_SUITE
