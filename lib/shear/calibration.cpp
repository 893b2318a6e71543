#include "shear/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlopt.hpp>
#include <sstream>

#include "scene/scene_node.hpp"
#include "shear/shear_analysis.hpp"

namespace mrjam {
namespace {

FlowPoint point_of(const nlohmann::json& e, const std::string& where) {
    FlowPoint p{0, 0, 0};
    if (e.is_array() && (e.size() == 2 || e.size() == 3) && e[0].is_number() && e[1].is_number()) {
        p = {e[0].get<double>(), e[1].get<double>(), e.size() == 3 && e[2].is_number() ? e[2].get<double>() : 0.0};
    } else if (e.is_object() && e.contains("rate") && e.contains("stress")) {
        p = {e["rate"].get<double>(), e["stress"].get<double>(), e.value("error", 0.0)};
    } else {
        throw SceneError("--calibrate",
                         where + ": expected [shear rate in 1/s, stress in Pa] or {\"rate\", \"stress\"}");
    }
    return p;
}

void check(const CalibrationData& d, const std::string& path) {
    if (d.points.size() < 2) throw SceneError("--calibrate", path + ": needs at least two (shear rate, stress) points");
    for (const auto& p : d.points)
        if (!(p.rate > 0) || !std::isfinite(p.stress) || p.error < 0)
            throw SceneError("--calibrate", path + ": every shear rate must be positive and every stress finite");
}

double wrap_residual(const std::vector<FlowPoint>& sim, const CalibrationData& data) {
    // RMS of the relative misfit at the measured rates (the ladder is the data's rates).
    double s = 0;
    std::size_t n = 0;
    for (const auto& d : data.points)
        for (const auto& q : sim)
            if (std::abs(q.rate - d.rate) <= 1e-9 * d.rate) {
                const double r = (q.stress - d.stress) / std::max(std::abs(d.stress), 1e-12);
                s += r * r;
                ++n;
            }
    return n == data.points.size() ? std::sqrt(s / n) : 1e300;
}

}  // namespace

CalibrationData read_calibration_data(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw SceneError("--calibrate", "cannot read " + path);
    std::stringstream buf;
    buf << in.rdbuf();
    const std::string text = buf.str();
    CalibrationData d;
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && (text[first] == '[' || text[first] == '{')) {
        nlohmann::json j;
        try {
            j = nlohmann::json::parse(text);
        } catch (const nlohmann::json::parse_error& e) {
            throw SceneError("--calibrate", path + ": " + e.what());
        }
        const nlohmann::json* list = &j;
        if (j.is_object()) {
            if (j.contains("points"))
                list = &j["points"];
            else if (j.contains("flow_curve"))
                list = &j["flow_curve"];
            else
                throw SceneError("--calibrate", path + ": expected a list of points, or an object with \"points\"");
        }
        if (!list->is_array()) throw SceneError("--calibrate", path + ": the points must be a list");
        for (std::size_t k = 0; k < list->size(); ++k)
            d.points.push_back(point_of((*list)[k], path + " entry " + std::to_string(k)));
    } else {
        std::istringstream lines(text);
        std::string line;
        int number = 0;
        while (std::getline(lines, line)) {
            ++number;
            std::replace(line.begin(), line.end(), ',', ' ');
            std::replace(line.begin(), line.end(), ';', ' ');
            const auto s = line.find_first_not_of(" \t\r");
            if (s == std::string::npos || line[s] == '#') continue;
            // Every field must be a whole number: ">> a >> b" read "41 kPa" as 41 Pa and dropped
            // the unit. A line without a leading number before the first point is a header.
            std::istringstream fields(line);
            std::vector<double> values;
            std::string token, bad;
            while (fields >> token) {
                std::size_t used = 0;
                double v = 0;
                try {
                    v = std::stod(token, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used == 0 || used != token.size() || !std::isfinite(v)) {
                    bad = token;
                    break;
                }
                values.push_back(v);
            }
            if (values.empty() && d.points.empty()) continue;  // a header line
            const std::string where = path + " line " + std::to_string(number) + ": ";
            if (!bad.empty())
                throw SceneError("--calibrate", where + "'" + bad +
                                                    "' is not a plain number: give the shear rate in 1/s, the stress "
                                                    "(and its error) in Pa, without units");
            if (values.size() < 2 || values.size() > 3)
                throw SceneError("--calibrate", where + "expected shear rate, stress and an optional error (" +
                                                    std::to_string(values.size()) + " numbers)");
            d.points.push_back({values[0], values[1], values.size() == 3 ? values[2] : 0.0});
        }
    }
    check(d, path);
    std::sort(d.points.begin(), d.points.end(), [](const FlowPoint& x, const FlowPoint& y) { return x.rate > y.rate; });
    return d;
}

std::vector<CalibrationParameter> parse_calibration_parameters(const std::vector<std::string>& items,
                                                               const ShearSpec& spec) {
    if (items.empty() || items.size() > 2)
        throw SceneError("--parameter",
                         "give one or two parameters to fit, as NAME=MIN:MAX (e.g. rolling_friction=0.02:0.4)");
    std::vector<CalibrationParameter> out;
    for (const auto& item : items) {
        const auto eq = item.find('='), colon = item.find(':', eq == std::string::npos ? 0 : eq);
        if (eq == std::string::npos || colon == std::string::npos)
            throw SceneError("--parameter", "'" + item + "': expected NAME=MIN:MAX");
        CalibrationParameter p;
        p.name = item.substr(0, eq);
        // The whole text must be the number: stod would read "0.1 um" as 0.1 and drop the rest.
        auto number = [&](const std::string& text) {
            std::size_t used = 0;
            double v = 0;
            try {
                v = std::stod(text, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used == 0 || used != text.size() || !std::isfinite(v))
                throw SceneError("--parameter",
                                 "'" + item + "': MIN and MAX must be plain numbers in SI units, not '" + text + "'");
            return v;
        };
        p.lo = number(item.substr(eq + 1, colon - eq - 1));
        p.hi = number(item.substr(colon + 1));
        if (!(p.hi > p.lo)) throw SceneError("--parameter", "'" + item + "': MAX must exceed MIN");
        const std::vector<std::string> material = {"rolling_friction",      "friction",
                                                   "rolling_damping",       "cohesion_energy_density",
                                                   "relative_permeability", "restitution"};
        if (p.name == "field_scale") {
            if (!(p.lo > 0)) throw SceneError("--parameter", "field_scale must be positive");
            p.pointer = "";
        } else if (std::find(material.begin(), material.end(), p.name) != material.end()) {
            p.pointer = "/material/" + p.name;
        } else if (!p.name.empty() && p.name[0] == '/') {
            p.pointer = p.name;
            bool present = false;
            try {
                present = spec.input.contains(nlohmann::json::json_pointer(p.pointer));
            } catch (const nlohmann::json::exception&) {
                throw SceneError("--parameter",
                                 p.pointer + " is not a valid JSON pointer (escape ~ as ~0 and / as ~1)");
            }
            if (!present) throw SceneError("--parameter", p.pointer + " is not a key of the shear scene");
        } else {
            throw SceneError(
                "--parameter",
                "unknown parameter '" + p.name +
                    "'; use rolling_friction, friction, rolling_damping, cohesion_energy_density, "
                    "relative_permeability, restitution, field_scale or a JSON pointer such as /material/friction");
        }
        // The same key twice ("friction=0:1" and "/material/friction=0:2") would search a 2D grid
        // along one axis.
        for (const CalibrationParameter& q : out)
            if (q.pointer == p.pointer)
                throw SceneError("--parameter",
                                 "'" + item + "' sets the same key as '" + q.name + "': give each parameter once");
        out.push_back(p);
    }
    return out;
}

namespace {

// The shear scene of one evaluation: `input` with each parameter set to its value in `x`.
nlohmann::json with_values(nlohmann::json input, const ShearSpec& spec, const std::vector<CalibrationParameter>& params,
                           const std::vector<double>& x) {
    for (std::size_t k = 0; k < params.size(); ++k) {
        if (params[k].pointer.empty())
            input["field"]["flux_density"] = spec.flux_density * x[k];
        else
            input[nlohmann::json::json_pointer(params[k].pointer)] = x[k];
    }
    return input;
}

// Every corner of the search box must make a scene the reader and the engine take: found out
// at the search's first step outside, it would stop the calibration hours in.
void check_box(const nlohmann::json& base, const ShearSpec& spec, const std::vector<CalibrationParameter>& params) {
    for (unsigned corner = 0; corner < (1u << params.size()); ++corner) {
        std::vector<double> x;
        for (std::size_t k = 0; k < params.size(); ++k) x.push_back(corner >> k & 1 ? params[k].hi : params[k].lo);
        try {
            check_engine_accepts(read_shear_spec(with_values(base, spec, params, x), spec.tier));
        } catch (const SceneError& e) {
            std::ostringstream at;
            for (std::size_t k = 0; k < params.size(); ++k) at << (k ? ", " : "") << params[k].name << " = " << x[k];
            throw SceneError("--parameter", "the scene is refused at the corner " + at.str() + " of the range: " +
                                                e.what() + "; keep MIN and MAX inside what that key accepts");
        }
    }
}

}  // namespace

// NLopt's Nelder-Mead simplex (bounded) over the parameters' box: derivative-free, because each
// evaluation is a noisy and expensive shear study. It starts at the box's centre with steps of a
// quarter of each range and stops after max_runs evaluations or when `stop` is set (an interrupt).
void minimise_in_box(const std::vector<CalibrationParameter>& params, int max_runs,
                     const std::function<double(const std::vector<double>&)>& evaluate, const bool& stop) {
    const unsigned n = static_cast<unsigned>(params.size());
    nlopt::opt search(nlopt::LN_NELDERMEAD, n);
    std::vector<double> lo(n), hi(n), x(n), step(n);
    for (unsigned k = 0; k < n; ++k) {
        lo[k] = params[k].lo;
        hi[k] = params[k].hi;
        x[k] = 0.5 * (lo[k] + hi[k]);
        step[k] = 0.25 * (hi[k] - lo[k]);
    }
    search.set_lower_bounds(lo);
    search.set_upper_bounds(hi);
    search.set_initial_step(step);
    search.set_maxeval(max_runs);
    struct Objective {
        const std::function<double(const std::vector<double>&)>* evaluate;
        const bool* stop;
        nlopt::opt* search;
    } objective{&evaluate, &stop, &search};
    search.set_min_objective(
        [](const std::vector<double>& at, std::vector<double>&, void* data) {
            auto* o = static_cast<Objective*>(data);
            const double value = (*o->evaluate)(at);
            if (*o->stop) o->search->force_stop();
            return value;
        },
        &objective);
    double best = 0;
    try {
        search.optimize(x, best);
    } catch (const nlopt::forced_stop&) {       // interrupted: the runs so far are the result
    } catch (const nlopt::roundoff_limited&) {  // the simplex cannot shrink further: done
    }
}

nlohmann::json calibrate(const ShearSpec& spec, const CalibrationData& data,
                         const std::vector<CalibrationParameter>& params, int max_runs, const ShearOptions& options) {
    nlohmann::json base = spec.input;
    std::vector<double> rates;
    for (const auto& p : data.points)
        if (rates.empty() || p.rate < rates.back()) rates.push_back(p.rate);
    nlohmann::json ladder = spec.resolved["ladder"];
    ladder.erase("wall_speeds");
    ladder["shear_rates"] = rates;
    base["ladder"] = ladder;
    base.erase("field_sweep");
    const std::string root_dir = spec.output.directory;
    check_box(base, spec, params);

    nlohmann::json result = {{"status", "complete"},
                             {"exit_status", 0},
                             {"runs", nlohmann::json::array()},
                             {"data_points", data.points.size()},
                             {"parameters", nlohmann::json::array()},
                             {"objective", "RMS of (simulated - measured) / measured stress at the measured rates"},
                             {"search", "Nelder-Mead simplex within the bounds (NLopt LN_NELDERMEAD)"}};
    for (const auto& p : params) result["parameters"].push_back({{"name", p.name}, {"min", p.lo}, {"max", p.hi}});
    double best = 1e300;
    bool stop = false;

    auto evaluate = [&](const std::vector<double>& x) -> double {
        if (stop || static_cast<int>(result["runs"].size()) >= max_runs) return 1e300;
        std::vector<double> clamped;
        nlohmann::json values = nlohmann::json::object();
        for (std::size_t k = 0; k < params.size(); ++k) {
            clamped.push_back(std::clamp(x[k], params[k].lo, params[k].hi));
            values[params[k].name] = clamped.back();
        }
        nlohmann::json input = with_values(base, spec, params, clamped);
        const int run = static_cast<int>(result["runs"].size());
        input["output"]["directory"] =
            (std::filesystem::path(root_dir) / ("calibrate_run_" + std::to_string(run))).string();
        const ShearSpec s = read_shear_spec(input, spec.tier);
        ShearOptions o = options;
        o.label = "calibrate " + std::to_string(run + 1) + "/" + std::to_string(max_runs);
        const ShearOutcome out = run_shear_study(s, o);
        const double residual = out.status == "complete" ? wrap_residual(flow_points(out.results), data) : 1e300;
        nlohmann::json rec = {{"values", values},
                              {"residual", residual < 1e299 ? nlohmann::json(residual) : nlohmann::json(nullptr)},
                              {"status", out.status},
                              {"yield_stress_Pa", out.results["yield_stress_Pa"]},
                              {"wall_time_s", out.wall_time}};
        result["runs"].push_back(rec);
        if (options.progress)
            std::fprintf(stderr, "[calibrate] run %d: %s -> residual %.4g\n", run + 1, values.dump().c_str(), residual);
        if (out.exit_status == 130) {
            stop = true;
            result["status"] = "interrupted";
            result["exit_status"] = 130;
        }
        if (residual < best) {
            best = residual;
            result["best"] = {{"values", values},
                              {"residual", residual},
                              {"flow_curve", out.results["flow_curve"]},
                              {"fits", out.results["fits"]},
                              {"yield_stress_Pa", out.results["yield_stress_Pa"]}};
        }
        return residual;
    };

    minimise_in_box(params, max_runs, evaluate, stop);
    return result;
}

}  // namespace mrjam
