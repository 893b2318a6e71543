#pragma once
// What the asteroid modes that simulate share before their first step: the lattice cloud built
// as an engine scene, set moving, checked to be bound and its self-gravity hold to be short
// against its free-fall time, and the tree's error measured on it.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/cloud.hpp"
#include "asteroid/coalesce_spec.hpp"
#include "asteroid/rubble_ledger.hpp"
#include "io/checkpoint.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"

namespace mrjam {

struct RubbleStart {
    std::unique_ptr<Scene> scene;
    CloudEnergetics energetics;
    nlohmann::json cloud;             // the report's `cloud` block (energetics, escape radius, seed grain)
    nlohmann::json gravity_accuracy;  // the tree against direct summation on the initial cloud
    double escape_radius = 0;         // m
};

// Throws SceneError naming the key for an unbound cloud (unless allowed) or a long hold.
RubbleStart start_rubble(const CoalesceSpec& spec, int threads, const std::string& fidelity, const char* mode);

// The engine scene a checkpoint carries, rebuilt without grains and filled from the checkpoint.
std::unique_ptr<Scene> restore_rubble(const std::string& checkpoint, const nlohmann::json& resolved_scene, int threads);

// What a cloud mode (coalesce, spinup) carries from its start, through its checkpoints, to its
// report: the engine scene, where the protocol stands, the cloud's and the tree's figures, the
// body's samples and the books of what escaped.
struct RubbleRun {
    std::unique_ptr<Scene> scene;
    ProtocolPosition start;
    nlohmann::json stage_log;
    nlohmann::json cloud, gravity_accuracy;
    nlohmann::json samples = nlohmann::json::array();
    RubbleLedger ledger;
    double next_sample = 0;  // s, the next body sample

    // A fresh run: start_rubble, and the ledger opened on the cloud.
    void begin(const CoalesceSpec& spec, int threads, const std::string& fidelity, const char* mode);
    // From a checkpoint the mode wrote, with `state` its history's state (as save() wrote it).
    void restore(const std::string& checkpoint, const nlohmann::json& state, const CheckpointHeader& header,
                 int threads);
    nlohmann::json save() const;  // the keys restore() reads

    // The run loop's options every cloud mode sets: its name, progress, where a resumed run stands,
    // the grains past the escape sphere taken out (the mode adds its checkpoint state).
    RunOptions run_options(const char* mode, const std::string& scene_path, bool progress);

    // The report's envelope (asteroid_report) with the cloud's and the tree's figures.
    nlohmann::json report(const RunOutcome& outcome, const char* mode, const nlohmann::json& inputs,
                          const std::string& fidelity) const;
    // The body as the run left it, drawn beside the report as `plots.final_body`.
    void draw_final_body(nlohmann::json& report, const std::string& report_path) const;
};

}  // namespace mrjam
