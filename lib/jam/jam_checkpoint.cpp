#include "jam/jam_checkpoint.hpp"

#include <fstream>
#include <optional>

#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

constexpr const char* kCampaignOnly = "mrjam jam campaign checkpoint";

// The campaign-only checkpoint, if `path` is one (a JSON object naming itself); nullopt otherwise.
std::optional<nlohmann::json> campaign_only(const std::string& path) {
    std::ifstream f(path);
    if (!f || f.peek() != '{') return std::nullopt;
    const nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
    if (j.is_discarded() || !j.is_object() || j.value("kind", "") != kCampaignOnly) return std::nullopt;
    return j.value("campaign", nlohmann::json());
}

void check_campaign(const std::string& path, const nlohmann::json& c) {
    if (!c.is_object() || !c.contains("scene") || !c.contains("seed_index") || !c.contains("seeds"))
        throw SceneError("--resume", path +
                                         " holds no record of its scene and seeds (written by `mrjam design` "
                                         "before its jam runs recorded them, or damaged): run the scene again");
}

}  // namespace

void write_campaign_checkpoint(const std::string& path, const nlohmann::json& campaign) {
    write_json_file(path, {{"kind", kCampaignOnly}, {"campaign", campaign}});
}

JamCheckpoint read_jam_checkpoint(const std::string& path) {
    JamCheckpoint out;
    if (std::optional<nlohmann::json> c = campaign_only(path)) {
        check_campaign(path, *c);
        out.campaign_only = true;
        out.campaign = std::move(*c);
        return out;
    }
    out.header = read_checkpoint_header(path);
    const nlohmann::json& h = out.header.history;
    if (!h.is_object() || h.value("mode", "") != "jam" || !h.contains("state") || !h["state"].contains("campaign"))
        throw SceneError("--resume",
                         path + " is not a jam checkpoint (it was written by another mode); resume it with that mode");
    out.stage_log = h.at("stage_log");
    out.state = h["state"].at("protocol");
    out.campaign = h["state"]["campaign"];
    check_campaign(path, out.campaign);
    return out;
}

}  // namespace mrjam
