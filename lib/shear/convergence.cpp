#include "shear/convergence.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "core/exit_status.hpp"
#include "core/machine_threads.hpp"
#include "core/sample_stats.hpp"
#include "scene/scene_file.hpp"
#include "scene/scene_node.hpp"
#include "shear/flow_curve_fit.hpp"
#include "sweep/sweep_run.hpp"
#include "sweep/sweep_table.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSizeKey = "cell/size";
constexpr const char* kSeedKey = "seed";

json cell_of(const ShearSpec& spec, double edge) {
    return json::array({edge, spec.monolayer ? spec.cell.y : edge, edge});
}

SweepSpec convergence_sweep(const ShearSpec& spec) {
    SweepSpec s;
    s.command = {"shear"};
    s.args = {"--fidelity", spec.tier};
    s.base_scene = spec.input;
    s.base_scene.erase("field_sweep");  // the convergence is the flow curve's
    s.base_scene.erase("convergence");
    s.base_directory = spec.output.directory;
    SweepAxis sizes{{kSizeKey}, {}}, seeds{{kSeedKey}, {}};
    for (double edge : spec.converge_cell_sizes) sizes.values.push_back({cell_of(spec, edge)});
    for (int k = 0; k < spec.converge_seeds; ++k) seeds.values.push_back({spec.seed + static_cast<std::uint64_t>(k)});
    s.axes = {sizes, seeds};
    s.outputs = {{"yield_stress_Pa", "results/yield_stress_Pa"},
                 {"yield_stress_error_Pa", "results/yield_stress_error_Pa"},
                 {"grains", "results/cell/grains"}};
    s.source = {{"shear_input", spec.input}, {"tier", spec.tier}, {"convergence", true}};
    return s;
}

std::string folder_of(std::size_t, const json& values) {
    char name[64];
    std::snprintf(name, sizeof name, "%gum_seed%llu", values.at(kSizeKey)[0].get<double>() * 1e6,
                  static_cast<unsigned long long>(values.at(kSeedKey).get<std::uint64_t>()));
    return name;
}

// The seeds' flow curves averaged rate by rate (the rates every seed finished).
json mean_flow_curve(const std::vector<json>& reports, std::vector<FlowPoint>& curve) {
    json out = json::array();
    std::size_t rates = SIZE_MAX;
    for (const json& r : reports) rates = std::min(rates, r["results"]["flow_curve"].size());
    for (std::size_t k = 0; k < rates && !reports.empty(); ++k) {
        std::vector<double> stress;
        double block_sq = 0;
        int drifting = 0;  // seeds whose stress still drifted through this rate's window
        for (const json& r : reports) {
            const json& q = r["results"]["flow_curve"][k];
            stress.push_back(q["stress_Pa"].get<double>());
            block_sq += std::pow(q["error_Pa"].get<double>(), 2);
            drifting += q.value("drifting_in_window", false) ? 1 : 0;
        }
        const double n = static_cast<double>(stress.size());
        const MeanSd m = mean_and_sd(stress);
        const double spread_error = m.sd / std::sqrt(n), block_error = std::sqrt(block_sq) / n;
        const double rate = reports[0]["results"]["flow_curve"][k]["rate_1_s"].get<double>();
        const double error = std::max(spread_error, block_error);
        curve.push_back({rate, m.mean, error});
        out.push_back({{"rate_1_s", rate},
                       {"stress_Pa", m.mean},
                       {"error_Pa", error},
                       {"seed_sd_Pa", m.sd},
                       {"seed_error_Pa", spread_error},
                       {"block_error_Pa", block_error},
                       {"seeds", stress.size()},
                       {"seeds_drifting", drifting}});
    }
    return out;
}

}  // namespace

json size_summary(const ShearSpec& spec, double edge, const std::vector<json>& reports) {
    std::vector<FlowPoint> curve;
    json size = {{"edge_m", edge}, {"seeds_done", reports.size()}};
    size["flow_curve"] = mean_flow_curve(reports, curve);
    std::vector<double> yields, grains;
    for (const json& r : reports) {
        if (r["results"]["yield_stress_Pa"].is_number())
            yields.push_back(r["results"]["yield_stress_Pa"].get<double>());
        grains.push_back(r["results"]["cell"]["grains"].get<double>());
    }
    size["grains_mean"] = grains.empty() ? json(nullptr) : json(mean_and_sd(grains).mean);
    size["seed_yield_stresses_Pa"] = yields;
    const ModelFit fit = fit_bingham(curve, spec.bingham_min_rate);
    size["bingham_of_mean_curve"] = to_json(fit);
    if (!fit.ok) {
        size["yield_stress_Pa"] = nullptr;
        size["yield_stress_error_Pa"] = nullptr;
        return size;
    }
    const double seed_error =
        mean_and_sd(yields).sd / std::sqrt(static_cast<double>(std::max<std::size_t>(1, yields.size())));
    size["seed_yield_error_Pa"] = yields.size() >= 2 ? json(seed_error) : json(nullptr);
    size["yield_stress_Pa"] = fit.yield_stress;
    size["yield_stress_error_Pa"] = std::max(fit.yield_stress_error, seed_error);
    size["error_from"] =
        seed_error > fit.yield_stress_error ? "the seeds' Bingham values" : "the fit of the mean curve";
    return size;
}

json convergence_verdict(const std::vector<json>& sizes) {
    std::vector<const json*> known;
    for (const json& s : sizes)
        if (s["yield_stress_Pa"].is_number()) known.push_back(&s);
    json v = {{"criterion",
               "converged from the smallest edge at which every step to the next larger edge changes the yield "
               "stress by less than the two sizes' errors combined (1 sigma); the value is their error-weighted "
               "mean"},
              {"converged", false},
              {"converged_from_edge_m", nullptr}};
    if (known.empty()) {
        v["yield_stress_Pa"] = nullptr;
        v["yield_stress_error_Pa"] = nullptr;
        return v;
    }
    const auto y = [&](std::size_t k) { return (*known[k])["yield_stress_Pa"].get<double>(); };
    const auto e = [&](std::size_t k) { return (*known[k])["yield_stress_error_Pa"].get<double>(); };
    std::size_t from = known.size() - 1;
    while (from > 0 && std::abs(y(from) - y(from - 1)) < std::hypot(e(from), e(from - 1))) --from;
    json steps = json::array();
    for (std::size_t k = 1; k < known.size(); ++k)
        steps.push_back({{"from_edge_m", (*known[k - 1])["edge_m"]},
                         {"to_edge_m", (*known[k])["edge_m"]},
                         {"change_Pa", y(k) - y(k - 1)},
                         {"combined_error_Pa", std::hypot(e(k), e(k - 1))}});
    v["steps"] = steps;
    if (from + 1 < known.size()) {
        double weights = 0, sum = 0;
        for (std::size_t k = from; k < known.size(); ++k) {
            const double w = e(k) > 0 ? 1 / (e(k) * e(k)) : 1;
            weights += w;
            sum += w * y(k);
        }
        v["converged"] = true;
        v["converged_from_edge_m"] = (*known[from])["edge_m"];
        v["yield_stress_Pa"] = sum / weights;
        v["yield_stress_error_Pa"] = 1 / std::sqrt(weights);
    } else {  // the largest size's value, not converged
        v["yield_stress_Pa"] = y(known.size() - 1);
        v["yield_stress_error_Pa"] = e(known.size() - 1);
    }
    return v;
}

ConvergenceOutcome run_convergence(const ShearSpec& spec, const ShearOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    ConvergenceOutcome out;
    const fs::path dir = fs::path(spec.output.directory) / "convergence";
    out.directory = dir.string();
    SweepOptions o;
    o.out_dir = out.directory;
    // Runs of a few thousand grains gain little from a second thread: side by side, one each.
    o.jobs = options.jobs > 0 ? options.jobs : machine_threads();
    o.threads = options.threads_given ? options.threads : 0;
    o.progress = options.progress;
    o.yes = true;
    SweepEngine engine;
    engine.label = options.label + " convergence";
    engine.folder_name = folder_of;
    engine.spread_over_ranks = false;
    const SweepSpec sweep = convergence_sweep(spec);
    // Rerunning continues the same study; runs of another scene are not mixed in.
    const std::string changed = sweep_changed_at(dir, sweep.source);
    if (!changed.empty())
        throw SceneError("--converge", out.directory + " holds the runs of another scene (it differs at " + changed +
                                           "): restore the scene, or give another output/directory");
    out.exit_status = run_sweep_spec(sweep, o, engine);
    out.status = out.exit_status == 0 ? "complete" : out.exit_status == kExitInterrupted ? "interrupted" : "failed";
    // The finished runs by size, in the order of the edges.
    std::map<double, std::vector<json>> by_size;
    const json table = read_own_json_file((dir / "table.json").string());
    if (table.is_object() && table.contains("rows"))
        for (const json& row : table["rows"])
            if (row["state"] == "done")
                by_size[row["values"][kSizeKey][0].get<double>()].push_back(
                    read_own_json_file((dir / row["point"].get<std::string>() / "report.json").string()));
    json sizes = json::array();
    for (double edge : spec.converge_cell_sizes)
        sizes.push_back(size_summary(spec, edge, by_size.count(edge) ? by_size[edge] : std::vector<json>{}));
    out.results = {{"sizes", sizes}, {"seeds_per_size", spec.converge_seeds}, {"table", (dir / "table.csv").string()}};
    out.results.update(convergence_verdict(sizes.get<std::vector<json>>()));
    if (spec.experiment.is_object() && spec.experiment.contains("yield_stress_Pa") &&
        out.results["yield_stress_Pa"].is_number()) {
        json cmp = spec.experiment;
        const double e = cmp["yield_stress_Pa"].get<double>();
        cmp["relative_error"] = (out.results["yield_stress_Pa"].get<double>() - e) / e;
        out.results["experiment"] = cmp;
    }
    out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

}  // namespace mrjam
