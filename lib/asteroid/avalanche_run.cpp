#include "asteroid/avalanche_run.hpp"

#include <algorithm>
#include <cmath>

#include "asteroid/asteroid_outcome.hpp"
#include "asteroid/grain_material.hpp"
#include "asteroid/heap_profile.hpp"
#include "core/format.hpp"
#include "io/checkpoint.hpp"
#include "io/svg_plot.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

constexpr const char* kMode = "asteroid avalanche";

nlohmann::json wall(const char* name, const nlohmann::json& point, const nlohmann::json& normal) {
    return {{"name", name}, {"type", "plane"}, {"point", point}, {"normal", normal}};
}

// The engine scene: the cell (periodic across y), its floor, end walls and gate, the column
// packed behind the gate, gravity, the field switched on after the settling, and the stages.
nlohmann::json avalanche_engine_scene(const AvalancheSpec& s) {
    const double d = s.diameter, L = s.length * d, W = s.width * d, H = s.height * d, gate = s.gate * d;
    nlohmann::json material = grain_material_json("grain", s.material);
    material["cohesion_energy_density"] = s.cohesion_energy_density;
    material["relative_permeability"] = s.relative_permeability;
    material["saturation_magnetisation"] = s.saturation_magnetisation;
    nlohmann::json j = {
        {"mode", kMode},
        {"seed", s.seed},
        {"domain", {{"lo", {0.0, 0.0, 0.0}}, {"hi", {L, W, H}}, {"periodic", "y"}}},
        {"materials", {material}},
        {"contact",
         {{"model", "hertz_mindlin"},
          {"rolling", s.material.engine_rolling()},
          {"cohesion", s.cohesion_energy_density > 0 ? "sjkr" : "none"}}},
        {"gravity", {0.0, 0.0, -s.gravity}},
        {"walls",
         {wall("floor", {0.0, 0.0, 0.0}, {0, 0, 1}), wall("back", {0.0, 0.0, 0.0}, {1, 0, 0}),
          wall("end", {L, 0.0, 0.0}, {-1, 0, 0}), wall("gate", {gate, 0.0, 0.0}, {-1, 0, 0})}},
        {"grains",
         {{{"material", "grain"},
           {"size", {{"distribution", "single"}, {"diameter", d}}},
           {"placement",
            {{"method", "random"},
             {"volume_fraction", s.fill_fraction},
             {"region", {{"shape", "box"}, {"lo", {0.0, 0.0, 0.0}}, {"hi", {gate, W, s.fill_height * d}}}}}}}}},
        {"stages",
         {{{"name", "settling"}, {"duration", s.settle_time}},
          {{"name", "magnetising"}, {"duration", std::max(s.magnetise_time, 1e-12)}},
          {{"name", "running out"}, {"duration", s.runout_time}, {"remove_walls", {"gate"}}}}},
        {"run",
         {{"timestep_safety", s.timestep_safety},
          {"characteristic_speed", std::sqrt(2.0 * s.gravity * s.fill_height * d)}}},
        {"output", engine_output_json(s.output)}};
    if (s.field > 0)
        j["magnetic"] = {
            {"field", {{"type", "uniform"}, {"flux_density", {0.0, 0.0, s.field}}, {"switch_on", s.settle_time}}},
            {"mutual", s.mutual_dipoles ? "lagged" : "fixed"},
            {"cutoff", {{"diameters", 3}}}};
    return j;
}

double rms_speed(const Particles& p) {
    double v2 = 0;
    for (const Vec3& v : p.velocity) v2 += norm2(v);
    return p.size() ? std::sqrt(v2 / p.size()) : 0.0;
}

}  // namespace

namespace {

// Table 4.5 of the source: the angle of repose without and with a 5 mT field, by grain size.
nlohmann::json source_angles(double diameter) {
    struct Row {
        double d, off, on;
    };
    static const Row rows[] = {{0.005, 37.2209, 50.4837}, {0.01, 32.4847, 34.4926}, {0.05, 31.2953, 31.4193}};
    for (const Row& r : rows)
        if (std::fabs(diameter / r.d - 1.0) < 0.01)
            return {{"diameter_m", r.d}, {"field_off_deg", r.off}, {"field_5mT_deg", r.on}, {"table", "4.5"}};
    return nullptr;
}

class Avalanche {
public:
    Avalanche(AvalancheSpec spec, CoalesceOptions options) : spec_(std::move(spec)), options_(std::move(options)) {}

    void start_fresh() {
        BuildOptions build;
        build.threads = options_.threads;
        build.fidelity = options_.fidelity;
        scene_ = std::make_unique<Scene>(build_scene(avalanche_engine_scene(spec_), build));
        choose_timestep(*scene_);
        set_up_stages();
    }

    void resume(const std::string& path, const nlohmann::json& state, const CheckpointHeader& header) {
        BuildOptions build;
        build.threads = options_.threads;
        build.insert_grains = false;
        scene_ = std::make_unique<Scene>(build_scene(header.resolved_scene, build));
        restore_scene(path, *scene_);
        start_ = header.position;
        stage_log_ = header.history.at("stage_log");
        column_ = state.at("column");
        speeds_ = state.at("runout_speeds");
        set_up_stages();
    }

    CoalesceOutcome run();

private:
    // Observed 200 times a stage; the run-out ends once the grains are at rest, after at least a
    // fifth of its time (the gate's grains must have started moving).
    void set_up_stages() {
        for (Stage& st : scene_->stages) st.observe_every = std::max(1L, st.steps / 200);
    }

    void observe(const System& s, std::size_t stage, long step) {
        if (stage == 1 && step == scene_->stages[1].steps) {
            const HeapProfile column =
                measure_heap(s.particles, spec_.length * spec_.diameter, spec_.width * spec_.diameter,
                             spec_.gate * spec_.diameter, 2 * spec_.diameter);
            column_ = {{"grains", s.particles.size()}, {"height_m", column.peak}, {"volume_m3", column.volume}};
        }
        if (stage == 2) speeds_.push_back({s.time, rms_speed(s.particles)});
    }

    bool at_rest(const System& s, std::size_t stage) const {
        if (stage != 2) return false;
        const double started = spec_.settle_time + spec_.magnetise_time;
        return s.time - started >= 0.2 * spec_.runout_time && rms_speed(s.particles) < spec_.rest_speed;
    }

    nlohmann::json checkpoint_state() const {
        return {{"avalanche_input", spec_.resolved},
                {"fidelity", options_.fidelity},
                {"column", column_},
                {"runout_speeds", speeds_}};
    }

    void write_plot(const std::string& path, const HeapProfile& heap) const;

    AvalancheSpec spec_;
    CoalesceOptions options_;
    std::unique_ptr<Scene> scene_;
    ProtocolPosition start_;
    nlohmann::json stage_log_, column_;
    nlohmann::json speeds_ = nlohmann::json::array();
};

void Avalanche::write_plot(const std::string& path, const HeapProfile& heap) const {
    Plot plot;
    plot.title = "Heap side profile, " + format_number(spec_.field * 1e3, 3) + " mT (height exaggerated)";
    plot.x_label = "distance from the back wall (m)";
    plot.y_label = "surface height (m)";
    PlotSeries surface;
    surface.label = "surface (top of the highest grain per bin)";
    surface.x = heap.x;
    surface.y = heap.height;
    plot.series.push_back(surface);
    auto chord_line = [&](const FaceChord& c, const char* label, const char* colour, bool dashed) {
        if (!c.found) return;
        PlotSeries line;
        line.label = std::string(label) + ": " + std::to_string(c.angle_deg).substr(0, 4) + " deg";
        line.colour = colour;
        line.line = true;
        line.dashed = dashed;
        line.x = {c.x_high, c.x_low};
        line.y = {c.z_high, c.z_low};
        plot.series.push_back(line);
    };
    chord_line(heap.face, "angle of repose, 90-10 % of the plateau", "#d62728", false);
    chord_line(heap.face_upper, "upper, 90-50 %", "#ff7f0e", true);
    chord_line(heap.face_lower, "lower, 50-10 %", "#2ca02c", true);
    write_svg(path, plot);
}

CoalesceOutcome Avalanche::run() {
    RunOptions run;
    run.mode = kMode;
    run.scene_path = options_.scene_path;
    run.progress = options_.progress;
    run.resumed_stage_log = stage_log_;
    run.checkpoint_state = [this] { return checkpoint_state(); };
    run.checkpoint_each_stage = true;
    run.stage_finished = [this](const System& s, std::size_t k) { return at_rest(s, k); };
    const RunOutcome outcome =
        run_protocol(*scene_, run, start_, [this](const System& s, std::size_t k, long i) { observe(s, k, i); });
    CoalesceOutcome out;
    out.exit_status = outcome.exit_status;
    nlohmann::json& r = out.report;
    r = asteroid_report(outcome, kMode, spec_.resolved, options_.fidelity);
    const HeapProfile heap =
        measure_heap(scene_->system.particles, spec_.length * spec_.diameter, spec_.width * spec_.diameter,
                     spec_.gate * spec_.diameter, 2 * spec_.diameter);
    nlohmann::json& a = r["results"]["avalanche"];
    a = to_json(heap);
    a["column_before_runout"] = column_;
    a["runout_rms_speed"] = speeds_;
    a["at_rest"] = !speeds_.empty() && speeds_.back().at(1).get<double>() < spec_.rest_speed;
    a["rest_speed_m_s"] = spec_.rest_speed;
    a["source"] = source_angles(spec_.diameter);
    if (!options_.report_path.empty()) {
        const std::string svg = plot_beside(options_.report_path, "heap");
        write_plot(svg, heap);
        r["plots"] = {{"heap_profile", svg}};
        write_json_file(options_.report_path, r);
    }
    return out;
}

}  // namespace

CoalesceOutcome run_avalanche(const AvalancheSpec& spec, const CoalesceOptions& options) {
    return run_fresh<Avalanche>(spec, spec.output.directory, options);
}

CoalesceOutcome resume_avalanche(const std::string& checkpoint, const CoalesceOptions& options) {
    return run_resumed<Avalanche>(checkpoint, options, kMode, "avalanche_input", read_avalanche_spec);
}

}  // namespace mrjam
