// One output block for every mode: the same keys read the same way, the flat keys of earlier
// versions refused with the key that replaced them, and what a mode cannot honour refused by name.
#include <doctest/doctest.h>

#include "jam/jam_scene.hpp"
#include "rel_approx.hpp"
#include "scene/output_block.hpp"
#include "shear/shear_spec.hpp"

using mrjam_test::rel;
using nlohmann::json;

namespace {

mrjam::OutputBlock read_block(const json& in, const std::string& refusal = "") {
    json resolved;
    return mrjam::read_output_block(mrjam::SceneNode(in, resolved, "/output"), "out/x", refusal);
}

// The SceneError's text for `in`, or "" if it was accepted.
std::string refusal_of(const json& in, const std::string& path_refusal = "") {
    try {
        (void)read_block(in, path_refusal);
    } catch (const mrjam::SceneError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("output block: every key read, the defaults, and the engine's block from it") {
        const mrjam::OutputBlock d = read_block(json::object());
        CHECK(d.directory == "out/x");
        CHECK(d.progress_interval == 5);
        CHECK(d.checkpoint_every_steps == 0);
        CHECK(d.checkpoint_every_seconds == 600);
        CHECK_FALSE(d.snapshots);
        const mrjam::OutputBlock o = read_block({{"directory", "here"},
                                                 {"progress_interval", "2 s"},
                                                 {"checkpoint", {{"every_steps", 500}, {"every_seconds", "1 min"}}},
                                                 {"snapshots", {{"format", "lammps"}, {"every", 100}}}});
        CHECK(o.checkpoint_every_seconds == rel(60));
        CHECK(o.snapshot_every == 100);
        const json engine = mrjam::engine_output_json(o);
        CHECK(engine["directory"] == "here");
        CHECK(engine["checkpoint"]["every_steps"] == 500);
        CHECK(engine["snapshots"]["format"] == "lammps");
        CHECK(engine["progress_interval"].get<double>() == rel(2));
    }

    TEST_CASE("output block: the old flat keys and what a mode does not honour are refused by name") {
        for (const auto& [key, now] : std::vector<std::pair<std::string, std::string>>{
                 {"checkpoint_every_seconds", "output/checkpoint/every_seconds"},
                 {"checkpoint_every_steps", "output/checkpoint/every_steps"},
                 {"snapshot_every_steps", "output/snapshots/every"}}) {
            const std::string e = refusal_of({{key, 10}});
            CAPTURE(e);
            CHECK(e.find("/output/" + key) != std::string::npos);
            CHECK(e.find("is now " + now) != std::string::npos);
        }
        CHECK(refusal_of({{"snapshots", {{"format", "png"}, {"every", 10}}}}).find("/output/snapshots/format") !=
              std::string::npos);
        CHECK(refusal_of({{"snapshots", {{"format", "vtk"}}}}).find("/output/snapshots/every") != std::string::npos);
        CHECK(refusal_of({{"directory", ""}}).find("/output/directory") != std::string::npos);
        CHECK(refusal_of({{"checkpoint", {{"path", "a.mrjam"}}}}).empty());
        CHECK(refusal_of({{"checkpoint", {{"path", "a.mrjam"}}}}, "this mode names it")
                  .find("/output/checkpoint/path: this mode names it") != std::string::npos);
    }

    TEST_CASE("output block: the shear and jam scenes read it, snapshots and step checkpoints included") {
        const json shear = {
            {"size", {{"distribution", "single"}, {"diameter", "6.7 um"}}},
            {"material", {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"}}},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "600 mT"}}},
            {"output",
             {{"directory", "o"}, {"snapshots", {{"every", 1000}}}, {"checkpoint", {{"every_steps", 20000}}}}}};
        const mrjam::ShearSpec s = mrjam::read_shear_spec(shear, "quick");
        CHECK(s.output.directory == "o");
        CHECK(s.output.snapshots);
        CHECK(s.output.checkpoint_every_steps == 20000);
        json with_path = shear;
        with_path["output"]["checkpoint"]["path"] = "x.mrjam";
        CHECK_THROWS_WITH_AS(mrjam::read_shear_spec(with_path, "quick"), doctest::Contains("/output/checkpoint/path"),
                             mrjam::SceneError);
        const json jam = {{"field", {{"type", "uniform"}, {"flux_density", "230 mT"}}},
                          {"output", {{"directory", "j"}, {"checkpoint_every_steps", 100}}}};
        CHECK_THROWS_WITH_AS(mrjam::read_jam_scene(jam, "quick", "."), doctest::Contains("checkpoint/every_steps"),
                             mrjam::SceneError);
    }
}
