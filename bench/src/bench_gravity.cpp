// `mrjam-bench gravity`: the self-gravity tree (lib/engine/gravity/) against direct summation:
// per-grain force error (median, 99th percentile, max) and microseconds per grain per evaluation
// for several N and opening angles, and the error a held evaluation adds as a cloud collapses.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <vector>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "gravity/self_gravity.hpp"
#include "particles.hpp"
#include "run/runner.hpp"

namespace mrjam::cli {

namespace {

struct GravityBenchArgs {
    std::vector<int> grains{1000, 4000, 16000};
    std::vector<double> thetas{0.3, 0.5, 0.7, 1.0};
    std::vector<int> holds{1, 4, 16, 64};
    int threads = 1;
    std::string json_out;
};

// N grains of 1 m, 3000 kg/m3, uniformly at random in a sphere at a volume fraction of 0.3.
Particles uniform_cloud(int n, unsigned seed) {
    Particles p;
    const double r = 1.0, R = std::cbrt(n / 0.3) * r;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-R, R);
    while (static_cast<int>(p.position.size()) < n) {
        const Vec3 x{u(rng), u(rng), u(rng)};
        if (norm(x) < R) p.position.push_back(x);
    }
    p.radius.assign(n, r);
    p.mass.assign(n, 3000 * 4.0 / 3.0 * M_PI * r * r * r);
    return p;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct ErrorStats {
    double median = 0, p99 = 0, max = 0;
};
ErrorStats relative_errors(const std::vector<Vec3>& a, const std::vector<Vec3>& ref) {
    std::vector<double> e(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) e[i] = norm(a[i] - ref[i]) / norm(ref[i]);
    std::sort(e.begin(), e.end());
    return {e[e.size() / 2], e[static_cast<std::size_t>(0.99 * (e.size() - 1))], e.back()};
}

nlohmann::json accuracy_rows(const GravityBenchArgs& args) {
    nlohmann::json rows = nlohmann::json::array();
    std::printf("%8s %6s %12s %12s %12s %14s %10s\n", "grains", "theta", "median err", "99th pct", "max err",
                "us/grain/eval", "nodes");
    for (int n : args.grains) {
        const Particles p = uniform_cloud(n, 7);
        std::vector<Vec3> direct, tree;
        auto t0 = std::chrono::steady_clock::now();
        direct_gravity(p, kNewtonG, direct, args.threads);
        const double direct_us = seconds_since(t0) * 1e6 / n;
        std::printf("%8d %6s %12s %12s %12s %14.3f %10s\n", n, "direct", "-", "-", "-", direct_us, "-");
        rows.push_back({{"grains", n}, {"method", "direct"}, {"us_per_grain", direct_us}});
        for (double theta : args.thetas) {
            GravityTree t({theta, 8, true});
            int repeats = 0;
            t0 = std::chrono::steady_clock::now();
            do {
                t.build(p);
                t.accelerations(p, kNewtonG, tree, args.threads);
                ++repeats;
            } while (seconds_since(t0) < 0.5);
            const double us = seconds_since(t0) * 1e6 / (repeats * static_cast<double>(n));
            const ErrorStats e = relative_errors(tree, direct);
            std::printf("%8d %6.2f %12.2e %12.2e %12.2e %14.3f %10zu\n", n, theta, e.median, e.p99, e.max, us,
                        t.nodes());
            rows.push_back({{"grains", n},
                            {"method", "tree"},
                            {"opening_angle", theta},
                            {"median_error", e.median},
                            {"p99_error", e.p99},
                            {"max_error", e.max},
                            {"us_per_grain", us},
                            {"nodes", t.nodes()}});
        }
    }
    return rows;
}

// A cold cloud collapsing (kick-drift-kick, dt = t_ff / 1000, fresh tree forces each step) to half
// its free-fall time; from there, the accelerations held for K steps against fresh ones.
nlohmann::json hold_rows(const GravityBenchArgs& args) {
    Particles p = uniform_cloud(4000, 11);
    p.velocity.assign(p.size(), Vec3{});
    double cloud_mass = 0;
    for (double m : p.mass) cloud_mass += m;
    const double R = std::cbrt(4000 / 0.3), rho = cloud_mass / (4.0 / 3.0 * M_PI * R * R * R);
    const double t_ff = std::sqrt(3 * M_PI / (32 * kNewtonG * rho)), dt = t_ff / 1000;
    GravityTree tree({0.5, 8, true});
    std::vector<Vec3> a;
    auto step = [&] {
        tree.build(p);
        tree.accelerations(p, kNewtonG, a, args.threads);
        for (std::size_t i = 0; i < p.size(); ++i) {
            p.velocity[i] += a[i] * dt;
            p.position[i] += p.velocity[i] * dt;
        }
    };
    for (int k = 0; k < 500; ++k) step();
    tree.build(p);
    std::vector<Vec3> held;
    tree.accelerations(p, kNewtonG, held, args.threads);
    nlohmann::json rows = nlohmann::json::array();
    std::printf("\nheld forces in a cloud collapsing (4000 grains, at t = t_ff / 2, dt = t_ff / 1000)\n");
    std::printf("%8s %14s %12s %12s\n", "K steps", "K dt / t_ff", "median err", "99th pct");
    int done = 0;
    for (int K : args.holds) {
        while (done < K) {
            step();
            ++done;
        }
        tree.build(p);
        tree.accelerations(p, kNewtonG, a, args.threads);
        const ErrorStats e = relative_errors(held, a);
        std::printf("%8d %14.4f %12.2e %12.2e\n", K, K * dt / t_ff, e.median, e.p99);
        rows.push_back({{"hold_steps", K},
                        {"hold_over_free_fall_time", K * dt / t_ff},
                        {"median_error", e.median},
                        {"p99_error", e.p99}});
    }
    return rows;
}

}  // namespace

void add_gravity_bench_command(CLI::App& bench, int& exit_status) {
    auto args = std::make_shared<GravityBenchArgs>();
    CLI::App* g = bench.add_subcommand(
        "gravity", "Self-gravity tree against direct summation: error and microseconds per grain, held-force error");
    g->add_option("--grains", args->grains, "Cloud sizes")->delimiter(',')->capture_default_str();
    g->add_option("--theta", args->thetas, "Opening angles")
        ->delimiter(',')
        ->check(CLI::Range(0.01, 1.0))
        ->capture_default_str();
    g->add_option("--hold", args->holds, "Hold intervals (steps) for the held-force error")
        ->delimiter(',')
        ->capture_default_str();
    g->add_option("--threads", args->threads, "OpenMP threads")->check(CLI::Range(1, 1024))->capture_default_str();
    g->add_option("--json", args->json_out, "Also write the rows as JSON");
    g->callback([args, &exit_status] {
        if (!args->json_out.empty()) prepare_output_file(args->json_out, "--json");
        nlohmann::json out = {{"benchmark", "gravity"}, {"threads", args->threads}};
        out["accuracy"] = accuracy_rows(*args);
        out["hold"] = hold_rows(*args);
        if (!args->json_out.empty()) write_json_file(args->json_out, out);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
