// `mrjam-bench flow`: what the valve's carrier-flow models cost per grain. The engine asks the
// flow for a velocity and a drag factor once per grain per step, and the coupled flow's
// controller bins all grains and solves its slices at every observation (50 steps by default),
// so the figures are ns per drag_at call (velocity and drag factor) and ns per grain per update, at points
// spread uniformly through the quick tier's 30x stretch (docs/benchmarks.md quotes them).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "fluid/valve_flow.hpp"
#include "jam/coupled_flow.hpp"
#include "run/runner.hpp"
#include "terms/drag_term.hpp"

namespace mrjam::cli {

namespace {

struct FlowBenchArgs {
    long points = 1000000;
    std::string json_out;
};

// Points uniform in the passage of the stretch (rejection from the bounding box), in a slab
// |x| < 66 um as the quick tier's.
std::vector<Vec3> passage_points(const ValveGeometry& v, long n, double half_slab) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> ux(-half_slab, half_slab), uy(-v.bore_radius(), v.bore_radius()),
        uz(-v.upstream_length, v.downstream_length);
    std::vector<Vec3> out;
    out.reserve(static_cast<std::size_t>(n));
    while (static_cast<long>(out.size()) < n) {
        const Vec3 p{ux(rng), uy(rng), uz(rng)};
        if (v.in_fluid(p)) out.push_back(p);
    }
    return out;
}

// ns per drag_at call (the velocity and the drag factor, as the drag pass asks), best of three passes.
double time_calls(const FlowField& f, const std::vector<Vec3>& points) {
    double best = 1e300, sink = 0;
    for (int pass = 0; pass < 3; ++pass) {
        const auto t0 = std::chrono::steady_clock::now();
        for (const Vec3& p : points) {
            const FlowField::Drag d = f.drag_at(p, 0);
            sink += d.velocity.z * d.factor;
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        best = std::min(best, s);
    }
    if (sink == 1.2345) std::printf(" ");  // keeps the loop from being optimised away
    return best * 1e9 / static_cast<double>(points.size());
}

}  // namespace

void add_flow_bench_command(CLI::App& bench, int& exit_status) {
    auto args = std::make_shared<FlowBenchArgs>();
    CLI::App* flow = bench.add_subcommand("flow", "Valve carrier flows: ns per drag_at call and per grain update");
    flow->add_option("--points", args->points, "Sample points (and grains for the coupled update)")
        ->check(CLI::Range(1000L, 100000000L))
        ->capture_default_str();
    flow->add_option("--json", args->json_out, "Write the figures as JSON here");
    flow->callback([args, &exit_status] {
        if (!args->json_out.empty()) prepare_output_file(args->json_out, "--json");
        ValveGeometry v;  // the 30x valve, quick tier's stretch
        v.upstream_length = 1.0e-3;
        v.downstream_length = 0.5e-3;
        const double half_slab = 66e-6;
        const auto points = passage_points(v, args->points, half_slab);
        nlohmann::json out = {{"benchmark", "flow"}, {"points", args->points}, {"valve", "30x, quick stretch"}};
        for (auto profile : {ValveFlow::Profile::source, ValveFlow::Profile::converging}) {
            const ValveFlow f(v, 0.273, profile, 0.224e-3);
            const double ns = time_calls(f, points);
            out["ns_per_call"][valve_flow_profile_name(profile)] = ns;
            std::printf("bench flow: %-10s %.1f ns per drag_at call (velocity and drag factor)\n",
                        valve_flow_profile_name(profile).c_str(), ns);
        }
        CoupledFlowSettings c;
        c.slab_half_thickness = half_slab;
        c.z_lo = -v.upstream_length;
        c.z_hi = v.downstream_length;
        c.cell_length = 88e-6;
        c.rings = 15;
        c.feed_fraction = 0.345;
        c.supply_pressure = 105e3;
        c.viscosity = 0.16;
        c.bore_speed = 0.273;
        c.wall_gap = 19e-6;
        c.jet_length = 0.224e-3;
        const CoupledFlow coupled(v, c);
        // Grains at the sample points, moving with the clear flow: one update per pass.
        System s;
        s.terms.add(std::make_unique<DragTerm>(c.viscosity, 1));
        for (const Vec3& p : points) {
            s.particles.position.push_back(p);
            s.particles.radius.push_back(19e-6);
            s.particles.velocity.push_back(coupled.field()->velocity(p, 0));
        }
        double best = 1e300;
        for (int pass = 0; pass < 3; ++pass) {
            const auto t0 = std::chrono::steady_clock::now();
            coupled.update(s);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        const double call = time_calls(*coupled.field(), points);
        const double update = best * 1e9 / static_cast<double>(points.size());
        out["ns_per_call"]["coupled"] = call;
        out["coupled_update_ns_per_grain"] = update;
        out["coupled_cells"] = coupled.cells();
        std::printf(
            "bench flow: %-10s %.1f ns per drag_at call; update %.1f ns per grain "
            "(%zu slice rings), every observation\n",
            "coupled", call, update, coupled.cells());
        if (!args->json_out.empty()) write_json_file(args->json_out, out);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
