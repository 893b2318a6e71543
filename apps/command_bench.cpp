// `mrjam bench contact`: the contact-engine benchmark. A fixed granular scene (monodisperse
// Hertz-Mindlin grains with friction at volume fraction 0.5 in a periodic box) timed over a
// fixed number of steps; prints grain-steps per second and core-microseconds per grain-step.
// bench/contact_vs_liggghts.sh runs the same state in LIGGGHTS for the side-by-side figure.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "integrator.hpp"
#include "io/lammps_data.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"

namespace mrjam::cli {

namespace {

struct BenchArgs {
    long grains = 20000;
    long steps = 2000;
    int threads = 1;
    std::string write_data;
    std::string json_out;
};

// The benchmark scene as a user would write it (docs/benchmarks.md lists it).
nlohmann::json contact_bench_scene(long grains) {
    const double d = 1e-3, phi = 0.5;
    const double side = std::cbrt(grains * M_PI / 6.0 * d * d * d / phi);
    return {
        {"description", "contact benchmark: monodisperse Hertz-Mindlin grains with friction, phi 0.5, periodic"},
        {"seed", 7},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {side, side, side}}, {"periodic", "xyz"}}},
        {"materials", {{{"name", "glass"}, {"density", 2500}, {"youngs_modulus", 1e7}, {"poisson_ratio", 0.3},
                        {"restitution", 0.5}, {"friction", 0.5}}}},
        {"grains", {{{"material", "glass"}, {"size", {{"distribution", "single"}, {"diameter", d}}},
                     {"placement", {{"method", "random"}, {"volume_fraction", phi}}}, {"random_velocity", 0.1}}}},
        {"run", {{"timestep", 1e-6}, {"steps", 1}, {"skin", 0.1}}},
    };
}

}  // namespace

void add_bench_command(CLI::App& app, int& exit_status) {
    CLI::App* bench = app.add_subcommand("bench", "Benchmarks (timing, not tests)");
    bench->require_subcommand(1);
    auto args = std::make_shared<BenchArgs>();
    CLI::App* contact = bench->add_subcommand("contact", "Hertz-Mindlin contact engine: grain-steps per second");
    contact->add_option("--grains", args->grains, "Number of grains")->check(CLI::Range(10L, 10000000L))->capture_default_str();
    contact->add_option("--steps", args->steps, "Timed steps")->check(CLI::Range(1L, 100000000L))->capture_default_str();
    contact->add_option("--threads", args->threads, "OpenMP threads")->check(CLI::Range(1, 1024))->capture_default_str();
    contact->add_option("--write-data", args->write_data, "Also write the initial state as a LAMMPS data file (for LIGGGHTS)");
    contact->add_option("--json", args->json_out, "Write the figures as JSON here");
    contact->callback([args, &exit_status] {
        BuildOptions build;
        build.threads = args->threads;
        const auto setup0 = std::chrono::steady_clock::now();
        Scene scene = build_scene(contact_bench_scene(args->grains), build);
        choose_timestep(scene);
        System& s = scene.system;
        if (!args->write_data.empty())
            write_lammps_data(args->write_data, s.particles, s.domain, {s.materials[0].density});
        prepare(s);
        const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - setup0).count();
        const auto t0 = std::chrono::steady_clock::now();
        for (long i = 0; i < args->steps; ++i) advance(s);
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double grain_steps = static_cast<double>(s.particles.size()) * args->steps;
        nlohmann::json out = {
            {"benchmark", "contact"},
            {"grains", s.particles.size()},
            {"steps", args->steps},
            {"threads", args->threads},
            {"timestep_s", s.dt},
            {"setup_s", setup},
            {"wall_s", wall},
            {"grain_steps_per_s", grain_steps / wall},
            {"core_us_per_particle_step", wall * args->threads * 1e6 / grain_steps},
            {"contacts_per_grain", 2.0 * s.contact_stats.contacts / s.particles.size()},
            {"neighbour_pairs_per_grain", 2.0 * s.contacts.pair_count() / s.particles.size()},
            {"neighbour_builds", s.contacts.builds()},
        };
        std::printf("bench contact: %zu grains, %ld steps, %d thread(s): %.3g grain-steps/s, %.3f core-us per grain-step "
                    "(%.2f contacts and %.2f listed neighbours per grain, %ld list builds)\n",
                    s.particles.size(), args->steps, args->threads, grain_steps / wall,
                    wall * args->threads * 1e6 / grain_steps, out["contacts_per_grain"].get<double>(),
                    out["neighbour_pairs_per_grain"].get<double>(), s.contacts.builds());
        if (!args->json_out.empty()) write_json_file(args->json_out, out);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
