#pragma once
// Checked reading of a scene file. Every getter names the JSON path of what it reads, checks
// type, units and range, and records the value it used (SI, defaults filled in) in a resolved
// copy so the report is a complete recipe. finish() refuses keys nobody asked for, so a typo
// never passes silently.
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/vec3.hpp"
#include "scene/units.hpp"

namespace mrjam {

using json = nlohmann::json;

// A bad scene: the message starts with the JSON path and says what was expected.
class SceneError : public std::runtime_error {
public:
    SceneError(const std::string& path, const std::string& message)
        : std::runtime_error(path + ": " + message), path_(path), message_(message) {}
    const std::string& path() const { return path_; }
    const std::string& message() const { return message_; }
    // The same error named by another path: where a generated or embedded scene's key is the
    // user's key under another name.
    SceneError at(const std::string& path) const { return SceneError(path, message_); }

private:
    std::string path_;
    std::string message_;
};

// Allowed interval for a number. Open ends exclude the bound.
struct Bounds {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;

    static Bounds any() { return {}; }
    static Bounds positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
    static Bounds non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
    static Bounds closed(double a, double b) { return {a, b, false, false}; }
    static Bounds open_closed(double a, double b) { return {a, b, true, false}; }
    static Bounds open(double a, double b) { return {a, b, true, true}; }
    bool contains(double v) const;
    std::string describe() const;
};

class SceneNode {
public:
    // in: the user's object; out: where resolved values go; path: JSON pointer of `in`.
    SceneNode(const json& in, json& out, std::string path);

    bool has(const std::string& key) const;
    const std::string& path() const { return path_; }
    std::string path_of(const std::string& key) const { return path_ + "/" + key; }

    // A quantity with units: a plain number is taken as SI, a string is parsed with units.
    double quantity(const std::string& key, const units::Dimension& dim, std::optional<double> fallback,
                    Bounds bounds = Bounds::any());
    double number(const std::string& key, std::optional<double> fallback, Bounds bounds = Bounds::any());
    long long integer(const std::string& key, std::optional<long long> fallback, long long lo = 0,
                      long long hi = std::numeric_limits<long long>::max());
    bool boolean(const std::string& key, std::optional<bool> fallback);
    std::string choice(const std::string& key, const std::vector<std::string>& options,
                       std::optional<std::string> fallback);
    std::string text(const std::string& key, std::optional<std::string> fallback);
    Vec3 vector(const std::string& key, const units::Dimension& dim, std::optional<Vec3> fallback,
                Bounds bounds = Bounds::any());
    std::vector<double> quantity_list(const std::string& key, const units::Dimension& dim,
                                      Bounds bounds = Bounds::any());
    // Three booleans, or axis letters such as "xy" for the periodic axes.
    std::vector<bool> axis_flags(const std::string& key, std::optional<std::vector<bool>> fallback);

    // Sub-objects. object() requires the key; optional_object() gives nullopt when absent.
    SceneNode object(const std::string& key);
    std::optional<SceneNode> optional_object(const std::string& key);
    std::vector<SceneNode> objects(const std::string& key, bool required = false);

    // The resolved (echoed) value of a key, for defaults that are whole objects.
    json& resolved_child(const std::string& key) {
        seen_.insert(key);
        return (*out_)[key];
    }

    // The raw value for pass-through data (e.g. a table), marked as read.
    const json& raw(const std::string& key);

    // Refuses keys that no getter asked for. Call after reading everything.
    void finish() const;

    [[noreturn]] void fail(const std::string& key, const std::string& message) const;

private:
    const json& at(const std::string& key);
    void record(const std::string& key, json value) { (*out_)[key] = std::move(value); }

    const json* in_;
    json* out_;
    std::string path_;
    mutable std::set<std::string> seen_;  // every key a getter asked about, present or not
};

}  // namespace mrjam
