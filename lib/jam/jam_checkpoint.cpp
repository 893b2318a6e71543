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
    return out;
}

}  // namespace mrjam
