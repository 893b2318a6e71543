#pragma once
// Reading a scene (or sweep) file: the JSON, bounded in size and depth, with a key given twice in
// one object refused (a JSON parser keeps the last without a word).
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace mrjam {

// Bounds on what a scene file may make the reader allocate: its size, and its nesting (the
// duplicate-key check keeps a path per open level, so memory grows with the square of the depth).
inline constexpr std::uintmax_t kMostSceneBytes = std::uintmax_t{256} << 20;
inline constexpr std::size_t kMostSceneDepth = 64;

// Parses a JSON file; throws SceneError with the file name and the parser's position, or naming
// the JSON path of a key given twice.
nlohmann::json read_json_file(const std::string& path);

// A JSON file this program wrote itself (a state or a report): null if it is absent or was cut
// short by a kill mid-write.
nlohmann::json read_own_json_file(const std::string& path);

}  // namespace mrjam
