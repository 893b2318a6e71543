#include "shear/shear_cell.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/format.hpp"
#include "integrator.hpp"
#include "io/checkpoint.hpp"
#include "observers.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "shear/block_average.hpp"
#include "shear/shear_analysis.hpp"
#include "shear/shear_stress.hpp"
#include "timestep.hpp"

namespace mrjam {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// One cell of a study: its field and its ladder.
struct CellPlan {
    std::string name;         // "main" or "field_sweep"
    double flux_density = 0;  // T
    std::vector<double> wall_speeds, rates, strains;
    std::vector<long> steps;               // fixed steps per rate (0: from the strain)
    std::vector<std::string> strain_keys;  // the scene key each strain came from, for refusals
};

std::vector<CellPlan> plan_of(const ShearSpec& spec) {
    std::vector<CellPlan> cells;
    CellPlan main;
    main.name = "main";
    main.flux_density = spec.flux_density;
    main.wall_speeds = spec.wall_speeds;
    main.rates = spec.rates;
    for (std::size_t k = 0; k < spec.rates.size(); ++k) {
        main.strains.push_back(k == 0 ? spec.strain_first : spec.strain_per_rate);
        main.steps.push_back(spec.steps_first > 0 ? (k == 0 ? spec.steps_first : spec.steps_per_rate) : 0);
        main.strain_keys.push_back(k == 0 ? "/ladder/strain_first" : "/ladder/strain_per_rate");
    }
    cells.push_back(main);
    for (double b : spec.sweep_fields) {
        // As the source's field runs: shear first at the ladder's top rate (strain_first) to build
        // the sheared structure, then measure at the sweep rate; the stress of a cell sheared from
        // rest is still rising (at 600 mT and 100 1/s, half the pre-sheared value after a strain of 0.05).
        CellPlan c;
        c.name = "field_sweep";
        c.flux_density = b;
        if (spec.rates.front() > spec.sweep_rate) {
            c.rates.push_back(spec.rates.front());
            c.strains.push_back(spec.steps_first > 0 ? 0.0 : spec.strain_first);
            c.steps.push_back(spec.steps_first > 0 ? spec.steps_first : 0);
            c.strain_keys.push_back("/ladder/strain_first");
        }
        c.rates.push_back(spec.sweep_rate);
        c.strains.push_back(spec.sweep_strain);
        c.steps.push_back(0);
        c.strain_keys.push_back("/field_sweep/strain");
        for (double g : c.rates) c.wall_speeds.push_back(0.5 * g * spec.gap());
        cells.push_back(c);
    }
    return cells;
}

std::string checkpoint_path(const ShearSpec& spec, const ShearOptions& o) {
    if (!o.checkpoint_path.empty()) return o.checkpoint_path;
    return (std::filesystem::path(spec.output_directory) / "shear_checkpoint.mrjam").string();
}

// The engine's refusals name engine-scene paths; give the user the shear-scene key instead.
[[noreturn]] void rethrow_as_shear(const SceneError& e) {
    std::string message = e.what();
    const std::string prefix = e.path() + ": ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    throw SceneError(shear_path_of(e.path()), message);
}

}  // namespace

void check_engine_accepts(const ShearSpec& spec) {
    BuildOptions build;
    build.insert_grains = false;
    try {
        build_scene(engine_scene(spec, spec.flux_density), build);
    } catch (const SceneError& e) {
        rethrow_as_shear(e);
    }
}

namespace {

class Study {
public:
    Study(const ShearSpec& spec, const ShearOptions& options) : spec_(spec), options_(options), cells_(plan_of(spec)) {}

    // Fresh study: the progress record starts empty.
    void start() {
        progress_ = {{"shear_input", spec_.input},
                     {"tier", spec_.tier},
                     {"cells", nlohmann::json::array()},
                     {"current", nullptr}};
    }

    // Resumed: the progress record and the engine state come from the checkpoint.
    void resume(const std::string& path) {
        const CheckpointHeader header = read_checkpoint_header(path);
        progress_ = header.history;
        BuildOptions build;
        build.threads = options_.threads;
        build.insert_grains = false;
        scene_ = std::make_unique<Scene>(build_scene(header.resolved_scene, build));
        restore_scene(path, *scene_);
        resumed_ = true;
    }

    ShearOutcome run() {
        t0_ = last_checkpoint_ = last_progress_ = Clock::now();
        install_interrupt_handler();
        prepare_output_directory(spec_.output_directory, "/output/directory");
        check_checkpoint_path(checkpoint_path(spec_, options_), "/output/directory");
        ShearOutcome out;
        try {
            for (std::size_t c = progress_["cells"].size(); c < cells_.size(); ++c) {
                if (!run_cell(c)) {
                    out.status = "interrupted";
                    out.exit_status = 130;
                    out.checkpoint = checkpoint_path(spec_, options_);
                    write_checkpoint_now();
                    if (options_.progress)
                        std::fprintf(stderr, "[%s] interrupted; checkpoint written to %s\n", options_.label.c_str(),
                                     out.checkpoint.c_str());
                    break;
                }
            }
        } catch (const BlowUp& e) {
            out.status = "failed";
            out.error = e.what();
            out.exit_status = 3;
        }
        if (out.status == "complete") discard_checkpoint(checkpoint_path(spec_, options_));
        out.results = summarise(spec_, progress_["cells"], progress_["current"]);
        out.engine = progress_.value("engine", nlohmann::json());
        out.wall_time = seconds_since(t0_);
        return out;
    }

private:
    // A strain or a magnetisation that needs more steps than any run could take is a unit or an
    // exponent gone wrong (a strain of 1e12 ran, showing "step 0/2.3e17"), or a step the damping
    // has shrunk: refused as run mode refuses a stage's duration.
    void check_step_counts(const CellPlan& plan) const {
        const double dt = scene_->system.dt;
        const std::string cause = ": check it, or what sets the step (" + scene_->limits.limiting + ")";
        for (std::size_t k = 0; k < plan.rates.size(); ++k) {
            const double steps = plan.strains[k] / plan.rates[k] / dt;
            if (plan.steps[k] == 0 && !(steps <= kMostSteps))
                throw SceneError(plan.strain_keys[k], "needs " + format_number(steps, 2) + " steps of " +
                                                          format_number(dt, 3) + " s at " +
                                                          format_number(plan.rates[k]) + " 1/s, more than " +
                                                          format_number(kMostSteps) + cause);
        }
        if (!(spec_.magnetise_max / dt <= kMostSteps))
            throw SceneError("/magnetise/max_duration", "needs " + format_number(spec_.magnetise_max / dt, 2) +
                                                            " steps of " + format_number(dt, 3) + " s, more than " +
                                                            format_number(kMostSteps) + cause);
    }

    // Builds cell c's engine scene (fresh grains) and checks the cell against the grains drawn.
    void build_cell(std::size_t c) {
        BuildOptions build;
        build.threads = options_.threads;
        try {
            scene_ = std::make_unique<Scene>(build_scene(engine_scene(spec_, cells_[c].flux_density), build));
            // Lees-Edwards: the box built periodic in z starts sliding (offset 0, at rest until
            // the first rate); a checkpoint carries the flag and the offset.
            scene_->system.domain.lees_edwards = spec_.lees_edwards;
            choose_timestep(*scene_);
        } catch (const SceneError& e) {
            rethrow_as_shear(e);
        }
        check_step_counts(cells_[c]);
        double d_max = 0;
        for (double r : scene_->system.particles.radius) d_max = std::max(d_max, 2 * r);
        // Chains must span several grains between the rafts, or the cell measures single grains
        // wedged between two walls.
        if (spec_.gap() < 2.5 * d_max)
            throw SceneError(
                "/cell/size",
                (spec_.lees_edwards ? "the height of the Lees-Edwards cell (" : "the gap between the rafts (") +
                    format_number(spec_.gap() * 1e6) + " um) must hold at least 2.5 of the largest grain drawn (" +
                    format_number(d_max * 1e6) + " um); make the cell higher" +
                    (spec_.lees_edwards ? "" : " or the rafts thinner (/cell/raft_thickness)"));
        prepare(scene_->system);
    }

    // false: interrupted (state saved by the caller).
    bool run_cell(std::size_t c) {
        const CellPlan& plan = cells_[c];
        nlohmann::json& cur = progress_["current"];
        if (!resumed_ || cur.is_null()) {
            build_cell(c);
            cur = {{"cell", c},
                   {"phase", "magnetise"},
                   {"magnetise_log", nlohmann::json::array()},
                   {"magnetise_steps", 0},
                   {"rate_index", 0},
                   {"step_in_rate", 0},
                   {"rates", nlohmann::json::array()},
                   {"samples",
                    {{"upper", nlohmann::json::array()},
                     {"lower", nlohmann::json::array()},
                     {"bulk", nlohmann::json::array()}}},
                   {"grains", scene_->system.particles.size()},
                   {"timestep_s", scene_->system.dt}};
        }
        resumed_ = false;
        // The first cell's engine scene and step, for the report; kept in the progress record
        // (so in the checkpoint), since a study resumed past its first cell never builds it.
        if (c == 0) {
            progress_["engine"] = {{"inputs", scene_->resolved},
                                   {"fidelity", scene_->fidelity},
                                   {"timestep",
                                    {{"used_s", scene_->system.dt},
                                     {"critical_s", scene_->limits.critical},
                                     {"limiting", scene_->limits.limiting},
                                     {"hertz_s", scene_->limits.hertz}}}};
        }
        System& s = scene_->system;
        if (cur["phase"] == "magnetise") {
            if (!magnetise(c)) return false;
            freeze();
            cur["phase"] = "shear";
        }
        for (std::size_t k = cur["rate_index"].get<std::size_t>(); k < plan.rates.size(); ++k) {
            if (!shear_rate(c, k)) return false;
            cur["rate_index"] = k + 1;
            cur["step_in_rate"] = 0;
            write_checkpoint_now();  // a finished rate is never redone
        }
        nlohmann::json done = {
            {"name", plan.name},    {"flux_density_T", plan.flux_density}, {"grains", s.particles.size()},
            {"timestep_s", s.dt},   {"rafts", nlohmann::json::array()},    {"magnetisation", cur["magnetisation"]},
            {"rates", cur["rates"]}};
        for (const Raft& r : s.rafts) done["rafts"].push_back({{"name", r.name}, {"grains", r.members}});
        progress_["cells"].push_back(done);
        cur = nullptr;
        write_checkpoint_now();
        return true;
    }

    // Steps `count` steps in chunks small enough to keep progress and Ctrl-C responsive.
    bool step(long count, const std::string& what) {
        System& s = scene_->system;
        while (count > 0) {
            const long chunk = std::min(count, 200L);
            advance_steps(s, chunk);
            count -= chunk;
            // The largest overlap seen (sampled at chunk ends): the report shows how far the soft
            // contacts were pushed.
            max_overlap_ = std::max(max_overlap_, s.contact_stats.max_overlap_ratio);
            if (interrupt_requested()) return false;
            if (seconds_since(last_checkpoint_) > spec_.checkpoint_every_seconds) write_checkpoint_now();
            if (options_.progress && seconds_since(last_progress_) > spec_.progress_interval) {
                std::fprintf(stderr, "[%s] %s; t = %.4g s, step %ld, %.0f s elapsed\n", options_.label.c_str(),
                             what.c_str(), s.time, s.step, seconds_since(t0_));
                last_progress_ = Clock::now();
            }
        }
        return true;
    }

    // Magnetisation criterion: every check_every, the contacts per grain and the mean |cos| of
    // contact normals to the field are recorded; the chains have settled when, over the last
    // `window` checks, each varies by less than `tolerance` of its mean (and min_duration has
    // passed). max_duration stops it regardless, and the report says so.
    bool magnetise(std::size_t c) {
        System& s = scene_->system;
        nlohmann::json& cur = progress_["current"];
        const long check_steps = std::max(1L, static_cast<long>(std::llround(spec_.magnetise_check_every / s.dt)));
        const long max_steps = static_cast<long>(std::ceil(spec_.magnetise_max / s.dt));
        const long min_steps = static_cast<long>(std::ceil(spec_.magnetise_min / s.dt));
        nlohmann::json& log = cur["magnetise_log"];
        max_overlap_ = 0;
        long done = cur["magnetise_steps"].get<long>();
        bool settled = false;
        while (done < max_steps) {
            const long n = std::min(check_steps - done % check_steps, max_steps - done);
            char what[160];
            std::snprintf(what, sizeof what, "cell %zu/%zu (%.0f mT): magnetising", c + 1, cells_.size(),
                          cells_[c].flux_density * 1e3);
            const long before = s.step;
            const bool ok = step(n, what);
            done += s.step - before;
            cur["magnetise_steps"] = done;
            // A check due at this step is made even when Ctrl-C came: the resumed run starts past
            // it and would otherwise never make it (and might settle at another time).
            if (done % check_steps != 0 && done < max_steps) {
                if (!ok) return false;
                continue;
            }
            const ChainState cs = chain_state(s, spec_.field_direction);
            log.push_back(
                {{"time_s", s.time}, {"contacts_per_grain", cs.contacts_per_grain}, {"mean_abs_cos", cs.mean_abs_cos}});
            if (done >= min_steps && static_cast<int>(log.size()) >= spec_.magnetise_window) {
                auto spread = [&](const char* key) {
                    double lo = 1e300, hi = -1e300, sum = 0;
                    for (std::size_t k = log.size() - spec_.magnetise_window; k < log.size(); ++k) {
                        const double v = log[k][key].get<double>();
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                        sum += v;
                    }
                    const double mean = sum / spec_.magnetise_window;
                    return mean > 0 ? (hi - lo) / mean : 0.0;
                };
                if (spread("contacts_per_grain") < spec_.magnetise_tolerance &&
                    spread("mean_abs_cos") < spec_.magnetise_tolerance) {
                    settled = true;
                    break;
                }
            }
            if (!ok) return false;
        }
        const ChainState cs = chain_state(s, spec_.field_direction);
        cur["magnetisation"] = {
            {"settled", settled},
            {"max_overlap_ratio_seen", max_overlap_},
            {"duration_s", done * s.dt},
            {"steps", done},
            {"contacts_per_grain", cs.contacts_per_grain},
            {"mean_abs_cos_to_field", cs.mean_abs_cos},
            {"criterion", "contacts per grain and mean |cos| of contact normals to the field each vary by less than " +
                              format_number(spec_.magnetise_tolerance) + " of their mean over the last " +
                              format_number(spec_.magnetise_window) + " checks, one every " +
                              format_number(spec_.magnetise_check_every) + " s, after at least " +
                              format_number(spec_.magnetise_min) + " s; at most " + format_number(spec_.magnetise_max) +
                              " s"}};
        if (!settled && options_.progress)
            std::fprintf(stderr, "[%s] warning: chains had not settled after %.3g s (max_duration); shearing anyway\n",
                         options_.label.c_str(), done * s.dt);
        return true;
    }

    // The top and bottom layers (grain centres within raft_thickness of a wall) become rafts.
    void freeze() {
        System& s = scene_->system;
        s.rafts.clear();
        if (spec_.lees_edwards) return;  // no rafts: the sliding images shear the cell
        s.rafts.push_back(Raft{"lower", {}, {}, 0});
        s.rafts.push_back(Raft{"upper", {}, {}, 0});
        for (std::size_t i = 0; i < s.particles.size(); ++i) {
            const double z = s.particles.position[i].z;
            s.particles.raft[i] = -1;
            if (z < spec_.raft_thickness) {
                s.particles.raft[i] = 0;
                ++s.rafts[0].members;
            } else if (z > spec_.cell.z - spec_.raft_thickness) {
                s.particles.raft[i] = 1;
                ++s.rafts[1].members;
            }
        }
        prepare(s);
    }

    // Settings of rate k (re-applied on resume: the checkpoint does not hold the flow).
    void apply_rate(double v) {
        System& s = scene_->system;
        if (spec_.lees_edwards) {
            // The image above moves at rate Z = 2 v (v = rate Z / 2, the "wall speed" of the
            // ladder); the fluid follows the affine profile through the whole periodic height.
            s.domain.shear_velocity = 2 * v;
            s.flow = std::make_shared<SimpleShearFlow>(0, 2, 2 * v / spec_.cell.z, 0.5 * spec_.cell.z);
            return;
        }
        s.rafts[0].velocity = Vec3{-v, 0, 0};
        s.rafts[1].velocity = Vec3{v, 0, 0};
        for (Wall& w : s.walls) w.velocity = Vec3{w.name == "top" ? v : -v, 0, 0};
        // Linear from -v at the lower raft's inner face to +v at the upper's, constant beyond
        // (fig. 2.4): the rafts and the fluid inside them move together, so they feel no drag.
        s.flow = std::make_shared<CouetteFlow>(2, spec_.raft_thickness, spec_.cell.z - spec_.raft_thickness,
                                               Vec3{-v, 0, 0}, Vec3{v, 0, 0});
    }

    bool shear_rate(std::size_t c, std::size_t k) {
        System& s = scene_->system;
        const CellPlan& plan = cells_[c];
        nlohmann::json& cur = progress_["current"];
        apply_rate(plan.wall_speeds[k]);
        const long total = plan.steps[k] > 0
                               ? plan.steps[k]
                               : std::max(1L, static_cast<long>(std::ceil(plan.strains[k] / plan.rates[k] / s.dt)));
        const long every = std::max(1L, total / spec_.samples_per_rate);
        long i = cur["step_in_rate"].get<long>();
        if (i == 0)
            cur["samples"] = {{"upper", nlohmann::json::array()},
                              {"lower", nlohmann::json::array()},
                              {"bulk", nlohmann::json::array()}};
        const auto t_rate = Clock::now();
        max_overlap_ = 0;
        while (i < total) {
            const long n = std::min(every - i % every, total - i);
            char what[200];
            std::snprintf(what, sizeof what,
                          "cell %zu/%zu (%.0f mT): rate %zu/%zu (%.4g 1/s), step %ld/%ld, last stress %.4g kPa", c + 1,
                          cells_.size(), plan.flux_density * 1e3, k + 1, plan.rates.size(), plan.rates[k], i, total,
                          cur["samples"]["upper"].empty() ? 0.0 : cur["samples"]["upper"].back().get<double>() * 1e-3);
            const long before = s.step;
            const bool ok = step(n, what);
            i += s.step - before;
            cur["step_in_rate"] = i;
            // A sample due at this step is taken even when Ctrl-C came, before the checkpoint:
            // the resumed run starts past it and would otherwise lose it.
            if (i % every == 0 || i == total) {
                ShearStress st;
                if (spec_.lees_edwards) {
                    // No rafts: the flow-curve stress is the virial of the whole periodic box.
                    st.bulk = st.upper = lees_edwards_stress(s);
                } else {
                    st = shear_stress(s, 1, 0, wall_index("top"), wall_index("bottom"), spec_.raft_thickness,
                                      spec_.cell.z - spec_.raft_thickness);
                }
                cur["samples"]["upper"].push_back(st.upper);
                if (!spec_.lees_edwards) cur["samples"]["lower"].push_back(st.lower);
                cur["samples"]["bulk"].push_back(st.bulk);
            }
            if (!ok) return false;
        }
        auto window = [&](const char* key) {
            const auto all = cur["samples"][key].get<std::vector<double>>();
            const std::size_t keep =
                std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(all.size() * spec_.window_fraction)));
            return block_average(std::vector<double>(all.end() - std::min(keep, all.size()), all.end()), spec_.blocks);
        };
        const BlockAverage up = window("upper"), bulk = window("bulk");
        nlohmann::json rate = {{"rate_1_s", plan.rates[k]},
                               {"wall_speed_m_s", plan.wall_speeds[k]},
                               {"steps", total},
                               {"strain", total * s.dt * plan.rates[k]},
                               {"sample_every_steps", every},
                               {"stress_Pa", up.mean},
                               {"error_Pa", up.error},
                               {"blocks", up.blocks},
                               {"samples_averaged", up.samples},
                               {"stress_source", spec_.lees_edwards ? "virial of the Lees-Edwards box" : "upper raft"},
                               {"bulk_stress_Pa", bulk.mean},
                               {"bulk_error_Pa", bulk.error},
                               {"series_upper_Pa", cur["samples"]["upper"]},
                               {"max_overlap_ratio_seen", max_overlap_},
                               {"wall_time_s", seconds_since(t_rate)}};
        if (!spec_.lees_edwards) {
            const BlockAverage lo = window("lower");
            rate["lower_raft_stress_Pa"] = lo.mean;
            rate["lower_raft_error_Pa"] = lo.error;
        }
        cur["rates"].push_back(rate);
        if (options_.progress)
            std::fprintf(stderr, "[%s] rate %.4g 1/s: stress %.4g +- %.2g kPa (%s)\n", options_.label.c_str(),
                         plan.rates[k], up.mean * 1e-3, up.error * 1e-3,
                         spec_.lees_edwards ? "Lees-Edwards virial" : "upper raft");
        return true;
    }

    int wall_index(const std::string& name) const {
        const auto& w = scene_->system.walls;
        for (std::size_t k = 0; k < w.size(); ++k)
            if (w[k].name == name) return static_cast<int>(k);
        return -1;
    }

    void write_checkpoint_now() {
        if (!scene_) return;
        write_checkpoint(checkpoint_path(spec_, options_), scene_->resolved, scene_->system, ProtocolPosition{},
                         progress_);
        last_checkpoint_ = Clock::now();
    }

    const ShearSpec& spec_;
    ShearOptions options_;
    std::vector<CellPlan> cells_;
    nlohmann::json progress_;
    std::unique_ptr<Scene> scene_;
    bool resumed_ = false;
    double max_overlap_ = 0;
    Clock::time_point t0_, last_checkpoint_, last_progress_;
};

}  // namespace

ShearOutcome run_shear_study(const ShearSpec& spec, const ShearOptions& options) {
    Study study(spec, options);
    study.start();
    return study.run();
}

ShearOutcome resume_shear_study(const std::string& checkpoint, const ShearOptions& options, ShearSpec& spec_out) {
    const CheckpointHeader header = read_checkpoint_header(checkpoint);
    if (!header.history.contains("shear_input"))
        throw SceneError("--resume", checkpoint + " is not a shear checkpoint (it was written by another mode)");
    spec_out = read_shear_spec(header.history["shear_input"], header.history["tier"].get<std::string>());
    Study study(spec_out, options);
    study.resume(checkpoint);
    return study.run();
}

}  // namespace mrjam
