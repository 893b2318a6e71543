// `mrjam-bench contact`: the contact-engine benchmark. A fixed granular scene (monodisperse
// Hertz-Mindlin grains with friction at volume fraction 0.5 in a periodic box) timed over a
// fixed number of steps; prints grain-steps per second and core-microseconds per grain-step.
// bench/contact_vs_liggghts.sh runs the same state in LIGGGHTS for the side-by-side figure.
//
// `mrjam-bench restitution`: the accuracy of the time step. Head-on collisions of two equal
// grains at a range of steps per contact, measuring the restitution the integrator realises
// against the set e and the undamped contact duration against Hertz; then what the automatic
// step costs for the same pair. docs/accuracy.md shows and explains the table.
//
// `mrjam-bench magnetic` and `mrjam-bench magnetic-accuracy` live in bench_magnetic.cpp
// (docs/magnetic_forces.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "contact/restitution.hpp"
#include "integrator.hpp"
#include "io/lammps_data.hpp"
#include "observers.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "timestep.hpp"

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
        {"materials",
         {{{"name", "glass"},
           {"density", 2500},
           {"youngs_modulus", 1e7},
           {"poisson_ratio", 0.3},
           {"restitution", 0.5},
           {"friction", 0.5}}}},
        {"grains",
         {{{"material", "glass"},
           {"size", {{"distribution", "single"}, {"diameter", d}}},
           {"placement", {{"method", "random"}, {"volume_fraction", phi}}},
           {"random_velocity", 0.1}}}},
        {"run", {{"timestep", 1e-6}, {"steps", 1}, {"skin", 0.1}}},
    };
}

// ---- bench restitution ----------------------------------------------------------------------

// The colliding pair: two equal glass-like grains (the soft 10 MPa grains of the physics tests).
// The damped Hertz collision is self-similar (tests/test_contact_physics.cpp, dimensionless_rebound):
// in units of the contact duration it depends on e alone, so the errors measured here hold for
// any size, stiffness and speed at the same steps per contact.
struct PairSpec {
    double radius = 0.5e-3;  // m
    double density = 2500;   // kg/m3
    double youngs = 1e7;     // Pa
    double poisson = 0.3;
    double friction = 0.5;
    double speed = 0.2;  // approach speed, m/s
};

Material pair_material(const PairSpec& p, double restitution) {
    Material m;
    m.name = "grain";
    m.density = p.density;
    m.youngs_modulus = p.youngs;
    m.poisson_ratio = p.poisson;
    m.restitution = restitution;
    m.friction = p.friction;
    return m;
}

// The two grains touching at the origin along x (grain 0 on the left), at rest, in a closed box
// with no walls and no gravity.
System pair_system(const PairSpec& p, double restitution) {
    System s;
    const double half = 40 * p.radius;
    s.domain.lo = {-half, -half, -half};
    s.domain.hi = {half, half, half};
    s.domain.periodic = {false, false, false};
    s.materials = {pair_material(p, restitution)};
    s.pairs = PairTable(s.materials);
    s.physics.contact = true;
    s.threads = 1;
    s.particles.add({-p.radius, 0, 0}, p.radius, p.density, 0);
    s.particles.add({p.radius, 0, 0}, p.radius, p.density, 0);
    return s;
}

struct PairConstants {
    double reduced_mass = 0, reduced_radius = 0, effective_youngs = 0;
    double contact_duration(double speed) const {
        return hertz_contact_duration(reduced_mass, reduced_radius, effective_youngs, speed);
    }
};

PairConstants pair_constants(const PairSpec& p) {
    const System s = pair_system(p, 1.0);
    const double m0 = s.particles.mass[0], m1 = s.particles.mass[1];
    const double r0 = s.particles.radius[0], r1 = s.particles.radius[1];
    return {m0 * m1 / (m0 + m1), r0 * r1 / (r0 + r1), s.pairs(0, 0).effective_youngs};
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Collision {
    double restitution = kNaN;  // separation speed / approach speed; NaN if they never separated
    double duration = kNaN;     // time with overlap > 0
};

// One head-on collision at `speed` with step `dt`. The grains start (3 + phase) steps of travel
// apart, so the first contact falls at that fraction of a step; the contact's start and end are
// interpolated linearly between steps (near the crossings the overlap is linear in time).
Collision collide(const PairSpec& p, double restitution, double speed, double dt, double phase) {
    System s = pair_system(p, restitution);
    const double gap = (3 + phase) * speed * dt;
    s.particles.position[0].x -= 0.5 * gap;
    s.particles.position[1].x += 0.5 * gap;
    s.particles.velocity[0] = {speed, 0, 0};
    s.dt = dt;
    s.contacts = NeighborList(NeighborList::Settings{0.5 * p.radius, 1.0, true});
    Collision out;
    try {
        prepare(s);
        const long max_steps = 20 + static_cast<long>(20 * pair_constants(p).contact_duration(speed) / dt);
        double prev_overlap = -1, prev_time = 0, begin = -1, end = -1;
        for (long k = 0; k < max_steps && end < 0; ++k) {
            advance(s);
            const double overlap = 2 * p.radius - norm(s.particles.position[0] - s.particles.position[1]);
            const auto crossing = [&] {
                return prev_time + (s.time - prev_time) * prev_overlap / (prev_overlap - overlap);
            };
            if (begin < 0 && prev_overlap <= 0 && overlap > 0) begin = crossing();
            if (begin >= 0 && end < 0 && prev_overlap > 0 && overlap <= 0) end = crossing();
            prev_overlap = overlap;
            prev_time = s.time;
        }
        if (end < 0) return out;
        // After separation no force acts; two more steps make sure both half kicks used zero force.
        advance(s);
        advance(s);
        out.restitution = (s.particles.velocity[1].x - s.particles.velocity[0].x) / speed;
        out.duration = end - begin;
    } catch (const BlowUp&) {
        // Too coarse a step for this pair: reported as not separated.
    }
    return out;
}

// Where in a step the contact begins changes the result at coarse resolution (the force is
// sampled at step ends, and the dashpot grows as d^(1/4) from the first touch), so each figure
// is the mean over impacts at kPhases evenly spread step fractions, with the spread reported.
constexpr int kPhases = 8;

struct PhaseAveraged {
    double restitution = kNaN, restitution_min = kNaN, restitution_max = kNaN;
    double duration = kNaN;
};

PhaseAveraged collide_phases(const PairSpec& p, double restitution, double speed, double dt) {
    double e_sum = 0, e_min = std::numeric_limits<double>::infinity(), e_max = -e_min, t_sum = 0;
    for (int k = 0; k < kPhases; ++k) {
        const Collision c = collide(p, restitution, speed, dt, (k + 0.5) / kPhases);
        if (!std::isfinite(c.restitution)) return {};
        e_sum += c.restitution;
        e_min = std::min(e_min, c.restitution);
        e_max = std::max(e_max, c.restitution);
        t_sum += c.duration;
    }
    return {e_sum / kPhases, e_min, e_max, t_sum / kPhases};
}

// Signed relative error in percent (NaN propagates: the collision did not complete).
double percent_error(double measured, double expected) { return 100.0 * (measured - expected) / expected; }

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

nlohmann::json restitution_json(double e, const PhaseAveraged& r) {
    return {{"e", e},
            {"measured_mean", number_or_null(r.restitution)},
            {"error_percent", number_or_null(percent_error(r.restitution, e))},
            {"error_percent_min", number_or_null(percent_error(r.restitution_min, e))},
            {"error_percent_max", number_or_null(percent_error(r.restitution_max, e))}};
}

std::string cell(double x, int width) {
    char buf[48];
    if (std::isfinite(x))
        std::snprintf(buf, sizeof buf, "%+*.3f", width, x);
    else
        std::snprintf(buf, sizeof buf, "%*s", width, "n/a");
    return buf;
}

std::string spread_cell(double lo, double hi, int width) {
    char buf[48];
    if (std::isfinite(lo) && std::isfinite(hi))
        std::snprintf(buf, sizeof buf, "%+.2f..%+.2f", lo, hi);
    else
        std::snprintf(buf, sizeof buf, "n/a");
    char out[64];
    std::snprintf(out, sizeof out, "%*s", width, buf);
    return out;
}

void print_e_header(const std::vector<double>& restitutions, int width) {
    for (double e : restitutions) {
        char label[16];
        std::snprintf(label, sizeof label, "e = %.1f", e);
        std::printf(" %*s |", width, label);
    }
}

void print_e_rule(const std::vector<double>& restitutions, int width) {
    for (std::size_t k = 0; k < restitutions.size(); ++k) std::printf("%s:|", std::string(width + 1, '-').c_str());
}

void run_restitution_bench(const std::string& json_out) {
    const PairSpec pair;
    const PairConstants pc = pair_constants(pair);
    const std::vector<double> restitutions = {0.1, 0.3, 0.5, 0.7, 0.9};
    const std::vector<long> resolutions = {5, 10, 20, 50, 100, 200, 1000};
    const double t_c = pc.contact_duration(pair.speed);

    std::printf(
        "bench restitution: head-on collision of two equal grains, R %g m, density %g kg/m3, Y %g Pa, "
        "nu %g, friction %g, approach speed %g m/s\n",
        pair.radius, pair.density, pair.youngs, pair.poisson, pair.friction, pair.speed);
    std::printf(
        "Hertz contact duration t_c = %.4g s; dt = t_c / (steps per contact); each figure is the mean over "
        "%d impact phases within a step.\n\n",
        t_c, kPhases);
    std::printf(
        "Relative error of the realised restitution and of the undamped (e = 1) contact duration, %% (signed):\n\n");
    std::printf("| steps/contact |");
    print_e_header(restitutions, 8);
    std::printf(" t_c (e = 1) |\n|--------------:|");
    print_e_rule(restitutions, 8);
    std::printf("------------:|\n");

    struct Row {
        long n;
        std::vector<PhaseAveraged> damped;
    };
    std::vector<Row> rows;
    nlohmann::json sweep = nlohmann::json::array();
    for (const long n : resolutions) {
        const double dt = t_c / static_cast<double>(n);
        Row row{n, {}};
        nlohmann::json rest = nlohmann::json::array();
        std::printf("| %13ld |", n);
        for (const double e : restitutions) {
            row.damped.push_back(collide_phases(pair, e, pair.speed, dt));
            rest.push_back(restitution_json(e, row.damped.back()));
            std::printf(" %s |", cell(percent_error(row.damped.back().restitution, e), 8).c_str());
        }
        const PhaseAveraged el = collide_phases(pair, 1.0, pair.speed, dt);
        const double dur_err = percent_error(el.duration, t_c);
        std::printf(" %s |\n", cell(dur_err, 11).c_str());
        sweep.push_back({{"steps_per_contact", n},
                         {"timestep_s", dt},
                         {"restitution", rest},
                         {"undamped",
                          {{"duration_s", number_or_null(el.duration)},
                           {"duration_error_percent", number_or_null(dur_err)},
                           {"restitution", number_or_null(el.restitution)}}}});
        rows.push_back(std::move(row));
    }

    std::printf("\nSpread of the restitution error over the impact phases (min..max, %%):\n\n");
    std::printf("| steps/contact |");
    print_e_header(restitutions, 14);
    std::printf("\n|--------------:|");
    print_e_rule(restitutions, 14);
    std::printf("\n");
    for (const Row& row : rows) {
        std::printf("| %13ld |", row.n);
        for (std::size_t k = 0; k < restitutions.size(); ++k) {
            const double e = restitutions[k];
            std::printf(" %s |", spread_cell(percent_error(row.damped[k].restitution_min, e),
                                             percent_error(row.damped[k].restitution_max, e), 14)
                                     .c_str());
        }
        std::printf("\n");
    }

    // The automatic step for a scene of these grains: safety x critical time at the default
    // characteristic speed, and what it resolves at a range of actual impact speeds.
    const double characteristic_speed = 1.0;
    const double safety = Scene{}.timestep_safety;  // the scene default of run.timestep_safety
    const TimestepLimits lim = timestep_limits(pair_system(pair, 0.5), characteristic_speed);
    const double dt_auto = safety * lim.critical;
    std::printf(
        "\nDefault automatic step: %g x critical time %.4g s (%s; Rayleigh %.4g s, Hertz at %g m/s %.4g s) "
        "= %.4g s.\n",
        safety, lim.critical, lim.limiting.c_str(), lim.rayleigh, characteristic_speed, lim.hertz, dt_auto);
    std::printf("Collisions of this pair run at that step, restitution error (%%, mean over phases):\n\n");
    std::printf("| impact speed (m/s) | t_c (s)   | steps/contact |");
    print_e_header(restitutions, 8);
    std::printf("\n|-------------------:|----------:|--------------:|");
    print_e_rule(restitutions, 8);
    std::printf("\n");
    nlohmann::json impacts = nlohmann::json::array();
    for (const double v : {0.01, 0.1, 1.0}) {
        const double tc_v = pc.contact_duration(v);
        std::printf("| %18g | %9.3g | %13.1f |", v, tc_v, tc_v / dt_auto);
        nlohmann::json rest = nlohmann::json::array();
        for (const double e : restitutions) {
            const PhaseAveraged r = collide_phases(pair, e, v, dt_auto);
            rest.push_back(restitution_json(e, r));
            std::printf(" %s |", cell(percent_error(r.restitution, e), 8).c_str());
        }
        std::printf("\n");
        impacts.push_back({{"impact_speed", v},
                           {"contact_duration_s", tc_v},
                           {"steps_per_contact", tc_v / dt_auto},
                           {"restitution", rest}});
    }

    if (!json_out.empty()) {
        const nlohmann::json out = {
            {"benchmark", "restitution"},
            {"pair",
             {{"radius", pair.radius},
              {"density", pair.density},
              {"youngs_modulus", pair.youngs},
              {"poisson_ratio", pair.poisson},
              {"friction", pair.friction},
              {"impact_speed", pair.speed},
              {"reduced_mass", pc.reduced_mass},
              {"reduced_radius", pc.reduced_radius},
              {"effective_youngs", pc.effective_youngs},
              {"contact_duration_s", t_c}}},
            {"impact_phases", kPhases},
            {"sweep", sweep},
            {"default_step",
             {{"timestep_safety", safety},
              {"characteristic_speed", characteristic_speed},
              {"rayleigh_s", lim.rayleigh},
              {"hertz_s", lim.hertz},
              {"critical_s", lim.critical},
              {"limiting", lim.limiting},
              {"timestep_s", dt_auto},
              {"impacts", impacts}}},
        };
        write_json_file(json_out, out);
    }
}

}  // namespace

void add_bench_commands(CLI::App& bench, int& exit_status) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* contact = bench.add_subcommand("contact", "Hertz-Mindlin contact engine: grain-steps per second");
    contact->add_option("--grains", args->grains, "Number of grains")
        ->check(CLI::Range(11L, 10000000L))
        ->capture_default_str();
    contact->add_option("--steps", args->steps, "Timed steps")
        ->check(CLI::Range(1L, 100000000L))
        ->capture_default_str();
    contact->add_option("--threads", args->threads, "OpenMP threads")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    contact->add_option("--write-data", args->write_data,
                        "Also write the initial state as a LAMMPS data file (for LIGGGHTS)");
    contact->add_option("--json", args->json_out, "Write the figures as JSON here");
    contact->callback([args, &exit_status] {
        // Checked before the benchmark: found at its end, a bad path lost the run.
        if (!args->json_out.empty()) prepare_output_file(args->json_out, "--json");
        if (!args->write_data.empty()) prepare_output_file(args->write_data, "--write-data", {args->json_out});
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
        advance_steps(s, args->steps);
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
            // For a cross-check of the physics against LIGGGHTS on the same state.
            {"kinetic_energy_final_J", energy(s).translational},
            {"rotational_energy_final_J", energy(s).rotational},
        };
        std::printf(
            "bench contact: %zu grains, %ld steps, %d thread(s): %.3g grain-steps/s, %.3f core-us per grain-step "
            "(%.2f contacts and %.2f listed neighbours per grain, %ld list builds)\n",
            s.particles.size(), args->steps, args->threads, grain_steps / wall,
            wall * args->threads * 1e6 / grain_steps, out["contacts_per_grain"].get<double>(),
            out["neighbour_pairs_per_grain"].get<double>(), s.contacts.builds());
        if (!args->json_out.empty()) write_json_file(args->json_out, out);
        exit_status = 0;
    });

    auto restitution_json = std::make_shared<std::string>();
    CLI::App* restitution = bench.add_subcommand(
        "restitution", "Accuracy of the time step: realised restitution and contact duration vs steps per contact");
    restitution->add_option("--json", *restitution_json, "Write the figures as JSON here");
    restitution->callback([restitution_json, &exit_status] {
        if (!restitution_json->empty()) prepare_output_file(*restitution_json, "--json");
        run_restitution_bench(*restitution_json);
        exit_status = 0;
    });

    add_magnetic_bench_commands(bench, exit_status);
    add_flow_bench_command(bench, exit_status);
    add_sphere_pair_bench_command(bench, exit_status);
    add_sphere_pair_fem_bench_command(bench, exit_status);
    add_gravity_bench_command(bench, exit_status);
}

}  // namespace mrjam::cli
