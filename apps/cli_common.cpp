#include "cli_common.hpp"

#include <fstream>
#include <sstream>

#include "scene/scene_node.hpp"

namespace mrjam::cli {

nlohmann::json read_json_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw SceneError(path, "cannot open the scene file (check the path)");
    std::stringstream buffer;
    buffer << in.rdbuf();
    try {
        return nlohmann::json::parse(buffer.str());
    } catch (const nlohmann::json::parse_error& e) {
        throw SceneError(path, std::string("not valid JSON: ") + e.what());
    }
}

}  // namespace mrjam::cli
