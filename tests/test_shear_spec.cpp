// Unit checks of the shear-scene reader: a mixture of size tables keeps its shares of solid
// volume (Trendler's 33:67), rates follow from wall speeds as 2 v / gap, and tier defaults apply.
#include <doctest/doctest.h>

#include <cmath>

#include "magnetic/magnetic_model.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "shear/calibration.hpp"
#include "shear/shear_spec.hpp"
#include "test_support.hpp"

using mrjam_test::rel;

using namespace mrjam;
using json = nlohmann::json;

namespace {
json base_scene() {
    return {{"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
            {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}}},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "600 mT"}}}};
}
}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("shear scene: a 33:67 mixture of two number tables keeps 33% of the solid volume in the first") {
        json s = base_scene();
        const json small = {{"distribution", "table"},
                            {"basis", "number"},
                            {"diameters", {"1 um", "2 um"}},
                            {"frequencies", {0.5, 0.5}}};
        const json large = {{"distribution", "table"},
                            {"basis", "number"},
                            {"diameters", {"5 um", "8 um", "10 um"}},
                            {"frequencies", {0.2, 0.5, 0.3}}};
        s["size"] = {{"distribution", "mixture"},
                     {"parts", {{{"share", 33}, {"size", small}}, {{"share", 67}, {"size", large}}}}};
        const ShearSpec spec = read_shear_spec(s, "standard");
        const auto d = spec.size_table["diameters"].get<std::vector<double>>();
        const auto f = spec.size_table["frequencies"].get<std::vector<double>>();
        REQUIRE(d.size() == 5);
        CHECK(spec.size_table["basis"] == "number");
        double v_small = 0, v_all = 0;
        for (std::size_t k = 0; k < d.size(); ++k) {
            const double v = f[k] * d[k] * d[k] * d[k];
            v_all += v;
            if (d[k] < 3e-6) v_small += v;
        }
        CHECK(v_small / v_all == rel(0.33).epsilon(1e-12));
        // Within a part, the number ratio of its classes is kept: 5 um : 8 um = 0.2 : 0.5.
        CHECK(f[2] / f[3] == rel(0.4).epsilon(1e-12));
        CHECK(spec.largest_diameter == rel(10e-6));
    }

    TEST_CASE("shear scene: mixture shares must sum to 1 or to 100; 0.33 and 0.67 is the same fluid as 33 and 67") {
        json s = base_scene();
        const json small = {{"distribution", "single"}, {"diameter", "1 um"}};
        const json large = {{"distribution", "single"}, {"diameter", "6 um"}};
        auto with_shares = [&](double a, double b) {
            s["size"] = {{"distribution", "mixture"},
                         {"parts", {{{"share", a}, {"size", small}}, {{"share", b}, {"size", large}}}}};
            return s;
        };
        const ShearSpec per_cent = read_shear_spec(with_shares(33, 67), "quick");
        const ShearSpec fractions = read_shear_spec(with_shares(0.33, 0.67), "quick");
        const auto f100 = per_cent.size_table["frequencies"].get<std::vector<double>>();
        const auto f1 = fractions.size_table["frequencies"].get<std::vector<double>>();
        REQUIRE(f100.size() == 2);
        REQUIRE(f1.size() == 2);
        for (std::size_t k = 0; k < 2; ++k) CHECK(f1[k] == rel(f100[k]).epsilon(1e-12));  // rounding only
        for (const auto& [a, b] : {std::pair{30.0, 67.0}, std::pair{0.3, 0.6}, std::pair{1.0, 2.0}}) {
            CAPTURE(a);
            CHECK_THROWS_WITH_AS(read_shear_spec(with_shares(a, b), "quick"), doctest::Contains("/size/parts"),
                                 SceneError);
        }
    }

    TEST_CASE(
        "shear scene: a cell whose periodic sides do not exceed two of the largest grains is refused at /cell/size") {
        json s = base_scene();
        s["size"] = {{"distribution", "single"}, {"diameter", "20 um"}};
        s["cell"] = {{"size", {"41 um", "41 um", "90 um"}}};
        CHECK_NOTHROW(read_shear_spec(s, "quick"));
        s["cell"]["size"] = {"39 um", "90 um", "90 um"};
        CHECK_THROWS_WITH_AS(read_shear_spec(s, "quick"), doctest::Contains("/cell/size"), SceneError);
        s["cell"]["size"] = {"90 um", "40 um", "90 um"};
        CHECK_THROWS_WITH_AS(read_shear_spec(s, "quick"), doctest::Contains("/cell/size"), SceneError);
        s["cell"] = {{"size", {"90 um", "90 um", "40 um"}}, {"boundaries", "lees_edwards"}};
        CHECK_THROWS_WITH_AS(read_shear_spec(s, "quick"), doctest::Contains("/cell/size"), SceneError);
    }

    // Found by fuzzing (scripts/fuzz.sh): a part whose diameter's cube overflows left the merged
    // table with no class, and the sampler's cumulative table was read past its end.
    TEST_CASE("shear scene: a mixture whose classes all weigh nothing is refused by path") {
        json s = base_scene();
        const json absurd = {{"distribution", "table"},
                             {"basis", "number"},
                             {"diameters", {"1e111 m", "2e111 m"}},
                             {"frequencies", {0.5, 0.5}}};
        s["size"] = {{"distribution", "mixture"}, {"parts", {{{"share", 100}, {"size", absurd}}}}};
        CHECK_THROWS_WITH_AS(read_shear_spec(s, "quick"), doctest::Contains("/size/parts"), SceneError);
    }

    TEST_CASE(
        "shear scene: wall speeds give rates 2 v / gap; the default ladder is the source's rates; tiers fill "
        "defaults") {
        json s = base_scene();
        s["cell"] = {{"size", {"100 um", "100 um", "100 um"}}, {"raft_thickness", "10 um"}};
        s["ladder"] = {{"wall_speeds", {"0.04 m/s", "0.02 m/s"}}};
        const ShearSpec a = read_shear_spec(s, "quick");
        REQUIRE(a.rates.size() == 2);
        CHECK(a.rates[0] == rel(2 * 0.04 / 80e-6));
        s.erase("ladder");
        s.erase("cell");
        const ShearSpec b = read_shear_spec(s, "paper");
        REQUIRE(b.rates.size() == 8);
        CHECK(b.rates[0] == rel(2 * 0.128 / 220e-6));  // 1164 1/s
        CHECK(b.rates[7] == rel(2 * 0.001 / 220e-6));
        CHECK(b.cell.x == rel(shear_tier("paper").cell_size));
        CHECK(b.strain_first == rel(shear_tier("paper").strain_first));
        CHECK(b.resolved["ladder"]["strain_first"] == b.strain_first);  // defaults are echoed
        CHECK_THROWS_AS(read_shear_spec(s, "fast"), SceneError);
    }

    // A material outside the engine's ranges is refused where it was given: a modulus of 1e-300 Pa
    // (a slip of units) at /material, and a real one scaled below the engine's floor at /scaling.
    TEST_CASE("shear scene: moduli and densities outside the ranges of solids are refused by name") {
        auto path_of_refusal = [](const json& s) {
            try {
                read_shear_spec(s, "quick");
            } catch (const SceneError& e) {
                return e.path();
            }
            return std::string("accepted");
        };
        json s = base_scene();
        CHECK(path_of_refusal(s) == "accepted");
        s["material"]["youngs_modulus"] = 1e-300;
        CHECK(path_of_refusal(s) == "/material/youngs_modulus");
        s = base_scene();
        s["material"]["density"] = 1e-300;
        CHECK(path_of_refusal(s) == "/material/density");
        s = base_scene();
        s["material"]["youngs_modulus"] = "10 kPa";
        s["scaling"] = {{"stiffness", 1e-3}};  // 10 Pa reaches the engine
        CHECK(path_of_refusal(s) == "/scaling/stiffness");
        s["scaling"] = {{"stiffness", 0.1}};
        CHECK(path_of_refusal(s) == "accepted");
    }

    // The calibration runs the magnetic model the jam predictor runs: `close_pairs` reaches the
    // engine (its table is built), and the engine's check of it is reported at the shear path.
    TEST_CASE("shear scene: magnetic/close_pairs reaches the engine and is checked there") {
        json s = base_scene();
        s["cell"] = {{"size", {"40 um", "40 um", "40 um"}}, {"raft_thickness", "8 um"}};
        s["magnetic"] = {{"close_pairs", {{"model", "linear"}, {"min_gap", 0.05}}}};
        const ShearSpec spec = read_shear_spec(s, "quick");
        Scene with = build_scene(engine_scene(spec, 0.1), BuildOptions{});
        choose_timestep(with);  // builds the pair lists and the correction's table, as the cell does
        CHECK(with.system.magnetic.settings.close_pairs.enabled);
        CHECK(with.system.magnetic.settings.close_pairs.min_gap == rel(0.05));
        CHECK_FALSE(with.system.magnetic.close_pair_table.empty());
        s["magnetic"]["close_pairs"]["min_gap"] = 2.0;  // beyond the engine's 0.005..1
        const ShearSpec bad = read_shear_spec(s, "quick");
        try {
            Scene scene = build_scene(engine_scene(bad, 0.1), BuildOptions{});
            choose_timestep(scene);
            FAIL("a min_gap of 2 radii was accepted");
        } catch (const SceneError& e) {
            CHECK(shear_path_of(e.path()) == "/magnetic/close_pairs/min_gap");
        }
        s.erase("magnetic");
        const Scene without = build_scene(engine_scene(read_shear_spec(s, "quick"), 0.1), BuildOptions{});
        CHECK_FALSE(without.system.magnetic.settings.close_pairs.enabled);
    }

    // Measured flow curves are plain numbers in SI: a unit in a cell ("41 kPa") was read as 41 Pa.
    TEST_CASE("calibration data: every field must be a plain number; a header is allowed before the points") {
        mrjam_test::TempDir dir("mrjam_calib");
        auto refusal = [&](const std::string& text) {
            mrjam_test::write_text(dir.file("d.csv"), text);
            try {
                read_calibration_data(dir.file("d.csv"));
            } catch (const SceneError& e) {
                return std::string(e.what());
            }
            return std::string("accepted");
        };
        CHECK(refusal("rate,stress\n100,41000\n200,42000,500\n") == "accepted");
        const std::string unit = refusal("rate,stress\n100,41000\n200,41 kPa\n");
        CHECK(unit.find("line 3") != std::string::npos);
        CHECK(unit.find("'kPa' is not a plain number") != std::string::npos);
        CHECK(refusal("100,41000,5,7\n200,42000\n").find("4 numbers") != std::string::npos);
        CHECK(refusal("100,41000\n200,4.1e4x\n").find("'4.1e4x'") != std::string::npos);
        mrjam_test::write_text(dir.file("d.csv"), "# rate stress\n100 41000\n200 42000\n");
        const CalibrationData d = read_calibration_data(dir.file("d.csv"));
        REQUIRE(d.points.size() == 2);
        CHECK(d.points[0].rate == 200);  // sorted by falling rate
        CHECK(d.points[0].stress == 42000);
    }

}  // TEST_SUITE
