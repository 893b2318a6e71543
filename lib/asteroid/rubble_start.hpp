#pragma once
// What the asteroid modes that simulate share before their first step: the lattice cloud built
// as an engine scene, set moving, checked to be bound and its self-gravity hold to be short
// against its free-fall time, and the tree's error measured on it.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/cloud.hpp"
#include "asteroid/coalesce_spec.hpp"
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

}  // namespace mrjam
