#include "sweep/sweep_spec.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "scene/scene_file.hpp"
#include "scene/scene_node.hpp"
#include "scene/units.hpp"

namespace mrjam {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr std::size_t kMostRangeValues = 1000;

json::json_pointer pointer_of(const std::string& key) { return json::json_pointer("/" + key); }

// A number and the unit written after it ("150 mT" -> 150, "mT"); a bare number has no unit.
std::pair<double, std::string> number_and_unit(const json& v, const std::string& path) {
    if (v.is_number()) return {v.get<double>(), ""};
    if (!v.is_string()) throw SceneError(path, "expected a number or a quantity such as \"150 mT\"");
    const std::string text = v.get<std::string>();
    try {
        units::parse(text);  // the unit must be one scenes accept
    } catch (const std::exception& e) {
        throw SceneError(path, std::string("not a quantity: ") + e.what());
    }
    std::size_t used = 0;
    const double number = std::stod(text, &used);
    std::string unit = text.substr(used);
    unit.erase(0, unit.find_first_not_of(' '));
    return {number, unit};
}

json with_unit(double value, const std::string& unit) {
    if (unit.empty()) return value;
    char b[48];
    std::snprintf(b, sizeof b, "%.6g", value);
    return std::string(b) + " " + unit;
}

// File paths in the base scene are relative to its folder; each point's scene lives in the
// sweep's folder, so any string naming an existing file relative to the base is made absolute.
void absolutise_paths(json& node, const fs::path& base) {
    if (node.is_object() || node.is_array()) {
        for (auto& child : node) absolutise_paths(child, base);
    } else if (node.is_string()) {
        const fs::path p(node.get<std::string>());
        std::error_code ec;
        if (p.is_relative() && !p.empty() && fs::is_regular_file(base / p, ec))
            node = fs::absolute(base / p).lexically_normal().string();
    }
}

json read_base_scene(const json& file, const std::string& sweep_directory, std::string& base_directory) {
    if (!file.contains("scene")) throw SceneError("/scene", "required: the base scene, inline or a file name");
    const json& given = file.at("scene");
    if (given.is_object()) {
        base_directory = sweep_directory;
        return given;
    }
    if (!given.is_string()) throw SceneError("/scene", "expected a scene object or a file name");
    fs::path path(given.get<std::string>());
    if (path.is_relative()) path = fs::path(sweep_directory) / path;
    json scene;
    try {
        scene = read_json_file(path.string());  // the modes' reader: bounded, duplicate keys refused
    } catch (const SceneError& e) {
        throw SceneError("/scene", e.what());
    }
    if (!scene.is_object()) throw SceneError("/scene", path.string() + " does not hold a JSON object");
    base_directory = fs::absolute(path).parent_path().string();
    return scene;
}

std::vector<std::string> read_command(const json& file) {
    if (!file.contains("mode"))
        throw SceneError("/mode", "required: jam, shear, run, magnetics, design or asteroid MODE");
    if (!file.at("mode").is_string()) throw SceneError("/mode", "expected a string such as \"jam\"");
    std::vector<std::string> words;
    std::string word;
    for (char c : file.at("mode").get<std::string>() + " ") {
        if (c != ' ') {
            word += c;
        } else if (!word.empty()) {
            words.push_back(word);
            word.clear();
        }
    }
    for (const auto& known : sweepable_commands())
        if (words == known) return words;
    throw SceneError("/mode", "unknown mode \"" + file.at("mode").get<std::string>() +
                                  "\": jam, shear, run, magnetics, design, asteroid coalesce, asteroid spinup, "
                                  "asteroid avalanche or asteroid scaling");
}

std::vector<std::string> read_args(const json& file) {
    std::vector<std::string> args;
    if (!file.contains("args")) return args;
    const json& a = file.at("args");
    if (!a.is_array()) throw SceneError("/args", "expected a list of strings such as [\"--fidelity\", \"quick\"]");
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (!a[i].is_string()) throw SceneError("/args/" + std::to_string(i), "expected a string");
        const std::string s = a[i].get<std::string>();
        for (const char* owned : {"--report", "--resume", "--threads"})
            if (s == owned)
                throw SceneError(
                    "/args/" + std::to_string(i),
                    s + " is the sweep's to set (each point's report and resume; `mrjam sweep --threads`)");
        args.push_back(s);
    }
    return args;
}

SweepAxis read_axis(const json& entry, const std::string& path, const json& base) {
    if (!entry.is_object()) throw SceneError(path, "expected an object with \"key\" (or \"keys\") and its values");
    SweepAxis axis;
    if (entry.contains("key") == entry.contains("keys"))
        throw SceneError(path, "give \"key\" (one scene key) or \"keys\" (zipped keys), not both or neither");
    if (entry.contains("key")) {
        if (!entry.at("key").is_string())
            throw SceneError(path + "/key", "expected a scene key such as \"valve/constriction\"");
        axis.keys.push_back(entry.at("key").get<std::string>());
    } else {
        if (!entry.at("keys").is_array() || entry.at("keys").empty())
            throw SceneError(path + "/keys", "expected a list of scene keys");
        for (const json& k : entry.at("keys")) {
            if (!k.is_string()) throw SceneError(path + "/keys", "expected a list of scene keys");
            axis.keys.push_back(k.get<std::string>());
        }
    }
    for (std::size_t k = 0; k < axis.keys.size(); ++k) {
        const std::string& key = axis.keys[k];
        const std::string at = entry.contains("key") ? path + "/key" : path + "/keys/" + std::to_string(k);
        if (key.empty() || key.front() == '/' || key.back() == '/')
            throw SceneError(at, "a scene key is written as in the docs, e.g. \"field/flux_density\"");
        if (!base.contains(pointer_of(key)))
            throw SceneError(at, "\"" + key + "\" is not in the base scene: give it a value there, so the mode " +
                                     "checks the key and the sweep only changes it");
    }
    const bool is_range = entry.contains("from") || entry.contains("to") || entry.contains("count");
    if (is_range == entry.contains("values"))
        throw SceneError(path,
                         "give \"values\" (a list) or a range (\"from\", \"to\", \"count\"), not both or neither");
    std::vector<json> list;
    if (is_range) {
        if (axis.keys.size() != 1) throw SceneError(path, "a range sweeps one key; zipped keys take \"values\"");
        list = range_values(entry, path);
    } else {
        if (!entry.at("values").is_array()) throw SceneError(path + "/values", "expected a list");
        list = entry.at("values").get<std::vector<json>>();
    }
    if (list.empty()) throw SceneError(path + "/values", "an axis needs at least one value");
    for (std::size_t i = 0; i < list.size(); ++i) {
        if (axis.keys.size() == 1) {
            axis.values.push_back({list[i]});
            continue;
        }
        if (!list[i].is_array() || list[i].size() != axis.keys.size())
            throw SceneError(path + "/values/" + std::to_string(i),
                             "zipped keys take one value per key: a list of " + std::to_string(axis.keys.size()));
        axis.values.push_back(list[i].get<std::vector<json>>());
    }
    return axis;
}

std::vector<SweepPlot> read_plots(const json& plots, const std::vector<SweepOutput>& outputs,
                                  const std::set<std::string>& swept) {
    if (!plots.is_array()) throw SceneError("/plots", "expected a list of {\"output\", \"x\", \"lines\"}");
    std::vector<SweepPlot> out;
    for (std::size_t i = 0; i < plots.size(); ++i) {
        const std::string path = "/plots/" + std::to_string(i);
        const json& p = plots[i];
        if (!p.is_object() || !p.contains("output") || !p.contains("x") || !p.at("output").is_string() ||
            !p.at("x").is_string() || (p.contains("lines") && !p.at("lines").is_string()))
            throw SceneError(path, "expected {\"output\": NAME, \"x\": KEY, \"lines\": KEY (optional)}");
        SweepPlot plot{p.at("output").get<std::string>(), p.at("x").get<std::string>(), p.value("lines", "")};
        bool known_output = false;
        for (const SweepOutput& o : outputs) known_output = known_output || o.name == plot.output;
        if (!known_output) throw SceneError(path + "/output", "\"" + plot.output + "\" is not one of /outputs");
        if (!swept.count(plot.x)) throw SceneError(path + "/x", "\"" + plot.x + "\" is not a key of /axes");
        if (!plot.lines.empty() && (!swept.count(plot.lines) || plot.lines == plot.x))
            throw SceneError(path + "/lines", "\"" + plot.lines + "\" is not another key of /axes");
        if (plot.x == "seed" || plot.lines == "seed")
            throw SceneError(path, "the seeds are aggregated over, not plotted against");
        out.push_back(plot);
    }
    return out;
}

}  // namespace

const std::vector<std::vector<std::string>>& sweepable_commands() {
    static const std::vector<std::vector<std::string>> commands{{"jam"},
                                                                {"shear"},
                                                                {"run"},
                                                                {"magnetics"},
                                                                {"design"},
                                                                {"asteroid", "coalesce"},
                                                                {"asteroid", "spinup"},
                                                                {"asteroid", "avalanche"},
                                                                {"asteroid", "scaling"}};
    return commands;
}

std::vector<json> range_values(const json& entry, const std::string& path) {
    for (const char* k : {"from", "to", "count"})
        if (!entry.contains(k)) throw SceneError(path + "/" + k, "required in a range");
    const auto [from, unit] = number_and_unit(entry.at("from"), path + "/from");
    const auto [to, to_unit] = number_and_unit(entry.at("to"), path + "/to");
    if (unit != to_unit)
        throw SceneError(path + "/to", "written in \"" + to_unit + "\" where /from is in \"" + unit +
                                           "\": write both ends in one unit");
    const json& c = entry.at("count");
    if (!c.is_number_integer() || c.get<long>() < 1 || c.get<long>() > static_cast<long>(kMostRangeValues))
        throw SceneError(path + "/count", "expected a whole number from 1 to " + std::to_string(kMostRangeValues));
    const std::string spacing = entry.value("spacing", std::string("linear"));
    if (spacing != "linear" && spacing != "log") throw SceneError(path + "/spacing", "linear or log");
    if (spacing == "log" && (from <= 0 || to <= 0))
        throw SceneError(path + "/spacing", "a logarithmic range needs both ends above zero");
    const long n = c.get<long>();
    std::vector<json> values;
    for (long i = 0; i < n; ++i) {
        const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
        const double v = spacing == "log" ? from * std::pow(to / from, t) : from + (to - from) * t;
        values.push_back(with_unit(v, unit));
    }
    return values;
}

SweepSpec read_sweep(const json& file, const std::string& sweep_directory) {
    if (!file.is_object()) throw SceneError("/", "a sweep file is a JSON object (docs/sweep.md)");
    static const std::set<std::string> known{"description", "mode", "args", "scene", "axes", "outputs", "plots"};
    for (const auto& [key, value] : file.items())
        if (!known.count(key))
            throw SceneError("/" + key, "unknown key (known: description, mode, args, scene, axes, outputs, plots)");
    SweepSpec spec;
    spec.source = file;
    spec.command = read_command(file);
    spec.args = read_args(file);
    spec.base_scene = read_base_scene(file, sweep_directory, spec.base_directory);
    absolutise_paths(spec.base_scene, spec.base_directory);
    if (!file.contains("axes") || !file.at("axes").is_array() || file.at("axes").empty())
        throw SceneError("/axes", "required: a list of at least one axis");
    std::set<std::string> swept;
    for (std::size_t a = 0; a < file.at("axes").size(); ++a) {
        const std::string path = "/axes/" + std::to_string(a);
        spec.axes.push_back(read_axis(file.at("axes")[a], path, spec.base_scene));
        for (const std::string& key : spec.axes.back().keys)
            if (!swept.insert(key).second) throw SceneError(path, "\"" + key + "\" is swept by another axis already");
    }
    if (file.contains("outputs")) {
        if (!file.at("outputs").is_object())
            throw SceneError("/outputs", "expected {\"column name\": \"report/path\", ...}");
        for (const auto& [name, path] : file.at("outputs").items()) {
            if (!path.is_string() || path.get<std::string>().empty())
                throw SceneError("/outputs/" + name, "expected a report path such as \"results/jammed\"");
            spec.outputs.push_back({name, path.get<std::string>()});
        }
    }
    if (file.contains("plots")) spec.plots = read_plots(file.at("plots"), spec.outputs, swept);
    return spec;
}

std::vector<SweepPoint> sweep_points(const SweepSpec& spec) {
    std::size_t total = 1;
    for (const SweepAxis& a : spec.axes) total *= a.values.size();
    std::vector<SweepPoint> points(total);
    for (std::size_t p = 0; p < total; ++p) {
        points[p].index = p;
        points[p].values = json::object();
        std::size_t rest = p;
        for (std::size_t a = spec.axes.size(); a-- > 0;) {
            const SweepAxis& axis = spec.axes[a];
            const std::size_t i = rest % axis.values.size();
            rest /= axis.values.size();
            for (std::size_t k = 0; k < axis.keys.size(); ++k) points[p].values[axis.keys[k]] = axis.values[i][k];
        }
    }
    return points;
}

json point_scene(const SweepSpec& spec, const SweepPoint& point, const std::string& output_directory) {
    json scene = spec.base_scene;
    for (const auto& [key, value] : point.values.items()) scene[pointer_of(key)] = value;
    // The design names its folder at the top level; every other mode under output/.
    if (spec.command.front() == "design")
        scene["output_directory"] = output_directory;
    else
        scene["output"]["directory"] = output_directory;
    return scene;
}

}  // namespace mrjam
