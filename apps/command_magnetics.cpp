// `mrjam magnetics SCENE.json --report R.json [--field-map MAP] [--fidelity TIER]`: the field
// an EPM valve puts into its fluid (magnetics/), with a picture of |B| on the mid-plane and,
// on request, a field map the DEM engine reads.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <iostream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "io/svg_raster.hpp"
#include "magnetic/external_field.hpp"
#include "magnetics/field_picture.hpp"
#include "magnetics/getdp_problem.hpp"
#include "magnetics/magnetics_scene.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

namespace fs = std::filesystem;
using namespace mrjam::magnetics;

namespace {

struct MagneticsArgs {
    std::string scene;
    std::string report = "magnetics_report.json";
    std::string field_map;
    std::string fidelity = "standard";
    bool quiet = false;
};

// The picture beside the report: REPORT_B_midplane.svg, with its PNG twin.
fs::path picture_path(const std::string& report) {
    fs::path p(report);
    return p.parent_path() / (p.stem().string() + "_B_midplane.svg");
}

nlohmann::json results_json(const EpmField& f, const MagneticsScene& scene) {
    nlohmann::json r{{"mean_B_active_T", f.mean_b_active},
                     {"max_B_active_T", f.max_b_active},
                     {"mean_B_inactive_T", f.mean_b_inactive},
                     {"uniformity_cv", f.uniformity}};
    // The 2D model and the circuit see the throat's cross-section: an area, not a volume.
    if (f.field_model == FieldModel::full_3d)
        r["active_fluid_volume_m3"] = f.active_volume;
    else
        r["active_fluid_area_m2"] = f.active_volume;
    if (f.field_model == FieldModel::circuit) {
        r["gradient_B2_active_mean_T2_per_m"] = nullptr;
        r["gradient_B2_active_max_T2_per_m"] = nullptr;
    } else {
        r["gradient_B2_active_mean_T2_per_m"] = f.gradient_b2_mean;
        r["gradient_B2_active_max_T2_per_m"] = f.gradient_b2_max;
    }
    const SourceFigure ref = source_figure(scene);
    if (ref.tesla > 0) {
        const double ours = ref.region == "active" ? f.mean_b_active : f.mean_b_inactive;
        r["source_comparison"] = {{"what", ref.what},
                                  {"source_T", ref.tesla},
                                  {"this_model_T", ours},
                                  {"relative_difference", (ours - ref.tesla) / ref.tesla}};
    }
    return r;
}

}  // namespace

void add_magnetics_command(CLI::App& app, int& exit_status) {
    auto args = std::make_shared<MagneticsArgs>();
    CLI::App* cmd = app.add_subcommand("magnetics", "Field of an EPM valve (gmsh + GetDP, or the circuit estimate)");
    cmd->add_option("scene", args->scene, "Magnetics scene JSON (see docs/magnetics.md)")->required();
    cmd->add_option("--report", args->report, "Where to write the JSON report")->capture_default_str();
    CLI::Option* field_map = cmd->add_option("--field-map", args->field_map,
                                             "Also write B on a grid over the fluid (mrjam-fieldmap format)");
    cmd->add_option("--fidelity", args->fidelity, "quick (2D), standard (3D) or paper (3D, fine mesh); the scene wins")
        ->check(CLI::IsMember(magnetics_tier_names()))
        ->capture_default_str();
    cmd->add_flag("--quiet", args->quiet, "No progress lines on stderr");
    cmd->callback([args, field_map, &exit_status] {
        const auto start = std::chrono::steady_clock::now();
        // A solve can take minutes: what it would write is checked before it.
        prepare_output_file(args->report, "--report", {args->scene});
        if (field_map->count() > 0)
            prepare_output_file(args->field_map, "--field-map",
                                {args->scene, args->report});  // "" is refused, not "none"
        MagneticsScene scene = read_magnetics_scene(read_json_file(args->scene), args->fidelity);
        const bool fem = scene.request.field_model != FieldModel::circuit;
        if (!args->field_map.empty() && !fem)
            throw SceneError("/model", "the circuit model gives no field map; use \"2d\" or \"3d\" with --field-map");
        // Checked before the mesh, and named as the scene's key (a file in the way was a raw
        // filesystem error, exit 1, once the solver tried to clear its work directory).
        prepare_output_directory(scene.output_directory, "/output/directory");
        if (fem && find_getdp().empty()) {
            std::cerr << "error: getdp was not found on PATH; install it with `apt-get install getdp` "
                         "(bash scripts/install-deps.sh installs everything)\n";
            exit_status = kExitBadInput;
            return;
        }
        fs::path output = scene.output_directory;
        scene.request.work_dir = output / "solver";
        if (!args->quiet)
            std::cerr << "[magnetics] " << variant_name(scene.request.model.bracket.variant) << " " << scene.state
                      << ", model " << field_model_name(scene.request.field_model) << " (tier " << scene.tier
                      << "): meshing and solving in " << scene.request.work_dir.string() << "\n";
        // Ctrl-C reaches gmsh or GetDP too, which then fail or stop early: either way the field is
        // not to be reported (exit 130, nothing written).
        install_interrupt_handler();
        auto interrupted = [&] {
            if (!interrupt_requested()) return false;
            std::cerr << "[magnetics] interrupted during the solve; no report written\n";
            exit_status = kExitInterrupted;
            return true;
        };
        EpmField field;
        try {
            field = compute_epm_field(scene.request);
        } catch (const SolverError& e) {
            if (interrupted()) return;
            std::cerr << "error: " << e.what() << "\n  mesh: fluid_size " << scene.request.mesh.fluid_size * 1e3
                      << " mm, device_size " << scene.request.mesh.device_size * 1e3 << " mm; no report written\n";
            exit_status = kExitError;
            return;
        }

        if (interrupted()) return;
        nlohmann::json report;
        report["mrjam_version"] = MRJAM_VERSION;
        report["mode"] = "magnetics";
        report["status"] = "done";
        report["scene_file"] = args->scene;
        report["inputs"] = scene.resolved;
        report["fidelity"] = {{"tier", scene.tier},
                              {"model", field_model_name(field.field_model)},
                              {"mesh", scene.resolved.value("mesh", nlohmann::json::object())}};
        report["results"] = results_json(field, scene);
        report["mesh"] = {{"nodes", field.mesh_nodes},
                          {"elements", field.mesh_elements},
                          {"unknowns", field.unknowns},
                          {"solver_iterations", field.solver_iterations}};
        report["notes"] = field.notes;
        nlohmann::json outputs = nlohmann::json::object();
        for (const std::string& file : {args->report, args->field_map})
            if (!file.empty() && fs::path(file).has_parent_path()) fs::create_directories(fs::path(file).parent_path());
        if (fem && has_midplane_picture(field)) {
            const fs::path svg = picture_path(args->report);
            write_midplane_picture(field, "Flux density the magnet puts into the fluid", svg.string());
            outputs["picture"] = png_twin(svg.string());
            outputs["picture_svg"] = svg.string();
        }
        if (!args->field_map.empty()) {
            const FieldGrid& g = field.fluid_map;
            FieldMap(g.count, g.origin, g.spacing, g.values).write(args->field_map);
            outputs["field_map"] = args->field_map;
            outputs["field_map_grid"] = {{"count", g.count},
                                         {"origin_m", {g.origin.x, g.origin.y, g.origin.z}},
                                         {"spacing_m", {g.spacing.x, g.spacing.y, g.spacing.z}}};
        }
        report["outputs"] = outputs;
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        report["timing"] = {{"mesh_s", field.mesh_seconds}, {"solve_s", field.solve_seconds}, {"wall_s", total}};
        write_json_file(args->report, report);
        if (fem && !scene.keep_solver_files) fs::remove_all(scene.request.work_dir);
        if (!args->quiet)
            std::cerr << "[magnetics] mean |B| in the active fluid " << field.mean_b_active * 1e3
                      << " mT, inactive gap " << field.mean_b_inactive * 1e3 << " mT (" << total << " s); report "
                      << args->report << "\n";
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
