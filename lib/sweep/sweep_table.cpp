#include "sweep/sweep_table.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "core/proportion_interval.hpp"
#include "core/sample_stats.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {
using json = nlohmann::json;

namespace {

const char* kSeedKey = "seed";

std::vector<std::string> swept_keys(const SweepSpec& spec) {
    std::vector<std::string> keys;
    for (const SweepAxis& a : spec.axes) keys.insert(keys.end(), a.keys.begin(), a.keys.end());
    return keys;
}

// One output over the seeds of a group.
json aggregate(const std::vector<json>& values) {
    std::vector<double> numbers;
    int yes = 0, booleans = 0;
    std::map<std::string, int> words;
    for (const json& v : values) {
        if (v.is_boolean()) {
            ++booleans;
            yes += v.get<bool>();
        } else if (v.is_number()) {
            numbers.push_back(v.get<double>());
        } else if (v.is_string()) {
            ++words[v.get<std::string>()];
        }
    }
    if (booleans > 0 && numbers.empty() && words.empty()) {
        const ProportionInterval ci = wilson_interval(yes, booleans);
        return {{"share", static_cast<double>(yes) / booleans},
                {"yes", yes},
                {"of", booleans},
                {"ci95", {ci.low, ci.high}}};
    }
    if (!numbers.empty() && booleans == 0 && words.empty()) {
        const MeanSd m = mean_and_sd(numbers);
        return {{"mean", m.mean}, {"sd", m.sd}, {"of", numbers.size()}};
    }
    json counts = json::object();
    for (const auto& [w, n] : words) counts[w] = n;
    return {{"counts", counts}, {"of", values.size()}};
}

json aggregates(const SweepSpec& spec, const json& rows) {
    std::vector<std::string> group_keys;
    for (const std::string& k : swept_keys(spec))
        if (k != kSeedKey) group_keys.push_back(k);
    std::vector<json> order;  // the groups in the order their first point comes
    std::map<std::string, std::vector<const json*>> groups;
    for (const json& row : rows) {
        json key = json::object();
        for (const std::string& k : group_keys) key[k] = row["values"][k];
        const std::string id = key.dump();
        if (!groups.count(id)) order.push_back(key);
        groups[id].push_back(&row);
    }
    json out = json::array();
    for (const json& key : order) {
        const auto& members = groups[key.dump()];
        json entry{{"values", key}, {"seeds", members.size()}, {"done", 0}, {"outputs", json::object()}};
        int done = 0;
        for (const json* r : members) done += (*r)["state"] == "done";
        entry["done"] = done;
        for (const SweepOutput& o : spec.outputs) {
            std::vector<json> values;
            for (const json* r : members)
                if ((*r)["state"] == "done") values.push_back((*r)["outputs"][o.name]);
            entry["outputs"][o.name] = aggregate(values);
        }
        out.push_back(entry);
    }
    return out;
}

std::string csv_cell(const json& v) {
    if (v.is_null()) return "";
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    if (v.is_number()) {
        char b[32];
        std::snprintf(b, sizeof b, "%.8g", v.get<double>());
        return b;
    }
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string quoted = "\"";
    for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

// Whether the report has the path at all (a null there is a value the mode wrote: a jam
// probability with no seed judged, say), so a misspelt path is told from an empty result.
bool report_has(const json& report, const std::string& path) {
    try {
        return report.contains(json::json_pointer("/" + path));
    } catch (const json::exception&) {
        return false;
    }
}

}  // namespace

json report_value(const json& report, const std::string& path) {
    try {
        const json::json_pointer p("/" + path);
        return report.contains(p) ? report.at(p) : json();
    } catch (const json::exception&) {
        return json();
    }
}

json sweep_table(const SweepSpec& spec, const std::vector<SweepRow>& rows) {
    json table{{"keys", swept_keys(spec)}, {"outputs", json::array()}, {"rows", json::array()}};
    for (const SweepOutput& o : spec.outputs) table["outputs"].push_back({{"name", o.name}, {"path", o.path}});
    std::vector<int> found(spec.outputs.size(), 0);
    int done = 0;
    for (const SweepRow& r : rows) {
        json row{{"point", r.folder}, {"state", r.state}, {"values", r.point.values}, {"outputs", json::object()}};
        done += r.state == "done";
        for (std::size_t k = 0; k < spec.outputs.size(); ++k) {
            const json v = r.state == "done" ? report_value(r.report, spec.outputs[k].path) : json();
            found[k] += r.state == "done" && report_has(r.report, spec.outputs[k].path);
            row["outputs"][spec.outputs[k].name] = v;
            if (!spec.outputs[k].interval_path.empty() && r.state == "done")
                row["outputs_95ci"][spec.outputs[k].name] = report_value(r.report, spec.outputs[k].interval_path);
        }
        table["rows"].push_back(row);
    }
    for (std::size_t k = 0; k < spec.outputs.size(); ++k)
        if (done > 0 && found[k] == 0)
            throw SceneError("/outputs/" + spec.outputs[k].name,
                             "no report of the " + std::to_string(done) + " points done has \"" + spec.outputs[k].path +
                                 "\": name a path in the mode's report (docs/reports.md)");
    bool seeded = false;
    for (const std::string& k : swept_keys(spec)) seeded = seeded || k == kSeedKey;
    if (seeded) table["aggregates"] = aggregates(spec, table["rows"]);
    return table;
}

std::string sweep_table_csv(const json& table) {
    std::ostringstream o;
    o << "point,state";
    for (const json& k : table["keys"]) o << "," << csv_cell(k);
    for (const json& out : table["outputs"]) o << "," << csv_cell(out["name"]);
    o << "\n";
    for (const json& row : table["rows"]) {
        o << csv_cell(row["point"]) << "," << csv_cell(row["state"]);
        for (const json& k : table["keys"]) o << "," << csv_cell(row["values"][k.get<std::string>()]);
        for (const json& out : table["outputs"]) o << "," << csv_cell(row["outputs"][out["name"].get<std::string>()]);
        o << "\n";
    }
    return o.str();
}

}  // namespace mrjam
