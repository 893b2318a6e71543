#include "scene/scene_file.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "scene/scene_node.hpp"

namespace mrjam {

nlohmann::json read_own_json_file(const std::string& path) {
    std::ifstream in(path);
    if (!in) return nullptr;
    try {
        return nlohmann::json::parse(in);
    } catch (const nlohmann::json::parse_error&) {
        return nullptr;
    }
}

nlohmann::json read_json_file(const std::string& path) {
    if (std::filesystem::is_directory(path)) throw SceneError(path, "is a directory: give the scene's JSON file");
    std::ifstream in(path);
    if (!in) throw SceneError(path, "cannot open the scene file (check the path)");
    // Sizes the input controls are bounded before anything is allocated for them: the parsed
    // document takes about ten times its text.
    std::error_code size_error;
    const auto bytes = std::filesystem::file_size(path, size_error);
    if (!size_error && bytes > kMostSceneBytes)
        throw SceneError(path, "is " + std::to_string(bytes >> 20) + " MB; a scene file may be at most " +
                                   std::to_string(kMostSceneBytes >> 20) +
                                   " MB (give long grain lists as a LAMMPS data file)");
    std::stringstream buffer;
    buffer << in.rdbuf();
    // A key given twice in one object: the parser would keep the last without a word, so the
    // scene would not run what its reader sees first. One frame per open object or array.
    struct Frame {
        bool array;
        std::string path;
        std::size_t index = 0;       // arrays: the element being read
        std::set<std::string> keys;  // objects: the keys seen
    };
    std::vector<Frame> open;
    std::string last_key, duplicate;
    const auto watch = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using E = nlohmann::json::parse_event_t;
        auto child_path = [&] {
            if (open.empty()) return std::string();
            return open.back().path + "/" + (open.back().array ? std::to_string(open.back().index) : last_key);
        };
        auto element_done = [&] {
            if (!open.empty() && open.back().array) ++open.back().index;
        };
        if ((event == E::object_start || event == E::array_start) && open.size() >= kMostSceneDepth)
            throw SceneError(child_path(), "is nested deeper than " + std::to_string(kMostSceneDepth) +
                                               " levels: no scene needs that; check the file (" + path + ")");
        switch (event) {
            case E::object_start:
                open.push_back({false, child_path(), 0, {}});
                break;
            case E::array_start:
                open.push_back({true, child_path(), 0, {}});
                break;
            case E::object_end:
            case E::array_end:
                open.pop_back();
                element_done();
                break;
            case E::key:
                last_key = parsed.get<std::string>();
                if (!open.back().keys.insert(last_key).second && duplicate.empty())
                    duplicate = open.back().path + "/" + last_key;
                break;
            case E::value:
                element_done();
                break;
        }
        return true;
    };
    nlohmann::json parsed;
    try {
        parsed = nlohmann::json::parse(buffer.str(), watch);
    } catch (const nlohmann::json::exception& e) {  // a syntax error, or a number out of range (1e999)
        throw SceneError(path, std::string("not valid JSON: ") + e.what());
    }
    if (!duplicate.empty()) throw SceneError(duplicate, "is given twice in the same object (" + path + "); keep one");
    return parsed;
}

}  // namespace mrjam
