#include "asteroid/asteroid_outcome.hpp"

#include <filesystem>

#include "scene/scene_node.hpp"

namespace mrjam {

nlohmann::json asteroid_report(const RunOutcome& outcome, const char* mode, const nlohmann::json& inputs,
                               const std::string& fidelity) {
    nlohmann::json r = outcome.report;
    r["mode"] = mode;
    r["engine_inputs"] = r["inputs"];
    r["inputs"] = inputs;
    r["fidelity"] = fidelity;
    return r;
}

std::string plot_beside(const std::string& report_path, const char* suffix) {
    const std::filesystem::path p(report_path);
    return (p.parent_path() / (p.stem().string() + "_" + suffix + ".svg")).string();
}

CheckpointHeader read_mode_checkpoint(const std::string& path, const char* mode) {
    CheckpointHeader header = read_checkpoint_header(path);
    if (!header.history.is_object() || header.history.value("mode", "") != mode)
        throw SceneError("--resume", path + " was not written by `mrjam " + mode + "`");
    return header;
}

}  // namespace mrjam
