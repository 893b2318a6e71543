#include "shear/field_sweep.hpp"

#include <cstdio>
#include <filesystem>

#include "core/exit_status.hpp"
#include "scene/scene_file.hpp"
#include "sweep/sweep_run.hpp"
#include "sweep/sweep_table.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kFieldKey = "field/flux_density";

fs::path sweep_directory(const ShearSpec& spec) { return fs::path(spec.output.directory) / "field_sweep"; }

// The pre-shear at the main ladder's first rate (when faster than the sweep's), then the sweep's rate.
json point_ladder(const ShearSpec& s) {
    std::vector<double> rates;
    if (s.rates.front() > s.sweep_rate) rates.push_back(s.rates.front());
    rates.push_back(s.sweep_rate);
    json ladder = {{"shear_rates", rates}};
    if (s.steps_first > 0) {  // fixed step counts, as the main ladder's
        ladder["steps_first"] = s.steps_first;
        ladder["steps_per_rate"] = s.steps_per_rate;
    } else {
        ladder["strain_first"] = rates.size() == 2 ? s.strain_first : s.sweep_strain;
        ladder["strain_per_rate"] = s.sweep_strain;
    }
    return ladder;
}

SweepSpec field_sweep_spec(const ShearSpec& spec) {
    SweepSpec s;
    s.command = {"shear"};
    s.args = {"--fidelity", spec.tier};
    s.base_scene = field_point_scene(spec);
    s.base_directory = spec.output.directory;
    SweepAxis axis;
    axis.keys = {kFieldKey};
    for (double b : spec.sweep_fields) axis.values.push_back({b});
    s.axes = {axis};
    const std::string last = std::to_string(point_ladder(spec)["shear_rates"].size() - 1);
    s.outputs = {{"stress_Pa", "results/flow_curve/" + last + "/stress_Pa"},
                 {"error_Pa", "results/flow_curve/" + last + "/error_Pa"}};
    s.source = {{"shear_input", spec.input}, {"tier", spec.tier}};
    return s;
}

std::string folder_of(std::size_t, const json& values) {
    char name[32];
    std::snprintf(name, sizeof name, "%gmT", values.at(kFieldKey).get<double>() * 1e3);
    return name;
}

}  // namespace

json field_point_scene(const ShearSpec& spec) {
    json scene = spec.input;
    scene.erase("field_sweep");
    scene["ladder"] = point_ladder(spec);
    return scene;
}

FieldSweepOutcome run_field_sweep(const ShearSpec& spec, const ShearOptions& options, bool resumed) {
    const fs::path dir = sweep_directory(spec);
    if (!resumed) fs::remove_all(dir);  // an earlier study's fields are not this one's
    SweepOptions o;
    o.out_dir = dir.string();
    o.threads = options.threads;
    o.progress = options.progress;
    o.yes = true;  // the list is the scene's own
    SweepEngine engine;
    engine.label = options.label + " field sweep";
    engine.folder_name = folder_of;
    engine.spread_over_ranks = false;
    engine.echo_output = options.progress;
    FieldSweepOutcome out;
    out.exit_status = run_sweep_spec(field_sweep_spec(spec), o, engine);
    const json table = read_own_json_file((dir / "table.json").string());
    if (!table.is_object() || !table.contains("rows")) return out;
    for (const json& row : table["rows"]) {
        const fs::path folder = dir / row["point"].get<std::string>();
        const json report = read_own_json_file((folder / "report.json").string());
        const json curve = report_value(report, "results/flow_curve");
        if (row["state"] == "done" && curve.is_array() && !curve.empty()) {
            const json& q = curve.back();  // the first, if two, is the pre-shear
            out.rows.push_back({{"flux_density_T", row["values"][kFieldKey]},
                                {"rate_1_s", q["rate_1_s"]},
                                {"stress_Pa", q["stress_Pa"]},
                                {"error_Pa", q["error_Pa"]},
                                {"strain", q["strain"]}});
        } else if (row["state"] == "failed" && out.error.empty()) {
            const json state = read_point_state(folder);
            out.error = "the field sweep's " + row["values"][kFieldKey].dump() + " T study failed (" +
                        state.value("error", std::string("see its log")) + "; " + (folder / "log.txt").string() + ")";
            if (out.exit_status != kExitInterrupted) out.exit_status = state.value("exit_status", kExitError);
        }
    }
    return out;
}

}  // namespace mrjam
