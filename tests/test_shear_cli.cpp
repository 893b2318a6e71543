// End-to-end checks of `mrjam shear`: a short study writes a report with the required keys and its
// plots; bad shear scenes are refused with exit 2 and the JSON path; an interrupted study resumes
// without redoing finished rates and ends where an uninterrupted one ends; --calibrate runs.
#include <doctest/doctest.h>

#include <cmath>

#include "test_support.hpp"

using namespace mrjam_test;
using json = nlohmann::json;

namespace {

// Monodisperse 6.7 um iron in a 40 um cell: about 120 grains, a fraction of a second per study.
json small_scene(const std::string& out_dir) {
    return {{"description", "test"},
            {"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
            {"cell", {{"size", {"40 um", "40 um", "40 um"}}, {"raft_thickness", "7 um"}}},
            {"material", mrjam_test::chapter2_iron()},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "600 mT"}}},
            {"magnetise", {{"min_duration", "3 us"}, {"max_duration", "6 us"}, {"field_ramp", "2 us"}}},
            {"ladder",
             {{"shear_rates", {"3000 1/s", "1500 1/s", "600 1/s"}}, {"strain_first", 0.1}, {"strain_per_rate", 0.05}}},
            {"measure", {{"samples_per_rate", 20}, {"blocks", 5}}},
            {"experiment", {{"yield_stress", "44.9 kPa"}, {"flow_curve", {{1000, 50000}, {300, 46000}}}}},
            {"output", {{"directory", out_dir}}}};
}

Result shear(const TempDir& dir, const std::string& name, const json& scene, const std::string& extra = "") {
    write_text(dir.file(name + ".json"), scene.dump(2));
    return mrjam(dir, "shear " + quote(dir.file(name + ".json")) + " --report " +
                          quote(dir.file(name + "_report.json")) + " --fidelity quick " + extra);
}

void expect_shear_refused(const TempDir& dir, const std::string& label, const json& scene, const std::string& path) {
    expect_mode_refused(dir, "shear", label, scene, path, "--fidelity quick");
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE(
        "shear cli: a short study reports the flow curve, the fits, the yield stress, the field sweep and its plots") {
        TempDir dir;
        json scene = small_scene(dir.file("out"));
        scene["field_sweep"] = {{"flux_densities", {"200 mT", "400 mT"}}, {"shear_rate", "1000 1/s"}, {"strain", 0.05}};
        const Result r = shear(dir, "s", scene);
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        CHECK(r.err.find("[shear]") != std::string::npos);  // progress on stderr
        const json rep = json::parse(slurp(dir.file("s_report.json")));
        CHECK(rep["mode"] == "shear");
        CHECK(rep["status"] == "complete");
        CHECK(rep["fidelity"]["tier"] == "quick");
        const json& res = rep["results"];
        REQUIRE(res["flow_curve"].size() == 3);
        for (const auto& q : res["flow_curve"]) {
            CHECK(q["rate_1_s"].get<double>() > 0);
            CHECK(q["stress_Pa"].is_number());
            CHECK(q["error_Pa"].get<double>() >= 0);
            // Where the stress settles: within the rate's strain (MSER searches its first half).
            CHECK(q["steady_from_strain"].get<double>() >= 0);
            CHECK(q["steady_from_strain"].get<double>() <= 0.5 * q["strain"].get<double>() * (1 + 1e-12));
            CHECK(q["steady_before_window"].is_boolean());
            CHECK(q["drifting_in_window"].is_boolean());
            CHECK(q["drift_error_Pa"].get<double>() >= 0);
            // Mn times the magnetic scale is the carrier's viscous stress, 10 mPa s x rate.
            CHECK(q["mason_number"].get<double>() * q["magnetic_stress_scale_Pa"].get<double>() ==
                  rel(0.010 * q["rate_1_s"].get<double>()));
            CHECK(q["stress_over_magnetic_scale"].get<double>() * q["magnetic_stress_scale_Pa"].get<double>() ==
                  rel(q["stress_Pa"].get<double>()));
            CHECK(q["contacts_per_grain"].get<double>() > 0);
        }
        // The fitted rates not steady in their windows are listed, as their own flags say.
        std::vector<double> unsteady;
        for (const auto& q : res["flow_curve"])
            if (!q["steady_before_window"].get<bool>() || q["drifting_in_window"].get<bool>())
                unsteady.push_back(q["rate_1_s"].get<double>());
        CHECK(res["fit_rates_not_steady_1_s"].get<std::vector<double>>() == unsteady);
        // The speed counts the main cell's steps, the magnetisation's and every rate's, and not the
        // field sweep's runs (studies of their own).
        long cell_steps =
            std::lround(res["magnetisation"]["duration_s"].get<double>() / rep["timestep"]["used_s"].get<double>());
        for (const auto& q : res["flow_curve"]) cell_steps += q["steps"].get<long>();
        CHECK(rep["performance"]["steps_run"].get<long>() == cell_steps);
        CHECK(rep["performance"]["core_us_per_grain_step"].get<double>() > 0);
        CHECK(rep["performance"]["grain_steps_per_s"].get<double>() *
                  rep["performance"]["core_us_per_grain_step"].get<double>() ==
              rel(1e6 * rep["threads"].get<double>()));
        CHECK(res["flow_curve"][0]["rate_1_s"].get<double>() == rel(3000));
        REQUIRE(res["yield_stress_Pa"].is_number());
        CHECK(res["fits"]["bingham"]["yield_stress_Pa"] == res["yield_stress_Pa"]);
        CHECK(res["fits"].contains("casson"));
        CHECK(res["fits"].contains("herschel_bulkley"));
        CHECK(res["magnetisation"].contains("criterion"));
        CHECK(res["experiment"]["yield_stress_Pa"].get<double>() == rel(44.9e3));
        CHECK(res["experiment"].contains("relative_error"));
        REQUIRE(res["field_sweep"].size() == 2);
        CHECK(res["field_sweep"][1]["flux_density_T"].get<double>() == rel(0.4));
        // Each field is a sweep point: a shear study of its own (the ladder's first rate, then the
        // sweep's), whose last rate is the row.
        const json point = json::parse(slurp(dir.file("out/field_sweep/points/400mT/report.json")));
        CHECK(point["inputs"]["field"]["flux_density"].get<double>() == rel(0.4));
        REQUIRE(point["results"]["flow_curve"].size() == 2);
        CHECK(point["results"]["flow_curve"][0]["rate_1_s"].get<double>() == rel(3000));
        CHECK(point["results"]["flow_curve"][1]["stress_Pa"] == res["field_sweep"][1]["stress_Pa"]);
        CHECK_FALSE(point["inputs"].contains("field_sweep"));
        const json manifest = json::parse(slurp(dir.file("out/field_sweep/manifest.json")));
        REQUIRE(manifest["points"].size() == 2);
        for (const json& p : manifest["points"]) CHECK(p["state"] == "done");
        // A field given twice would be one study: refused by its place in the list.
        json twice = scene;
        twice["field_sweep"]["flux_densities"] = {"200 mT", "0.2 T"};
        expect_shear_refused(dir, "field_twice", twice, "/field_sweep/flux_densities/1");
        CHECK(rep["inputs"]["ladder"]["strain_first"] == 0.1);  // the recipe is echoed
        for (const char* key : {"flow_curve", "field_sweep", "stress_strain"}) {
            const std::string svg = slurp(rep["plots"][key].get<std::string>());
            CHECK(svg.rfind("<svg", 0) == 0);
        }
    }

    TEST_CASE("shear cli: --converge runs every cell size and seed, reports each size and the verdict, and resumes") {
        TempDir dir;
        json scene = small_scene(dir.file("out"));
        scene["convergence"] = {{"cell_sizes", {"36 um", "40 um", "44 um"}}, {"seeds", 2}};
        const Result r = shear(dir, "conv", scene, "--converge --threads 1");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = json::parse(slurp(dir.file("conv_report.json")));
        CHECK(rep["mode"] == "shear-converge");
        CHECK(rep["status"] == "complete");
        const json& res = rep["results"];
        REQUIRE(res["sizes"].size() == 3);
        for (const json& size : res["sizes"]) {
            CHECK(size["seeds_done"] == 2);
            CHECK(size["flow_curve"].size() == 3);
            REQUIRE(size["seed_yield_stresses_Pa"].size() == 2);
        }
        CHECK(res["sizes"][2]["edge_m"].get<double>() == rel(44e-6));
        // A larger cell holds more grains.
        CHECK(res["sizes"][2]["grains_mean"].get<double>() > res["sizes"][0]["grains_mean"].get<double>());
        CHECK(res["converged"].is_boolean());
        CHECK(res["yield_stress_Pa"].is_number());
        CHECK(res["experiment"]["relative_error"].is_number());
        // Each run is the scene at that edge and seed, the field sweep's and this block left out.
        const json run = json::parse(slurp(dir.file("out/convergence/points/40um_seed2/report.json")));
        CHECK(run["seed"] == 2);
        CHECK(run["results"]["cell"]["size_m"][0].get<double>() == rel(40e-6));
        CHECK(res["sizes"][1]["seed_yield_stresses_Pa"][1] == run["results"]["yield_stress_Pa"]);
        // Each rate counts the seeds still drifting through its window, as their reports say.
        int drifting = 0;
        for (const char* seed : {"40um_seed1", "40um_seed2"})
            drifting += json::parse(slurp(dir.file(std::string("out/convergence/points/") + seed +
                                                   "/report.json")))["results"]["flow_curve"][0]["drifting_in_window"]
                            .get<bool>();
        CHECK(res["sizes"][1]["flow_curve"][0]["seeds_drifting"] == drifting);
        for (const char* plot : {"convergence", "flow_curves"})
            CHECK(slurp(rep["plots"][plot].get<std::string>()).rfind("<svg", 0) == 0);
        // Rerun: every run is done, none is run again, and the verdict is the same.
        const Result again = shear(dir, "conv", scene, "--converge --threads 1");
        REQUIRE(again.exit_code == 0);
        const json rep2 = json::parse(slurp(dir.file("conv_report.json")));
        CHECK(rep2["results"] == rep["results"]);
        for (const json& p : json::parse(slurp(dir.file("out/convergence/manifest.json")))["points"])
            CHECK(p["attempts"] == 1);
        // A changed scene against those runs is refused, naming what changed.
        scene["field"]["flux_density"] = "500 mT";
        const Result changed = shear(dir, "conv", scene, "--converge --threads 1");
        CHECK(changed.exit_code == 2);
        CHECK(changed.err.find("--converge") != std::string::npos);
        CHECK(changed.err.find("/shear_input/field/flux_density") != std::string::npos);
        const Result mixed = shear(dir, "conv", scene, "--converge --resume x.mrjam");
        CHECK(mixed.exit_code != 0);
    }

    TEST_CASE("shear cli: pairwise contact damping replaces the Stokes drag when asked") {
        TempDir dir;
        json scene = small_scene(dir.file("out"));
        scene["dissipation"] = "contact_damping";
        const Result r = shear(dir, "damped", scene, "--quiet");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = json::parse(slurp(dir.file("damped_report.json")));
        CHECK_FALSE(rep["engine_scene"].contains("fluid"));  // no drag against the affine flow
        // Default coefficient: the Stokes coefficient of the mean grain, 6 pi mu R = 3 pi mu d.
        CHECK(rep["engine_scene"]["contact"]["pair_damping"].get<double>() == rel(3 * M_PI * 0.01 * 6.7e-6));
        CHECK(rep["results"]["flow_curve"].size() == 3);
        scene.erase("dissipation");
        scene["contact_damping"] = "1 uN s/m";
        const Result stray = shear(dir, "stray", scene, "--quiet");
        CHECK(stray.exit_code == 2);
        CHECK(stray.err.find("/contact_damping") != std::string::npos);
    }

    TEST_CASE("shear cli: a monolayer cell runs end to end, with rafts and with Lees-Edwards boundaries") {
        TempDir dir;
        for (const char* boundaries : {"rafts", "lees_edwards"}) {
            CAPTURE(boundaries);
            json scene = small_scene(dir.file(std::string("out_") + boundaries));
            scene["cell"] = {{"size", {"40 um", "6.7 um", "40 um"}}, {"monolayer", true}, {"boundaries", boundaries}};
            if (std::string(boundaries) == "rafts") scene["cell"]["raft_thickness"] = "7 um";
            scene["area_fraction"] = 0.6;
            const Result r = shear(dir, std::string("mono_") + boundaries, scene, "--quiet");
            CAPTURE(r.err);
            REQUIRE(r.exit_code == 0);
            const json rep = json::parse(slurp(dir.file(std::string("mono_") + boundaries + "_report.json")));
            const json& cell = rep["results"]["cell"];
            CHECK(cell["monolayer"] == true);
            CHECK(cell["stress_thickness_m"].get<double>() == rel(6.7e-6));
            // 0.6 of a 40 um square in 6.7 um discs: 0.6 x 1600 / 35.3 = 27 discs.
            CHECK(cell["grains"].get<int>() == rel(27).epsilon(0.1));
            REQUIRE(rep["results"]["flow_curve"].size() == 3);
            for (const auto& q : rep["results"]["flow_curve"]) CHECK(std::isfinite(q["stress_Pa"].get<double>()));
            CHECK(rep["engine_scene"]["domain"]["monolayer"] == "y");
        }
    }

    TEST_CASE("shear cli: bad shear scenes are refused with the JSON path and a fix") {
        TempDir dir;
        json base = small_scene(dir.file("out"));
        {
            json s = base;
            s["ladder"]["shear_rates"] = {"600 1/s", "1500 1/s"};
            expect_shear_refused(dir, "increasing_rates", s, "/ladder/shear_rates/1");
        }
        {
            json s = base;
            s["ladder"].erase("shear_rates");
            s["ladder"]["wall_speeds"] = {0.1, 0.05, 0.05};
            expect_shear_refused(dir, "repeated_speed", s, "/ladder/wall_speeds/2");
        }
        {
            // A magnetic range longer than half the cell: a pair would meet through two images.
            json s = base;
            s["magnetic"] = {{"cutoff", {{"beyond_contact", "20 um"}}}};
            expect_shear_refused(
                dir, "range_past_half_cell", s,
                "/magnetic/cutoff: the magnetic cutoff of the largest grains drawn (diameter 6.7e-06 m)");
        }
        {
            // A strain that needs more steps than any run could take (it ran, showing "step 0/2.3e17").
            json s = base;
            s["ladder"]["strain_first"] = 1e12;
            expect_shear_refused(dir, "endless_strain", s, "/ladder/strain_first: needs ");
        }
        {
            // Tesla for millitesla, in the field and in a sweep.
            json s = base;
            s["field"]["flux_density"] = "600 T";
            expect_shear_refused(dir, "tesla_slip", s, "/field/flux_density: 600 T is more than any magnet applies");
            s = base;
            s["field_sweep"] = {{"flux_densities", {"100 mT", "300 T"}}};
            expect_shear_refused(dir, "tesla_slip_sweep", s, "/field_sweep/flux_densities/1");
        }
        {
            json s = base;
            s["cell"] = {{"size", {"40 um", "40 um", "20 um"}}, {"raft_thickness", "3 um"}};
            expect_shear_refused(dir, "thin_cell", s, "/cell/size");
        }
        {
            json s = base;
            s["size"] = {{"distribution", "table"}, {"diameters", json::array()}, {"frequencies", json::array()}};
            expect_shear_refused(dir, "empty_table", s, "/size/diameters");
        }
        {
            json s = base;
            s["material"]["frictoin"] = 0.2;
            expect_shear_refused(dir, "typo", s, "/material/frictoin");
        }
        {
            // A field still ramping when the shear starts (it gave a negative yield stress), and a
            // single block, whose error bar would read 0.
            json s = base;
            s["magnetise"]["field_ramp"] = "4 us";
            expect_shear_refused(dir, "ramp_past_magnetisation", s, "/magnetise/field_ramp");
            s = base;
            s["measure"]["blocks"] = 1;
            expect_shear_refused(dir, "one_block", s, "/measure/blocks");
        }
        {
            json s = base;
            s["cell"]["boundaries"] = "lees_edward";
            expect_shear_refused(dir, "boundaries_typo", s, "/cell/boundaries");
        }
        {
            json s = base;
            s["cell"]["boundaries"] = "lees_edwards";  // keeps raft_thickness: a Lees-Edwards cell has no rafts
            expect_shear_refused(dir, "rafts_with_lees_edwards", s, "/cell/raft_thickness");
        }
        json mono = base;
        mono["cell"]["monolayer"] = true;
        mono["cell"]["size"] = {"40 um", "6.7 um", "40 um"};
        mono.erase("volume_fraction");
        {
            json s = mono;
            s["volume_fraction"] = 0.3;
            expect_shear_refused(dir, "monolayer_volume_fraction", s, "/volume_fraction");
        }
        {
            json s = mono;
            s["area_fraction"] = 0.9;
            expect_shear_refused(dir, "monolayer_too_dense", s, "/area_fraction");
        }
        {
            json s = mono;
            s["field"]["direction"] = {0, 1, 0};
            expect_shear_refused(dir, "monolayer_field_out_of_plane", s, "/field/direction");
        }
        {
            json s = mono;
            s["cell"]["size"] = {"40 um", "3 um", "40 um"};
            expect_shear_refused(dir, "monolayer_too_thin", s, "/cell/size");
        }
        {
            json s = base;
            s["area_fraction"] = 0.5;
            expect_shear_refused(dir, "area_fraction_in_3d", s, "/area_fraction");
        }
        {
            json s = base;
            s["size"] = {{"distribution", "mixture"},
                         {"parts", {{{"share", 0}, {"size", {{"distribution", "single"}, {"diameter", "5 um"}}}}}}};
            expect_shear_refused(dir, "zero_share", s, "/size/parts");
        }
    }

}  // TEST_SUITE

namespace {

// Runs the study whole, then again interrupted half way and resumed from its checkpoint: the
// resumed study must not redo finished rates and must end bit for bit where the whole one ends.
// `at`: the share of the whole study's wall time at which it is interrupted.
void check_resume_matches(const TempDir& dir, json scene, double at = 0.5) {
    scene["output"]["directory"] = dir.file("out_full");
    // Three rates, enough strain for a rate to finish before the signal (the checks are of
    // equality, bit for bit, not of the physics).
    scene["ladder"] = {
        {"shear_rates", {"3000 1/s", "1500 1/s", "750 1/s"}}, {"strain_first", 0.15}, {"strain_per_rate", 0.05}};
    const Result full = shear(dir, "full", scene, "--quiet");
    REQUIRE(full.exit_code == 0);
    const json a = json::parse(slurp(dir.file("full_report.json")));

    scene["output"]["directory"] = dir.file("out_cut");
    write_text(dir.file("cut.json"), scene.dump());
    const double wall = a["wall_time_s"].get<double>();
    const Result cut = mrjam_test::mrjam_interrupted(
        dir,
        "shear " + quote(dir.file("cut.json")) + " --report " + quote(dir.file("cut_report.json")) +
            " --fidelity quick --quiet",
        std::max(0.05, at * wall), [&](const Result&) { return std::filesystem::exists(dir.file("cut_report.json")); });
    REQUIRE(cut.exit_code == 130);
    const json c = json::parse(slurp(dir.file("cut_report.json")));
    CHECK(c["status"] == "interrupted");
    CHECK(c["resume_with"].get<std::string>().find("--resume") != std::string::npos);
    const std::size_t finished = c["results"]["flow_curve"].size();
    const Result resumed = mrjam(dir, "shear --resume " + quote(c["checkpoint"].get<std::string>()) + " --report " +
                                          quote(dir.file("resumed.json")));
    CAPTURE(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    // Rates finished before the interrupt are not run again (no progress line reports them; a
    // sweep's cells shear at the ladder's first rate too, so there the lines cannot tell).
    MESSAGE("interrupted with " << finished << " flow-curve rate(s) finished");
    for (std::size_t k = 0; !scene.contains("field_sweep") && k < finished; ++k) {
        char line[64];
        std::snprintf(line, sizeof line, "rate %.4g 1/s:", c["results"]["flow_curve"][k]["rate_1_s"].get<double>());
        CHECK(resumed.err.find(line) == std::string::npos);
    }
    const json b = json::parse(slurp(dir.file("resumed.json")));
    REQUIRE(b["results"]["flow_curve"].size() == a["results"]["flow_curve"].size());
    // The checkpoint holds the whole state, so the resumed study ends bit for bit where the full one does.
    for (std::size_t k = 0; k < a["results"]["flow_curve"].size(); ++k) {
        CHECK(b["results"]["flow_curve"][k]["stress_Pa"] == a["results"]["flow_curve"][k]["stress_Pa"]);
        CHECK(b["results"]["flow_curve"][k]["bulk_stress_Pa"] == a["results"]["flow_curve"][k]["bulk_stress_Pa"]);
    }
    if (a["results"].contains("field_sweep")) CHECK(b["results"]["field_sweep"] == a["results"]["field_sweep"]);
    // The first cell's engine scene and step are reported also when the resumed part starts
    // after that cell (they come from the checkpoint, not from rebuilding the cell).
    CHECK(b["timestep"] == a["timestep"]);
    json engine_a = a["engine_scene"], engine_b = b["engine_scene"];
    REQUIRE(engine_b.is_object());
    engine_a.erase("output");  // out_full and out_cut
    engine_b.erase("output");
    CHECK(engine_b == engine_a);
    // A completed study leaves no checkpoint behind to be resumed by mistake.
    CHECK_FALSE(std::filesystem::exists(c["checkpoint"].get<std::string>()));
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE(
        "shear cli: an interrupted study resumes without redoing finished rates and ends as the uninterrupted one") {
        TempDir dir;
        check_resume_matches(dir, small_scene(""));
    }

    TEST_CASE(
        "shear cli: a field sweep interrupted after its first cell resumes and reports as the uninterrupted one") {
        TempDir dir;
        json scene = small_scene("");
        // A sweep rate that is not on the ladder, so the progress lines tell the cells apart.
        scene["field_sweep"] = {{"flux_densities", {"200 mT", "400 mT"}}, {"shear_rate", "1200 1/s"}, {"strain", 0.02}};
        check_resume_matches(dir, scene, 0.85);
    }

    TEST_CASE(
        "shear cli: an interrupted Lees-Edwards study resumes bit for bit (the checkpoint carries the sliding "
        "offset)") {
        TempDir dir;
        json scene = small_scene("");
        scene["cell"] = {{"size", {"40 um", "40 um", "40 um"}}, {"boundaries", "lees_edwards"}};
        check_resume_matches(dir, scene);
        const json rep = json::parse(slurp(dir.file("full_report.json")));
        CHECK(rep["results"]["cell"]["boundaries"] == "lees_edwards");
        CHECK(rep["results"]["cell"]["gap_m"].get<double>() == rel(40e-6));
        if (rep["results"]["cell"].contains("rafts")) CHECK(rep["results"]["cell"]["rafts"].empty());
        for (const auto& q : rep["results"]["flow_curve"]) {
            CHECK(q["stress_source"] == "virial of the Lees-Edwards box");
            CHECK(q["stress_Pa"] == q["bulk_stress_Pa"]);
            CHECK_FALSE(q.contains("lower_raft_stress_Pa"));
        }
    }

    TEST_CASE("shear cli: a Lees-Edwards cell started at a high rate starts on the affine profile") {
        // 1e6 1/s in the 40 um cell: the sliding image moves at rate Z = 40 m/s. Grains started from
        // rest would meet it at up to that speed; on the affine profile neighbours approach at about
        // rate d = 6.7 m/s. The largest Hertz overlap of a head-on pair at speed v (equal spheres,
        // delta / R = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) / R) is 0.080 R at rate d and 0.33 R at
        // rate Z; the test allows twice the first, which a start from rest exceeded (0.17 R).
        TempDir dir;
        json scene = small_scene(dir.file("out"));
        scene["cell"] = {{"size", {"40 um", "40 um", "40 um"}}, {"boundaries", "lees_edwards"}};
        scene["ladder"] = {{"shear_rates", {"1e6 1/s", "5e5 1/s"}}, {"steps_first", 20}, {"steps_per_rate", 20}};
        const Result r = shear(dir, "fast", scene, "--quiet");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = json::parse(slurp(dir.file("fast_report.json")));
        const double radius = 3.35e-6, rate = 1e6, v = rate * 2 * radius;
        const double mass = 7800 * 4.0 / 3.0 * 3.141592653589793 * radius * radius * radius;
        const double e_star = 1e9 / (2 * (1 - 0.278 * 0.278)), r_star = radius / 2;
        const double hertz = std::pow(15 * (mass / 2) * v * v / (16 * e_star * std::sqrt(r_star)), 0.4) / radius;
        CHECK(hertz == rel(0.0797).epsilon(0.01));
        const json& first = rep["results"]["flow_curve"][0];
        CHECK(first["max_overlap_ratio_seen"].get<double>() < 2 * hertz);
        CHECK(std::isfinite(first["stress_Pa"].get<double>()));
        // Too few steps for the samples is refused by the key that sets them, not averaged from one sample.
        scene["ladder"] = {{"shear_rates", {"1e7 1/s"}}, {"strain_first", 0.1}};
        expect_shear_refused(dir, "few_steps", scene, "/ladder/strain_first");
    }

    TEST_CASE("shear cli: --calibrate fits a parameter to a measured flow curve and reports the optimum") {
        TempDir dir;
        const json scene = small_scene(dir.file("out"));
        write_text(dir.file("data.csv"), "# rate (1/s), stress (Pa)\nrate,stress\n3000, 30000\n1500, 28000\n");
        const Result r = shear(
            dir, "cal", scene,
            "--quiet --calibrate " + quote(dir.file("data.csv")) + " --parameter field_scale=0.5:1.5 --max-runs 4");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json rep = json::parse(slurp(dir.file("cal_report.json")));
        CHECK(rep["mode"] == "shear-calibrate");
        REQUIRE(rep["runs"].size() == 4);
        double best = 1e300;
        for (const auto& run : rep["runs"]) {
            const double f = run["values"]["field_scale"];
            CHECK(f >= 0.5);
            CHECK(f <= 1.5);
            if (run["residual"].is_number()) best = std::min(best, run["residual"].get<double>());
        }
        CHECK(rep["best"]["residual"].get<double>() == best);
        CHECK(rep["best"]["flow_curve"].size() == 2);  // the ladder is the data's rates
        CHECK(slurp(rep["plots"]["calibration"].get<std::string>()).rfind("<svg", 0) == 0);

        write_text(dir.file("bad.csv"), "1000, 2\n");
        const Result bad = shear(
            dir, "bad", scene, "--quiet --calibrate " + quote(dir.file("bad.csv")) + " --parameter friction=0.05:0.3");
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("--calibrate") != std::string::npos);
        const Result unknown = shear(
            dir, "unk", scene, "--quiet --calibrate " + quote(dir.file("data.csv")) + " --parameter fricton=0.05:0.3");
        CHECK(unknown.exit_code == 2);
        CHECK(unknown.err.find("fricton") != std::string::npos);
        // A range with units or trailing text (stod read "0.1 um" as 0.1), a pointer that is not
        // one, and a parameter without --calibrate: refused, naming --parameter.
        for (const std::string& bad_parameter :
             {"--calibrate " + quote(dir.file("data.csv")) + " --parameter 'friction=0.1 um:0.5'",
              "--calibrate " + quote(dir.file("data.csv")) + " --parameter friction=0:0.5xyz",
              "--calibrate " + quote(dir.file("data.csv")) + " --parameter '/material/fr~iction=0:1'",
              // One key twice (by name and by pointer): a 2D search along one axis.
              "--calibrate " + quote(dir.file("data.csv")) +
                  " --parameter friction=0:1 --parameter /material/friction=0:2",
              std::string("--parameter friction=0:0.5"), std::string("--max-runs 3")}) {
            CAPTURE(bad_parameter);
            const Result refused = shear(dir, "badp", scene, "--quiet " + bad_parameter);
            CHECK(refused.exit_code == 2);
            CHECK((refused.err.find("--parameter") != std::string::npos ||
                   refused.err.find("--max-runs") != std::string::npos));
        }
        // A range past what its key accepts (restitution in (0, 1], a negative friction, a
        // permeability below 1) is refused before the first study, naming the corner and the key;
        // it used to fail at the search's first step outside, after the studies before it.
        for (const std::string range : {"restitution=0.5:1.5", "friction=-0.1:0.5", "relative_permeability=0.5:100"}) {
            CAPTURE(range);
            const Result refused = shear(
                dir, "range", scene, "--quiet --calibrate " + quote(dir.file("data.csv")) + " --parameter " + range);
            CHECK(refused.exit_code == 2);
            CHECK(refused.err.find("--parameter") != std::string::npos);
            CHECK(refused.err.find("/material/" + range.substr(0, range.find('='))) != std::string::npos);
            CHECK(refused.err.find("corner") != std::string::npos);
        }
        // A scene path that is a directory says so.
        const Result directory = mrjam(dir, "shear " + quote(dir.file("")) + " --quiet");
        CHECK(directory.exit_code == 2);
        CHECK(directory.err.find("is a directory") != std::string::npos);
    }

}  // TEST_SUITE
