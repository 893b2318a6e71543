#include "scene/output_block.hpp"

#include <stdexcept>

#include "io/snapshot.hpp"
#include "scene/units.hpp"

namespace mrjam {

OutputBlock read_output_block(SceneNode node, const std::string& default_directory, const std::string& path_refusal) {
    for (const auto& [old_key, new_key] :
         {std::pair<const char*, const char*>{"checkpoint_every_seconds", "checkpoint/every_seconds"},
          {"checkpoint_every_steps", "checkpoint/every_steps"},
          {"snapshot_every_steps", "snapshots/every"}})
        if (node.has(old_key))
            node.fail(old_key, std::string("is now output/") + new_key +
                                   " (one output block with the same keys in every mode; docs/scene.md, \"Output\")");
    OutputBlock out;
    out.directory = node.text("directory", default_directory);
    if (out.directory.empty()) node.fail("directory", "must name a directory, e.g. \"" + default_directory + "\"");
    out.progress_interval = node.quantity("progress_interval", units::time, 5.0, Bounds::positive());
    if (auto ck = node.optional_object("checkpoint")) {
        out.checkpoint_every_steps = ck->integer("every_steps", 0, 0);
        out.checkpoint_every_seconds = ck->quantity("every_seconds", units::time, 600.0, Bounds::positive());
        if (ck->has("path") && !path_refusal.empty()) ck->fail("path", path_refusal);
        out.checkpoint_path = ck->text("path", "");
        ck->finish();
    }
    if (auto snap = node.optional_object("snapshots")) {
        out.snapshot_format = snap->text("format", "vtk");
        try {
            (void)snapshot_format_from_name(out.snapshot_format);
        } catch (const std::invalid_argument& e) {
            snap->fail("format", e.what());
        }
        out.snapshot_every = snap->integer("every", std::nullopt, 1);
        out.snapshots = true;
        snap->finish();
    }
    node.finish();
    return out;
}

OutputPlan output_plan(const OutputBlock& out) {
    OutputPlan plan;
    plan.directory = out.directory;
    plan.snapshots = out.snapshots;
    if (out.snapshots) plan.snapshot_format = snapshot_format_from_name(out.snapshot_format);
    plan.snapshot_every = out.snapshot_every;
    plan.checkpoint_every_steps = out.checkpoint_every_steps;
    plan.checkpoint_every_seconds = out.checkpoint_every_seconds;
    plan.checkpoint_path = out.checkpoint_path;
    plan.progress_interval_s = out.progress_interval;
    return plan;
}

nlohmann::json engine_output_json(const OutputBlock& out) {
    nlohmann::json checkpoint = {{"every_steps", out.checkpoint_every_steps},
                                 {"every_seconds", out.checkpoint_every_seconds}};
    if (!out.checkpoint_path.empty()) checkpoint["path"] = out.checkpoint_path;
    nlohmann::json j = {
        {"directory", out.directory}, {"progress_interval", out.progress_interval}, {"checkpoint", checkpoint}};
    if (out.snapshots) j["snapshots"] = {{"format", out.snapshot_format}, {"every", out.snapshot_every}};
    return j;
}

}  // namespace mrjam
