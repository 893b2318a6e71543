// `mrjam-bench sphere-pair`: how far the point-dipole (mutual dipole) model the engine uses is
// from the exact force between two equal magnetisable spheres, as their gap closes. Not a
// timing: a table of the model's error (docs/magnetic_forces.md, "Close pairs"), from the exact
// multipole solution in lib/engine/magnetic/sphere_pair_exact.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "run/runner.hpp"
#include "scene/scene_parts.hpp"

namespace mrjam::cli {

namespace {

struct SpherePairArgs {
    std::vector<double> permeabilities{1000.0, 100.0, 10.0};
    std::vector<double> gaps{1.0, 0.3, 0.1, 0.03, 0.01};
    double tolerance = 1e-6;
    int max_order = 2048;
    std::string json_out;
};

void run_sphere_pair_bench(const SpherePairArgs& args) {
    nlohmann::json rows = nlohmann::json::array();
    std::printf(
        "exact two-sphere force over the converged mutual-dipole force (gap in radii; axial: field along\n"
        "the line of centres, attraction; transverse: across it, repulsion)\n");
    std::printf("%8s %8s %14s %14s %16s %6s\n", "mu_r", "gap", "axial ratio", "transv. ratio", "moment ratio ax.",
                "order");
    for (double mu : args.permeabilities) {
        for (double gap : args.gaps) {
            const double s = 2.0 + gap;
            const auto axial =
                converged_sphere_pair_response(mu, s, PairOrientation::axial, args.tolerance, args.max_order);
            const auto across =
                converged_sphere_pair_response(mu, s, PairOrientation::transverse, args.tolerance, args.max_order);
            const auto axial_dip = mutual_dipole_pair_response(mu, s, PairOrientation::axial);
            const auto across_dip = mutual_dipole_pair_response(mu, s, PairOrientation::transverse);
            const double axial_ratio = axial.dpolarisability_ds / axial_dip.dpolarisability_ds;
            const double across_ratio = across.dpolarisability_ds / across_dip.dpolarisability_ds;
            const double moment_ratio = axial.polarisability / axial_dip.polarisability;
            std::printf("%8.0f %8.3g %14.4f %14.4f %16.4f %6d\n", mu, gap, axial_ratio, across_ratio, moment_ratio,
                        std::max(axial.order, across.order));
            rows.push_back({{"relative_permeability", mu},
                            {"gap_radii", gap},
                            {"axial_force_ratio", axial_ratio},
                            {"transverse_force_ratio", across_ratio},
                            {"axial_moment_ratio", moment_ratio},
                            {"axial_force_coefficient", 2 * M_PI * axial.dpolarisability_ds},
                            {"transverse_force_coefficient", 2 * M_PI * across.dpolarisability_ds},
                            {"order", std::max(axial.order, across.order)}});
        }
    }
    std::printf("force = coefficient x mu0 H0^2 a^2 (a the radius, H0 the applied field)\n");
    if (!args.json_out.empty())
        write_json_file(args.json_out, {{"benchmark", "sphere-pair"}, {"tolerance", args.tolerance}, {"rows", rows}});
}

}  // namespace

void add_sphere_pair_bench_command(CLI::App& bench, int& exit_status) {
    auto args = std::make_shared<SpherePairArgs>();
    CLI::App* pair = bench.add_subcommand(
        "sphere-pair", "Exact two-sphere magnetic force against the point dipoles' as the gap closes (accuracy table)");
    pair->add_option("--permeability", args->permeabilities, "Relative permeabilities of the grains")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    pair->add_option("--gap", args->gaps, "Surface gaps, in radii")->check(CLI::PositiveNumber)->capture_default_str();
    pair->add_option("--tolerance", args->tolerance, "Relative change between orders that counts as converged")
        ->check(CLI::Range(1e-14, 1e-2))
        ->capture_default_str();
    pair->add_option("--max-order", args->max_order, "Highest multipole order tried (the cost grows as its cube)")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    pair->add_option("--json", args->json_out, "Write the table as JSON here");
    pair->callback([args, &exit_status] {
        // Relative permeability 1 is no magnetisation (every ratio 0/0), and gaps past these ends
        // are below the double's resolution of the centre distance or past any force worth tabling.
        for (double mu : args->permeabilities)
            if (!(mu > 1 && mu <= 1e7))
                throw SceneError("--permeability",
                                 "must be above 1 (a grain of permeability 1 is not magnetised) and at most 1e7, not " +
                                     format_number(mu));
        for (double gap : args->gaps)
            if (!(gap >= 1e-6 && gap <= 1e3))
                throw SceneError("--gap", "must be between 1e-6 and 1000 radii, not " + format_number(gap));
        if (!args->json_out.empty()) prepare_output_file(args->json_out, "--json");
        run_sphere_pair_bench(*args);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
