#include "asteroid/asteroid_outcome.hpp"

#include <filesystem>
#include <iostream>

#include "asteroid/body_spin.hpp"
#include "io/grain_views.hpp"
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

std::string plot_beside(const std::string& report_path, const std::string& suffix) {
    const std::filesystem::path p(report_path);
    return (p.parent_path() / (p.stem().string() + "_" + suffix + ".svg")).string();
}

std::string body_views_beside(const std::string& report_path, const std::string& suffix, const System& s,
                              const std::string& title) {
    GrainViews views;
    views.title = title;
    double mass = 0;
    for (std::size_t i : heaviest_cluster(s).grains) {
        views.position.push_back(s.particles.position[i]);
        views.radius.push_back(s.particles.radius[i]);
        views.centre += s.particles.mass[i] * s.particles.position[i];
        mass += s.particles.mass[i];
    }
    if (mass > 0) views.centre = views.centre / mass;
    const std::string path = plot_beside(report_path, suffix);
    try {
        write_grain_views(path, views);
        return path;
    } catch (const std::exception& e) {
        std::cerr << "[asteroid] warning: the body's picture was not written: " << e.what() << "\n";
        return {};
    }
}

CheckpointHeader read_mode_checkpoint(const std::string& path, const char* mode) {
    CheckpointHeader header = read_checkpoint_header(path);
    if (!header.history.is_object() || header.history.value("mode", "") != mode)
        throw SceneError("--resume", path + " was not written by `mrjam " + mode + "`");
    return header;
}

}  // namespace mrjam
