// `mrjam asteroid avalanche` (lib/asteroid/heap_profile, avalanche_spec): the angle of repose of a
// surface built on known slopes, a bent slope's two halves, the heap's volume and run-out; and the
// scene's refusals (no field given, a cell too narrow for the dipoles, a gate outside the cell).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "asteroid/avalanche_spec.hpp"
#include "asteroid/heap_profile.hpp"
#include "particles.hpp"
#include "rel_approx.hpp"
#include "scene/scene_node.hpp"

using namespace mrjam;
using json = nlohmann::json;
using mrjam_test::rel;

namespace {

// A surface of grains (radius r) whose tops follow z(x) from x = 0 to x_end, one grain per r.
Particles surface_grains(double r, double x_end, double (*z)(double)) {
    Particles p;
    std::size_t n = 0;
    for (double x = 0.5 * r; x < x_end; x += r) ++n;
    p.resize(n);
    std::size_t i = 0;
    for (double x = 0.5 * r; x < x_end; x += r, ++i) {
        p.position[i] = {x, 0.0, z(x) - r};
        p.radius[i] = r;
        p.mass[i] = 1;
    }
    return p;
}

json avalanche_scene() {
    return {{"grains", {{"diameter", "5 mm"}, {"material", {{"density", "7750 kg/m3"}, {"youngs_modulus", "10 MPa"}}}}},
            {"gravity", "0.144 m/s2"},
            {"field", "5 mT"},
            {"protocol", {{"settle_time", "1 s"}, {"magnetise_time", "0.5 s"}, {"runout_time", "4 s"}}}};
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("heap profile: a plateau and a 35 degree slope give 35 degrees, the volume under it and the toe") {
        // z = 0.5 m to x = 0.4 m, then down at 35 degrees to the floor.
        static const double tan35 = std::tan(35.0 * M_PI / 180.0);
        const auto z = [](double x) { return x < 0.4 ? 0.5 : std::max(0.0, 0.5 - (x - 0.4) * tan35); };
        const double toe = 0.4 + 0.5 / tan35;
        const Particles p = surface_grains(0.002, toe, z);
        const HeapProfile h = measure_heap(p, 2.0, 0.1, 0.3, 0.01);
        REQUIRE(h.slope.points >= 3);
        // Bins of 1 cm on a surface sampled every 2 mm: the highest top per bin sits up to a bin's
        // drop above the line, the same at every bin, so the fit's angle is within 0.2 degrees.
        CHECK(std::fabs(h.slope.angle_deg - 35.0) < 0.2);
        CHECK(std::fabs(h.upper.angle_deg - 35.0) < 0.5);
        CHECK(std::fabs(h.lower.angle_deg - 35.0) < 0.5);
        CHECK(h.peak == rel(0.5).epsilon(1e-9));
        // The chords (the reported angles) on the same face: the plateau behind the gate is 0.5 m,
        // and every crossing sits the same part of a bin's drop off the line.
        CHECK(h.plateau == rel(0.5).epsilon(1e-9));
        REQUIRE(h.face.found);
        CHECK(std::fabs(h.face.angle_deg - 35.0) < 0.2);
        CHECK(std::fabs(h.face_upper.angle_deg - 35.0) < 0.5);
        CHECK(std::fabs(h.face_lower.angle_deg - 35.0) < 0.5);
        CHECK(h.face.x_low == rel(0.4 + 0.45 / tan35).epsilon(0.02));
        // Volume: 0.4 x 0.5 plus the triangle 0.5 x 0.5 / tan35 / 2, times the width 0.1, within a bin.
        CHECK(h.volume == rel(0.1 * (0.2 + 0.125 / tan35)).epsilon(0.02));
        CHECK(h.runout == rel(toe - 0.3).epsilon(0.01));
    }

    TEST_CASE("heap profile: a chain standing on the plateau or lying ahead of it does not move the fit") {
        static const double tan35 = std::tan(35.0 * M_PI / 180.0);
        const auto z = [](double x) { return x < 0.4 ? 0.5 : std::max(0.0, 0.5 - (x - 0.4) * tan35); };
        Particles p = surface_grains(0.002, 0.4 + 0.5 / tan35, z);
        const std::size_t n = p.size();
        p.resize(n + 2);
        p.position[n] = {0.105, 0.0, 0.7};    // an upright chain's top, 0.2 m above the plateau
        p.position[n + 1] = {1.3, 0.0, 0.3};  // a chain ahead of the toe
        for (std::size_t i = n; i < n + 2; ++i) {
            p.radius[i] = 0.002;
            p.mass[i] = 1;
        }
        const HeapProfile h = measure_heap(p, 2.0, 0.1, 0.3, 0.01);
        CHECK(h.peak == rel(0.5).epsilon(1e-9));
        CHECK(std::fabs(h.slope.angle_deg - 35.0) < 0.2);
        // The bins' raw tops keep both.
        CHECK(*std::max_element(h.top.begin(), h.top.end()) == rel(0.702).epsilon(1e-9));
    }

    TEST_CASE("heap profile: a slope steep on top and shallow below is fitted as two halves") {
        // 50 degrees down to half the peak, then 30 degrees: the source's 5 mm heap in a field.
        static const double t50 = std::tan(50.0 * M_PI / 180.0), t30 = std::tan(30.0 * M_PI / 180.0);
        const auto z = [](double x) {
            const double bend = 0.2 + 0.25 / t50;
            if (x < 0.2) return 0.5;
            if (x < bend) return 0.5 - (x - 0.2) * t50;
            return std::max(0.0, 0.25 - (x - bend) * t30);
        };
        const Particles p = surface_grains(0.001, 2.0, z);
        const HeapProfile h = measure_heap(p, 2.0, 0.1, 0.1, 0.005);
        CHECK(std::fabs(h.upper.angle_deg - 50.0) < 1.0);
        CHECK(std::fabs(h.lower.angle_deg - 30.0) < 1.0);
        CHECK(h.slope.angle_deg > 30.0);  // one line through both lies between them
        CHECK(h.slope.angle_deg < 50.0);
        // The chords: 90-50 % of the plateau on the 50 degree part, 50-10 % on the 30 degree part.
        CHECK(std::fabs(h.face_upper.angle_deg - 50.0) < 1.0);
        CHECK(std::fabs(h.face_lower.angle_deg - 30.0) < 1.0);
        CHECK(h.face.angle_deg > 30.0);
        CHECK(h.face.angle_deg < 50.0);
    }

    TEST_CASE(
        "heap profile: a heap that ends in a cliff reads steep; the fits, which see no bin on the face, have none") {
        // A magnetised column that hardly ran out: 0.5 m high to x = 0.4 m, then a vertical face.
        const auto z = [](double x) { return x < 0.4 ? 0.5 : 0.0; };
        const Particles p = surface_grains(0.002, 0.4, z);
        const HeapProfile h = measure_heap(p, 2.0, 0.1, 0.3, 0.01);
        REQUIRE(h.face.found);
        // Both crossings fall between the last full bin and the first empty one, 1 cm apart:
        // 0.4 m of drop over 0.8 cm.
        CHECK(h.face.angle_deg > 85.0);
        CHECK(h.face.x_high == rel(0.396).epsilon(0.01));
        CHECK(h.face.x_low == rel(0.404).epsilon(0.01));
        CHECK(h.slope.points < 3);
    }

    TEST_CASE("avalanche scene: the field is required, the cell must hold the dipoles' reach, the gate the cell") {
        CHECK(read_avalanche_spec(avalanche_scene(), "quick").width == 8);
        json s = avalanche_scene();
        s.erase("field");
        CHECK_THROWS_WITH_AS(read_avalanche_spec(s, "quick"), doctest::Contains("/field"), SceneError);
        s = avalanche_scene();
        s["cell"] = {{"width", 4}};
        CHECK_THROWS_WITH_AS(read_avalanche_spec(s, "quick"), doctest::Contains("/cell/width"), SceneError);
        s["field"] = "0 T";  // no dipoles: a thin slice is allowed
        CHECK(read_avalanche_spec(s, "quick").width == 4);
        s = avalanche_scene();
        s["cell"] = {{"length", 50}, {"gate", 60}};
        CHECK_THROWS_WITH_AS(read_avalanche_spec(s, "quick"), doctest::Contains("/cell/gate"), SceneError);
    }

    TEST_CASE("avalanche scene: EPSD rolling resistance by default, the SDS keys refused with it") {
        json s = avalanche_scene();
        s["grains"]["material"].update({{"rolling_friction", 0.4}, {"rolling_damping", 0.4}});
        const AvalancheSpec epsd = read_avalanche_spec(s, "quick");
        CHECK(epsd.material.rolling_model == "epsd");
        CHECK(epsd.material.engine_rolling() == "epsd");
        CHECK(epsd.material.rolling_damping == 0.4);
        s["grains"]["material"]["rolling_stiffness"] = "10 N/m";
        CHECK_THROWS_WITH_AS(read_avalanche_spec(s, "quick"), doctest::Contains("/grains/material/rolling_stiffness"),
                             SceneError);
        // Asked for by name, SDS takes its own keys and refuses EPSD's damping ratio as unknown.
        s["grains"]["material"]["rolling_model"] = "sds";
        s["grains"]["material"].erase("rolling_damping");
        const AvalancheSpec sds = read_avalanche_spec(s, "quick");
        CHECK(sds.material.engine_rolling() == "sds");
        CHECK(sds.material.rolling_stiffness == 10.0);
        s["grains"]["material"]["rolling_damping"] = 0.4;
        CHECK_THROWS_WITH_AS(read_avalanche_spec(s, "quick"), doctest::Contains("rolling_damping"), SceneError);
        // Without rolling friction there is no rolling resistance, whichever the model.
        json none = avalanche_scene();
        CHECK(read_avalanche_spec(none, "quick").material.engine_rolling() == "none");
    }
}

#include "run/runner.hpp"
#include "scene/scene.hpp"

TEST_SUITE("unit") {
    TEST_CASE("stages: remove_walls takes a named plane out of reach as its stage starts; other walls refused") {
        const json gate = {{"name", "gate"}, {"type", "plane"}, {"point", {0.05, 0, 0}}, {"normal", {-1, 0, 0}}};
        const json pipe = {
            {"name", "pipe"}, {"type", "cylinder"}, {"point", {0.05, 0.05, 0}}, {"axis", {0, 0, 1}}, {"radius", 0.05}};
        const json grain = {{"size", {{"distribution", "single"}, {"diameter", 0.004}}},
                            {"placement", {{"method", "list"}, {"positions", {{0.02, 0.05, 0.05}}}}}};
        json scene = {{"domain", {{"lo", {0, 0, 0}}, {"hi", {0.1, 0.1, 0.1}}}},
                      {"materials", json::array({{{"name", "g"}, {"density", 2500}, {"youngs_modulus", 1e7}}})},
                      {"walls", json::array({gate, pipe})},
                      {"grains", json::array({grain})},
                      {"run", {{"timestep", 1e-6}}},
                      {"output", {{"directory", "."}, {"progress_interval", 1e9}}}};
        scene["stages"] = json::array(
            {{{"name", "held"}, {"steps", 2}}, {{"name", "lifted"}, {"steps", 2}, {"remove_walls", {"gate"}}}});
        BuildOptions build;
        Scene s = build_scene(scene, build);
        choose_timestep(s);
        REQUIRE(s.stages[1].remove_walls == std::vector<std::string>{"gate"});
        RunOptions o;
        o.progress = false;
        run_protocol(s, o);
        // Behind itself (along -normal, +x here), farther than ten box diagonals.
        CHECK(s.system.walls[0].point.x > 10 * std::sqrt(0.03));
        CHECK(s.system.walls[1].point.x == 0.05);
        json bad = scene;
        bad["stages"][1]["remove_walls"] = {"pipe"};
        CHECK_THROWS_WITH_AS(build_scene(bad, build), doctest::Contains("remove_walls"), SceneError);
        bad["stages"][1]["remove_walls"] = {"door"};
        CHECK_THROWS_WITH_AS(build_scene(bad, build), doctest::Contains("/stages/1/remove_walls"), SceneError);
    }
}
