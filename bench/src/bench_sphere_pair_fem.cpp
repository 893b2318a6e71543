// `mrjam-bench sphere-pair-fem`: the force between two touching-to-close iron spheres with the
// iron's saturation, by axisymmetric finite elements (magnetics/sphere_pair_fem), beside the exact
// linear two-sphere force and the point dipoles'. Not a timing: the table the saturating
// close-pair force is built from, and its check against the linear solution.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "magnetics/sphere_pair_fem.hpp"
#include "run/runner.hpp"
#include "scene/scene_parts.hpp"

namespace mrjam::cli {

namespace {

struct SpherePairFemArgs {
    magnetics::SpherePairFemRequest base;
    std::vector<double> fields{1e5};  // A/m
    std::vector<double> gaps{0.1, 0.03, 0.01};
    bool linear = false;
    std::string work_dir = "sphere_pair_fem";
    std::string json_out;
    std::string table_out;
};

// The grid as C++ arrays for lib/engine/magnetic/saturating_pair_table.inc (rows per field).
void write_table_source(const SpherePairFemArgs& args, const std::vector<magnetics::SpherePairFemResult>& results) {
    std::FILE* f = std::fopen(args.table_out.c_str(), "w");
    if (!f) throw std::runtime_error("cannot write " + args.table_out);
    std::fprintf(
        f,
        "// Written by `mrjam-bench sphere-pair-fem --table-out` (magnetics/sphere_pair_fem: axisymmetric\n"
        "// finite elements, Frohlich-Kennelly iron, refinement %g, truncation radius %g radii). Do not edit.\n",
        args.base.refinement, args.base.outer_radius);
    std::fprintf(f, "constexpr double kSatPermeability = %.17g;\n", args.base.relative_permeability);
    const auto list = [&](const char* name, const std::vector<double>& v, double unit) {
        std::fprintf(f, "constexpr double %s[] = {", name);
        for (std::size_t i = 0; i < v.size(); ++i) std::fprintf(f, "%s%.17g", i ? ", " : "", v[i] / unit);
        std::fprintf(f, "};\n");
    };
    list("kSatGaps", args.gaps, 1.0);
    list("kSatFieldsOverMs", args.fields, args.base.saturation_magnetisation);
    const auto grid = [&](const char* name, double magnetics::SpherePairFemResult::*member) {
        std::fprintf(f, "constexpr double %s[][%zu] = {\n", name, args.gaps.size());
        for (std::size_t h = 0; h < args.fields.size(); ++h) {
            std::fprintf(f, "    {");
            for (std::size_t g = 0; g < args.gaps.size(); ++g)
                std::fprintf(f, "%s%.10g", g ? ", " : "", results[h * args.gaps.size() + g].*member);
            std::fprintf(f, "},\n");
        }
        std::fprintf(f, "};\n");
    };
    grid("kSatForce", &magnetics::SpherePairFemResult::force_coefficient);
    grid("kSatPolarisability", &magnetics::SpherePairFemResult::polarisability);
    std::fclose(f);
}

void run_sphere_pair_fem_bench(const SpherePairFemArgs& args) {
    nlohmann::json rows = nlohmann::json::array();
    std::printf("axial force on touching-to-close spheres: coefficient = F / (mu0 H0^2 a^2), negative attracts\n");
    std::printf("%10s %8s %12s %12s %12s %10s %9s %9s %8s %8s %6s\n", "H0 (A/m)", "gap", "FEM", "exact lin.", "dipoles",
                "FEM/dip.", "alpha FEM", "alpha lin", "B_gap(T)", "unknowns", "s");
    const double mu = args.base.relative_permeability;
    std::vector<magnetics::SpherePairFemResult> results;
    for (double h : args.fields) {
        for (double gap : args.gaps) {
            auto request = args.base;
            request.applied_field = h;
            request.gap = gap;
            request.saturating = !args.linear;
            const auto fem = magnetics::solve_sphere_pair_fem(request, args.work_dir);
            const auto exact_response = converged_sphere_pair_response(mu, 2 + gap, PairOrientation::axial);
            const double exact = 2 * std::numbers::pi * exact_response.dpolarisability_ds;
            const double dipoles = 2 * std::numbers::pi *
                                   mutual_dipole_pair_response(mu, 2 + gap, PairOrientation::axial).dpolarisability_ds;
            std::printf("%10.4g %8.3g %12.5g %12.5g %12.5g %10.4f %9.4f %9.4f %8.3f %8d %6.1f\n", h, gap,
                        fem.force_coefficient, exact, dipoles, fem.force_coefficient / dipoles, fem.polarisability,
                        exact_response.polarisability, fem.max_gap_flux_density, fem.unknowns, fem.seconds);
            std::fflush(stdout);
            results.push_back(fem);
            rows.push_back({{"applied_field_A_m", h},
                            {"gap_radii", gap},
                            {"fem_force_coefficient", fem.force_coefficient},
                            {"exact_linear_force_coefficient", exact},
                            {"mutual_dipole_force_coefficient", dipoles},
                            {"fem_polarisability", fem.polarisability},
                            {"exact_linear_polarisability", exact_response.polarisability},
                            {"max_gap_flux_density_T", fem.max_gap_flux_density},
                            {"unknowns", fem.unknowns},
                            {"newton_steps", fem.newton_steps}});
        }
    }
    if (!args.table_out.empty()) write_table_source(args, results);
    if (!args.json_out.empty())
        write_json_file(args.json_out, {{"benchmark", "sphere-pair-fem"},
                                        {"relative_permeability", mu},
                                        {"saturation_magnetisation_A_m", args.base.saturation_magnetisation},
                                        {"saturating", !args.linear},
                                        {"refinement", args.base.refinement},
                                        {"rows", rows}});
}

}  // namespace

void add_sphere_pair_fem_bench_command(CLI::App& bench, int& exit_status) {
    auto args = std::make_shared<SpherePairFemArgs>();
    CLI::App* pair = bench.add_subcommand(
        "sphere-pair-fem", "Saturating two-sphere force by finite elements (gmsh + GetDP) beside the linear ones");
    pair->add_option("--field", args->fields, "Applied fields H0, A/m")->check(CLI::Range(1.0, 1e8));
    pair->add_option("--gap", args->gaps, "Surface gaps, in radii")->check(CLI::Range(1e-4, 10.0));
    pair->add_option("--permeability", args->base.relative_permeability, "Initial relative permeability of the iron")
        ->check(CLI::Range(1.01, 1e6))
        ->capture_default_str();
    pair->add_option("--saturation", args->base.saturation_magnetisation, "Saturation magnetisation M_s, A/m")
        ->check(CLI::Range(1.0, 1e8))
        ->capture_default_str();
    pair->add_option("--refinement", args->base.refinement, "Divide every element size by this")
        ->check(CLI::Range(0.25, 16.0))
        ->capture_default_str();
    pair->add_option("--outer-radius", args->base.outer_radius, "Truncation radius, in radii")
        ->check(CLI::Range(200.0, 1e6))
        ->capture_default_str();
    pair->add_flag("--linear", args->linear, "Linear iron (no saturation): checks the FEM against the exact solution");
    pair->add_option("--work-dir", args->work_dir, "Where the meshes and GetDP files go")->capture_default_str();
    pair->add_option("--json", args->json_out, "Write the table as JSON here");
    pair->add_option("--table-out", args->table_out,
                     "Write the grid as C++ arrays (lib/engine/magnetic/saturating_pair_table.inc); fields and gaps "
                     "ascending");
    pair->callback([args, &exit_status] {
        if (!args->table_out.empty() && (!std::is_sorted(args->fields.begin(), args->fields.end()) ||
                                         !std::is_sorted(args->gaps.begin(), args->gaps.end()) || args->linear))
            throw SceneError("--table-out",
                             "needs ascending --field and --gap lists and saturating iron (no --linear)");
        if (!args->json_out.empty()) prepare_output_file(args->json_out, "--json");
        run_sphere_pair_fem_bench(*args);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
