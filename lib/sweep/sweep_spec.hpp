#pragma once
// A sweep file (docs/sweep.md): a base scene of one mode, the axes whose values it is run at, and
// the report values to tabulate. Read and checked here; each point's scene is the base scene with
// that point's values written at the axes' keys.
//
//   {"mode": "jam", "args": ["--fidelity", "quick"],
//    "scene": "examples/table32/mix2_20x.json" | {...inline scene...},
//    "axes": [{"key": "valve/constriction", "values": ["20x", "30x", "40x"]},
//             {"key": "field/scale", "from": 0.5, "to": 2, "count": 4, "spacing": "log"},
//             {"keys": ["grains/volume_fraction", "fluid/viscosity"], "values": [[0.3, "0.1 Pa s"], ...]},
//             {"key": "seed", "values": [1, 2, 3]}],
//    "outputs": {"outcome": "results/outcome", "jammed": "results/jammed"},
//    "plots": [{"output": "jammed", "x": "field/scale", "lines": "valve/constriction"}]}
//
// Axes combine as a product, the last varying fastest; the keys of one axis entry are zipped.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mrjam {

struct SweepAxis {
    std::vector<std::string> keys;                    // scene keys ("valve/constriction"), zipped
    std::vector<std::vector<nlohmann::json>> values;  // values[i][k]: the i-th value of keys[k]
};

struct SweepOutput {
    std::string name;                // the table's column
    std::string path;                // where in the mode's report ("results/jammed")
    std::string interval_path = "";  // a [low, high] interval of it in the report (bars in the plots), if any
};

// A picture of one output against one swept key, a line per value of another (or one line).
struct SweepPlot {
    std::string output, x, lines;                        // lines may be empty
    std::string title = "", x_label = "", y_label = "";  // "": from the output's and the keys' names
};

struct SweepSpec {
    std::vector<std::string> command;  // the mode's words after `mrjam` ("jam"; "asteroid", "spinup")
    std::vector<std::string> args;     // passed to every point's run ("--fidelity", "quick")
    nlohmann::json base_scene;         // with relative file paths made absolute
    std::string base_directory;        // the base scene's (or the sweep file's) folder
    std::vector<SweepAxis> axes;
    std::vector<SweepOutput> outputs;
    std::vector<SweepPlot> plots;
    nlohmann::json source;  // the sweep file as given: a rerun into the same folder must match it
};

// A point of the sweep: its index in the product and its value at every key.
struct SweepPoint {
    std::size_t index = 0;
    nlohmann::json values;  // {"valve/constriction": "20x", "seed": 1, ...}
};

// The modes a sweep can run, as their words after `mrjam`.
const std::vector<std::vector<std::string>>& sweepable_commands();

// Reads and checks a sweep file; throws SceneError naming the JSON path of what is wrong.
SweepSpec read_sweep(const nlohmann::json& file, const std::string& sweep_directory);

// Every point, in order (the product of the axes, the last fastest).
std::vector<SweepPoint> sweep_points(const SweepSpec& spec);

// The base scene with the point's values at their keys, its output directory set to `output_directory`.
nlohmann::json point_scene(const SweepSpec& spec, const SweepPoint& point, const std::string& output_directory);

// The values of a range axis entry {"from", "to", "count", "spacing"}: numbers, or "<number> <unit>"
// strings in the unit both ends are written in. Throws SceneError under `path`.
std::vector<nlohmann::json> range_values(const nlohmann::json& entry, const std::string& path);

}  // namespace mrjam
