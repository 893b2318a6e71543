#include "scene/scene_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "core/format.hpp"

namespace mrjam {

bool Bounds::contains(double v) const {
    if (!std::isfinite(v)) return false;
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
}

std::string Bounds::describe() const {
    std::ostringstream s;
    const bool lo_inf = std::isinf(lo), hi_inf = std::isinf(hi);
    if (lo_inf && hi_inf) return "a finite number";
    if (hi_inf) {
        s << (lo_open ? "> " : ">= ") << lo;
    } else if (lo_inf) {
        s << (hi_open ? "< " : "<= ") << hi;
    } else {
        s << "in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
    }
    return s.str();
}

SceneNode::SceneNode(const json& in, json& out, std::string path) : in_(&in), out_(&out), path_(std::move(path)) {
    if (!in_->is_object()) throw SceneError(path_.empty() ? "/" : path_, "expected a JSON object");
    if (!out_->is_object()) *out_ = json::object();
}

bool SceneNode::has(const std::string& key) const {
    seen_.insert(key);  // asking about a key makes it a known key of this object
    return in_->contains(key);
}

namespace {

// Levenshtein distance, for "did you mean" hints on short keys.
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// Close enough to be a misspelling: one edit for short keys, two for longer ones.
bool looks_like(const std::string& typed, const std::string& known) {
    if (typed == known) return false;
    const std::size_t limit = known.size() <= 4 ? 1 : 2;
    return edit_distance(typed, known) <= limit;
}

}  // namespace

void SceneNode::fail(const std::string& key, const std::string& message) const {
    std::string text = message;
    // A required key that is absent is most often misspelt: name the key that was given instead,
    // with its path, so the error points at the line to fix.
    if (!in_->contains(key)) {
        for (auto it = in_->begin(); it != in_->end(); ++it) {
            if (seen_.count(it.key()) || !looks_like(it.key(), key)) continue;
            text +=
                "; the scene has " + path_of(it.key()) + ", not a known key here: a misspelling of \"" + key + "\"?";
            break;
        }
    }
    throw SceneError(path_of(key), text);
}

const json& SceneNode::at(const std::string& key) {
    seen_.insert(key);
    return in_->at(key);
}

const json& SceneNode::raw(const std::string& key) {
    if (!has(key)) fail(key, "required key is missing");
    const json& v = at(key);
    record(key, v);
    return v;
}

double SceneNode::quantity(const std::string& key, const units::Dimension& dim, std::optional<double> fallback,
                           Bounds bounds) {
    double value;
    if (!has(key)) {
        if (!fallback)
            fail(key, "required key is missing (a number in SI or a string with units, " + units::spoken(dim) + ")");
        value = *fallback;
    } else {
        const json& v = at(key);
        if (v.is_number()) {
            value = v.get<double>();
        } else if (v.is_string()) {
            try {
                value = units::parse_as(v.get<std::string>(), dim);
            } catch (const units::UnitError& e) {
                fail(key, e.what());
            }
        } else {
            fail(key, "expected a number or a string with units (" + units::spoken(dim) + ")");
        }
    }
    if (!bounds.contains(value)) {
        std::ostringstream s;
        s << "value " << value << " (SI) is out of range; expected " << bounds.describe();
        fail(key, s.str());
    }
    record(key, value);
    return value;
}

double SceneNode::number(const std::string& key, std::optional<double> fallback, Bounds bounds) {
    return quantity(key, units::dimensionless, fallback, bounds);
}

long long SceneNode::integer(const std::string& key, std::optional<long long> fallback, long long lo, long long hi) {
    long long value;
    if (!has(key)) {
        if (!fallback) fail(key, "required key is missing (an integer)");
        value = *fallback;
    } else {
        const json& v = at(key);
        if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) {
            // Above a long long's range it would wrap to a negative number the user never wrote.
            fail(key, "value " + v.dump() + " is out of range; expected in [" + format_number(lo) + ", " +
                          format_number(hi) + "]");
        } else if (v.is_number_integer()) {
            value = v.get<long long>();
        } else if (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>() &&
                   std::fabs(v.get<double>()) < 9e18) {
            value = static_cast<long long>(v.get<double>());  // 1e5 is fine as a step count
        } else {
            fail(key, "expected an integer");
        }
    }
    if (value < lo || value > hi)
        fail(key, "value " + format_number(value) + " is out of range; expected in [" + format_number(lo) + ", " +
                      format_number(hi) + "]");
    record(key, value);
    return value;
}

bool SceneNode::boolean(const std::string& key, std::optional<bool> fallback) {
    bool value;
    if (!has(key)) {
        if (!fallback) fail(key, "required key is missing (true or false)");
        value = *fallback;
    } else {
        const json& v = at(key);
        if (!v.is_boolean()) fail(key, "expected true or false");
        value = v.get<bool>();
    }
    record(key, value);
    return value;
}

std::string SceneNode::text(const std::string& key, std::optional<std::string> fallback) {
    std::string value;
    if (!has(key)) {
        if (!fallback) fail(key, "required key is missing (a string)");
        value = *fallback;
    } else {
        const json& v = at(key);
        if (!v.is_string()) fail(key, "expected a string");
        value = v.get<std::string>();
    }
    record(key, value);
    return value;
}

std::string SceneNode::choice(const std::string& key, const std::vector<std::string>& options,
                              std::optional<std::string> fallback) {
    std::string list;
    for (const auto& o : options) list += (list.empty() ? "" : ", ") + ("\"" + o + "\"");
    if (!has(key) && !fallback) fail(key, "required key is missing; expected one of " + list);
    if (has(key) && !in_->at(key).is_string()) fail(key, "expected one of " + list);
    const std::string value = text(key, fallback);
    for (const auto& o : options)
        if (o == value) return value;
    fail(key, "\"" + value + "\" is not a known choice; expected one of " + list);
}

Vec3 SceneNode::vector(const std::string& key, const units::Dimension& dim, std::optional<Vec3> fallback,
                       Bounds bounds) {
    Vec3 value;
    if (!has(key)) {
        if (!fallback) fail(key, "required key is missing (three numbers or strings with units)");
        value = *fallback;
    } else {
        const json& v = at(key);
        if (!v.is_array() || v.size() != 3) fail(key, "expected an array of three components");
        json tmp_out = json::object();
        json tmp_in = {{"0", v[0]}, {"1", v[1]}, {"2", v[2]}};
        SceneNode comp(tmp_in, tmp_out, path_of(key));
        for (int k = 0; k < 3; ++k) value[k] = comp.quantity(std::to_string(k), dim, std::nullopt, bounds);
    }
    record(key, json::array({value.x, value.y, value.z}));
    return value;
}

std::vector<double> SceneNode::quantity_list(const std::string& key, const units::Dimension& dim, Bounds bounds) {
    if (!has(key)) fail(key, "required key is missing (an array)");
    const json& v = at(key);
    if (!v.is_array() || v.empty()) fail(key, "expected a non-empty array");
    std::vector<double> values;
    json tmp_out = json::object();
    for (std::size_t i = 0; i < v.size(); ++i) {
        json tmp_in = {{std::to_string(i), v[i]}};
        SceneNode item(tmp_in, tmp_out, path_of(key));
        values.push_back(item.quantity(std::to_string(i), dim, std::nullopt, bounds));
    }
    record(key, values);
    return values;
}

std::vector<bool> SceneNode::axis_flags(const std::string& key, std::optional<std::vector<bool>> fallback) {
    std::vector<bool> flags(3, false);
    if (!has(key)) {
        if (!fallback) fail(key, "required key is missing");
        flags = *fallback;
    } else {
        const json& v = at(key);
        if (v.is_string()) {
            for (char c : v.get<std::string>()) {
                if (c < 'x' || c > 'z') fail(key, "expected axis letters from \"xyz\", e.g. \"xy\"");
                if (flags[c - 'x'])
                    fail(key, std::string("names axis ") + c + " twice; give each axis once, e.g. \"xy\"");
                flags[c - 'x'] = true;
            }
        } else if (v.is_array() && v.size() == 3 && v[0].is_boolean() && v[1].is_boolean() && v[2].is_boolean()) {
            for (int k = 0; k < 3; ++k) flags[k] = v[k].get<bool>();
        } else {
            fail(key, "expected axis letters such as \"xy\" or three booleans");
        }
    }
    std::string letters;
    for (int k = 0; k < 3; ++k)
        if (flags[k]) letters += static_cast<char>('x' + k);
    record(key, letters);
    return flags;
}

SceneNode SceneNode::object(const std::string& key) {
    if (!has(key)) fail(key, "required object is missing");
    auto node = optional_object(key);
    return *node;
}

std::optional<SceneNode> SceneNode::optional_object(const std::string& key) {
    if (!has(key)) return std::nullopt;
    const json& v = at(key);
    if (!v.is_object()) fail(key, "expected a JSON object");
    if (!out_->contains(key)) (*out_)[key] = json::object();
    return SceneNode(v, (*out_)[key], path_of(key));
}

std::vector<SceneNode> SceneNode::objects(const std::string& key, bool required) {
    std::vector<SceneNode> nodes;
    if (!has(key)) {
        if (required) fail(key, "required array of objects is missing");
        return nodes;
    }
    const json& v = at(key);
    if (!v.is_array()) fail(key, "expected an array of objects");
    (*out_)[key] = json::array();
    json& arr = (*out_)[key];
    for (std::size_t i = 0; i < v.size(); ++i) arr.push_back(json::object());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_object()) throw SceneError(path_of(key) + "/" + std::to_string(i), "expected a JSON object");
        nodes.emplace_back(v[i], arr[i], path_of(key) + "/" + std::to_string(i));
    }
    return nodes;
}

void SceneNode::finish() const {
    for (auto it = in_->begin(); it != in_->end(); ++it) {
        if (seen_.count(it.key())) continue;
        std::string known, guess;
        for (const auto& k : seen_) {
            known += (known.empty() ? "" : ", ") + k;
            if (guess.empty() && looks_like(it.key(), k)) guess = k;
        }
        throw SceneError(path_of(it.key()),
                         "unknown key" + (guess.empty() ? std::string() : " (did you mean \"" + guess + "\"?)") +
                             (known.empty() ? std::string() : "; known keys here: " + known) + " (see docs/scene.md)");
    }
}

}  // namespace mrjam
