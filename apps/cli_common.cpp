#include "cli_common.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/scene_node.hpp"

namespace mrjam::cli {

nlohmann::json read_json_file(const std::string& path) {
    if (std::filesystem::is_directory(path)) throw SceneError(path, "is a directory: give the scene's JSON file");
    std::ifstream in(path);
    if (!in) throw SceneError(path, "cannot open the scene file (check the path)");
    std::stringstream buffer;
    buffer << in.rdbuf();
    try {
        return nlohmann::json::parse(buffer.str());
    } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number out of range (1e999)
        throw SceneError(path, std::string("not valid JSON: ") + e.what());
    }
}

void prepare_output_file(const std::string& path, const std::string& option) {
    namespace fs = std::filesystem;
    if (path.empty()) throw SceneError(option, "is empty: give a file name such as report.json");
    const fs::path p(path);
    if (!p.has_filename() || fs::is_directory(p))
        throw SceneError(option, path + " is a directory: give a file name such as " + (p / "report.json").string());
    const fs::path dir = p.parent_path();
    if (dir.empty()) return;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw SceneError(option, "cannot create the directory " + dir.string() + " for " + path +
                                     (ec ? " (" + ec.message() + ")" : std::string()) + ": choose another path");
}

}  // namespace mrjam::cli
