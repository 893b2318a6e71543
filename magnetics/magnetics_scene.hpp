#pragma once
// A `mrjam magnetics` scene: which EPM valve, in which state, solved by which model. Read with
// the engine's checked SceneNode, so unknown keys, units and ranges are refused the same way
// and every default is echoed into the report. Keys: docs/magnetics.md.
#include <nlohmann/json.hpp>
#include <string>

#include "magnetics/epm_field.hpp"

namespace mrjam::magnetics {

struct MagneticsScene {
    EpmFieldRequest request;       // model, field model, mesh; work_dir is set by the caller
    std::string tier;              // quick / standard / paper
    std::string state;             // on / off / partial
    std::string output_directory;  // where solver scratch files go
    bool keep_solver_files = false;
    nlohmann::json resolved;  // the scene with every default filled in
};

// Fidelity tiers of the magnetics mode: the field model and the element sizes they imply.
std::vector<std::string> magnetics_tier_names();
MeshSettings tier_mesh(const std::string& tier);
FieldModel tier_field_model(const std::string& tier);

// Throws SceneError (path + what was expected) for bad or impossible input.
MagneticsScene read_magnetics_scene(const nlohmann::json& scene, const std::string& tier);

// The source's FEM figure for a variant and state, if it reports one (tesla; 0 if none), and
// which region it describes ("active" or "inactive").
struct SourceFigure {
    double tesla = 0;
    std::string region;
    std::string what;
};
SourceFigure source_figure(const MagneticsScene&);

}  // namespace mrjam::magnetics
