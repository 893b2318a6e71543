#include "jam/jam_checkpoint.hpp"

#include <stdexcept>

#include "scene/scene_node.hpp"

namespace mrjam {

JamCheckpoint read_jam_checkpoint(const std::string& path) {
    JamCheckpoint out;
    try {
        out.header = read_checkpoint_header(path);
    } catch (const std::runtime_error& e) {
        throw SceneError("--resume", e.what());
    }
    const nlohmann::json& h = out.header.history;
    if (!h.is_object() || h.value("mode", "") != "jam" || !h.contains("state") || !h["state"].contains("campaign"))
        throw SceneError("--resume",
                         path + " is not a jam checkpoint (it was written by another mode); resume it with that mode");
    out.stage_log = h.at("stage_log");
    out.state = h["state"].at("protocol");
    out.campaign = h["state"]["campaign"];
    return out;
}

}  // namespace mrjam
