#include "jam/jam_checkpoint.hpp"

#include "scene/scene_node.hpp"

namespace mrjam {

JamCheckpoint read_jam_checkpoint(const std::string& path) {
    JamCheckpoint out;
    out.header = read_checkpoint_header(path);
    const nlohmann::json& h = out.header.history;
    if (!h.is_object() || h.value("mode", "") != "jam" || !h.contains("state") || !h["state"].contains("campaign"))
        throw SceneError("--resume",
                         path + " is not a jam checkpoint (it was written by another mode); resume it with that mode");
    out.stage_log = h.at("stage_log");
    out.state = h["state"].at("protocol");
    out.campaign = h["state"]["campaign"];
    const nlohmann::json& c = out.campaign;
    if (!c.is_object() || !c.contains("scene") || !c.contains("seed_index") || !c.contains("seeds"))
        throw SceneError("--resume", path +
                                         " holds no record of its scene and seeds (written by `mrjam design` "
                                         "before its jam runs recorded them, or damaged): run the scene again");
    // A campaign checkpointed before magnetic forces could be held evaluated them every step, and
    // its remaining seeds do too (restore_state enforces it); saying so in its scene keeps the
    // report's `inputs_jam` from showing a later tier default, and new checkpoints carry it on.
    // Likewise the carrier-flow lookups, which could be held from version 6 on.
    if (out.header.version < 6) {
        nlohmann::json& scene = out.campaign.at("scene");
        if (!scene.contains("model")) scene["model"] = nlohmann::json::object();
        nlohmann::json& model = scene["model"];
        if (model.is_object()) {
            if (out.header.version < 5 && !model.contains("magnetic_update_interval"))
                model["magnetic_update_interval"] = 1;
            if (!model.contains("flow_lookup_interval")) model["flow_lookup_interval"] = 1;
        }
    }
    return out;
}

}  // namespace mrjam
