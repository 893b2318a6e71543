#include "shear/shear_cell.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/exit_status.hpp"
#include "core/format.hpp"
#include "integrator.hpp"
#include "io/checkpoint.hpp"
#include "io/snapshot.hpp"
#include "magnetic/magnetic_model.hpp"
#include "observers.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "shear/block_average.hpp"
#include "shear/dimensionless.hpp"
#include "shear/field_sweep.hpp"
#include "shear/shear_analysis.hpp"
#include "shear/shear_progress.hpp"
#include "shear/shear_stress.hpp"
#include "shear/steady_state.hpp"
#include "timestep.hpp"

namespace mrjam {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The study's cell: its field and its ladder (the field sweep's cells are studies of their own,
// shear/field_sweep.hpp).
struct CellPlan {
    std::string name;         // "main"
    double flux_density = 0;  // T
    std::vector<double> wall_speeds, rates, strains;
    std::vector<long> steps;  // fixed steps per rate (0: from the strain)
};

std::vector<CellPlan> plan_of(const ShearSpec& spec) {
    CellPlan main;
    main.name = "main";
    main.flux_density = spec.flux_density;
    main.wall_speeds = spec.wall_speeds;
    main.rates = spec.rates;
    for (std::size_t k = 0; k < spec.rates.size(); ++k) {
        main.strains.push_back(k == 0 ? spec.strain_first : spec.strain_per_rate);
        main.steps.push_back(spec.steps_first > 0 ? (k == 0 ? spec.steps_first : spec.steps_per_rate) : 0);
    }
    return {main};
}

std::string checkpoint_path(const ShearSpec& spec, const ShearOptions& o) {
    if (!o.checkpoint_path.empty()) return o.checkpoint_path;
    return (std::filesystem::path(spec.output.directory) / "shear_checkpoint.mrjam").string();
}

// The engine's refusals name engine-scene paths; give the user the shear-scene key instead.
[[noreturn]] void rethrow_as_shear(const SceneError& e) {
    std::string message = e.what();
    const std::string prefix = e.path() + ": ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    throw SceneError(shear_path_of(e.path()), message);
}

// The speed of the cells a command stepped, summed over their runs (each run's wall time leaves
// out the packing of its grains); null rates when no cell stepped (a study resumed at its end).
struct CellSpeed {
    RunSpeed total;

    void add(const RunSpeed& cell) {
        total.steps_run += cell.steps_run;
        total.grain_steps += cell.grain_steps;
        total.wall_s += cell.wall_s;
    }

    nlohmann::json summary(int threads) const {
        if (total.grain_steps > 0 && total.wall_s > 0) return performance_json(total, std::max(1, threads));
        return {{"steps_run", total.steps_run}, {"grain_steps_per_s", nullptr}, {"core_us_per_grain_step", nullptr}};
    }
};

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

// A study: its cells one after another, each a scene the runner steps through its stages (the
// magnetisation, then one stage per rate), with this class's observer sampling the chains and
// the stresses and its typed progress in every checkpoint.
class Study {
public:
    Study(const ShearSpec& spec, const ShearOptions& options) : spec_(spec), options_(options), cells_(plan_of(spec)) {}

    // Resumed: the progress and, inside a cell, the engine state and the runner's position.
    void resume(const std::string& path) {
        const CheckpointHeader header = read_checkpoint_header(path);
        const nlohmann::json& state = header.history.at("state");
        progress_ = StudyProgress::from_json(state.at("progress"));
        resumed_ = true;
        if (!progress_.current) return;  // between cells: the next starts fresh
        BuildOptions build;
        build.threads = options_.threads;
        build.insert_grains = false;
        scene_ = std::make_unique<Scene>(build_scene(header.resolved_scene, build));
        restore_scene(path, *scene_);
        resume_at_ = header.position;
        resumed_stage_log_ = header.history.at("stage_log");
    }

    ShearOutcome run() {
        t0_ = Clock::now();
        install_interrupt_handler();
        prepare_output_directory(spec_.output.directory, "/output/directory");
        check_checkpoint_path(checkpoint_path(spec_, options_), "/output/directory");
        ShearOutcome out;
        for (std::size_t c = progress_.cells.size(); c < cells_.size() && out.status == "complete"; ++c) {
            RunOutcome cell;
            try {
                cell = run_cell(c);
            } catch (const SetupInterrupted&) {
                // Ctrl-C while a later cell packs its grains: the finished cells are in the last
                // checkpoint (written at the end of each of their stages), so report them and
                // stop as an interrupt; before any cell there is nothing to keep.
                if (c == 0) throw;
                cell.exit_status = kExitInterrupted;
            }
            if (cell.exit_status == kExitInterrupted) {
                out.status = "interrupted";
                out.exit_status = kExitInterrupted;
                out.checkpoint = checkpoint_path(spec_, options_);
                if (options_.progress)
                    std::fprintf(stderr, "[%s] interrupted; checkpoint written to %s\n", options_.label.c_str(),
                                 out.checkpoint.c_str());
            } else if (cell.exit_status != 0) {
                out.status = "failed";
                out.error = cell.report.value("error", std::string("the run failed"));
                out.exit_status = cell.exit_status;
            } else {
                finish_cell(c);
            }
            speed_.add(cell.speed);
        }
        nlohmann::json field_sweep;
        if (out.status == "complete" && !spec_.sweep_fields.empty()) field_sweep = run_fields(out);
        if (out.status == "complete") discard_checkpoint(checkpoint_path(spec_, options_));
        const nlohmann::json current = progress_.current ? progress_.current->to_json() : nlohmann::json(nullptr);
        out.results = summarise(spec_, progress_.cells, current, field_sweep);
        out.engine = progress_.engine;
        out.wall_time = seconds_since(t0_);
        out.performance = speed_.summary(scene_ ? scene_->system.threads : options_.threads);
        return out;
    }

private:
    // The field sweep, once the main ladder is done; its fields as far as they got. The main
    // cell's checkpoint stays until the sweep is done, so --resume on it continues the sweep.
    nlohmann::json run_fields(ShearOutcome& out) {
        const FieldSweepOutcome fields = run_field_sweep(spec_, options_, resumed_);
        if (fields.exit_status == kExitInterrupted) {
            out.status = "interrupted";
            out.exit_status = kExitInterrupted;
            out.checkpoint = checkpoint_path(spec_, options_);
            if (options_.progress)
                std::fprintf(stderr, "[%s] interrupted in the field sweep; resume with the checkpoint %s\n",
                             options_.label.c_str(), out.checkpoint.c_str());
        } else if (fields.exit_status != 0) {
            out.status = "failed";
            out.error = fields.error;
            out.exit_status = fields.exit_status;
        }
        return fields.rows;
    }

    // A strain or a magnetisation that needs more steps than any run could take is a unit or an
    // exponent gone wrong (a strain of 1e12 ran, showing "step 0/2.3e17"), or a step the damping
    // has shrunk: refused as run mode refuses a stage's duration.
    void check_step_counts(const CellPlan& plan) const {
        const double dt = scene_->system.dt;
        const std::string cause = ": check it, or what sets the step (" + scene_->limits.limiting + ")";
        for (std::size_t k = 0; k < plan.rates.size(); ++k) {
            const double steps = plan.strains[k] / plan.rates[k] / dt;
            if (plan.steps[k] == 0 && !(steps <= kMostSteps))
                throw SceneError(ladder_length_key(k, false), "needs " + format_number(steps, 2) + " steps of " +
                                                                  format_number(dt, 3) + " s at " +
                                                                  format_number(plan.rates[k]) + " 1/s, more than " +
                                                                  format_number(kMostSteps) + cause);
            // Fewer steps than stress samples: the window holds one or two samples and a zero error.
            const bool fixed = plan.steps[k] > 0;
            const double taken = fixed ? static_cast<double>(plan.steps[k]) : steps;
            if (taken < spec_.samples_per_rate)
                throw SceneError(ladder_length_key(k, fixed),
                                 "gives " + format_number(taken, 2) + " steps of " + format_number(dt, 3) + " s at " +
                                     format_number(plan.rates[k]) + " 1/s, fewer than the " +
                                     std::to_string(spec_.samples_per_rate) +
                                     " stress samples of /measure/samples_per_rate (one a step at most): raise it, "
                                     "lower the rate or the samples");
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
    }

    // Cell c from its start, or from the checkpoint resume() read.
    RunOutcome run_cell(std::size_t c) {
        ProtocolPosition start;
        nlohmann::json stage_log;
        if (progress_.current && progress_.current->cell == c && scene_) {
            start = resume_at_;
            stage_log = resumed_stage_log_;
        } else {
            build_cell(c);
            progress_.current = CellProgress{};
            progress_.current->cell = c;
            progress_.current->grains = scene_->system.particles.size();
            progress_.current->timestep = scene_->system.dt;
        }
        // The first cell's engine scene and step, for the report; kept in the progress (so in the
        // checkpoint), since a study resumed past its first cell never builds it.
        if (c == 0) progress_.engine = engine_info();
        set_up_stages(c);
        RunOptions run;
        run.mode = options_.label;
        run.progress = options_.progress;
        run.resumed_stage_log = stage_log;
        run.stage_finished = [this](const System&, std::size_t k) { return k == 0 && progress_.current->settled; };
        run.checkpoint_state = [this] { return checkpoint_state(); };
        run.checkpoint_each_stage = true;  // a finished rate is never redone
        return run_protocol(*scene_, run, start, [this, c](const System& s, std::size_t k, long i) {
            if (k == 0)
                observe_magnetisation(s, i);
            else
                observe_rate(s, c, k - 1, i);
        });
    }

    nlohmann::json engine_info() const {
        return {{"inputs", scene_->resolved},
                {"fidelity", scene_->fidelity},
                {"threads", scene_->system.threads},
                {"timestep",
                 {{"used_s", scene_->system.dt},
                  {"critical_s", scene_->limits.critical},
                  {"limiting", scene_->limits.limiting},
                  {"hertz_s", scene_->limits.hertz}}}};
    }

    nlohmann::json checkpoint_state() const {
        return {{"shear_input", spec_.input}, {"tier", spec_.tier}, {"progress", progress_.to_json()}};
    }

    // The cell's stages: the magnetisation (checked every check_every, ended when settled), then a
    // stage per rate (sampled samples_per_rate times), and where the runner writes and reports.
    void set_up_stages(std::size_t c) {
        const CellPlan& plan = cells_[c];
        const double dt = scene_->system.dt;
        char label[96];
        std::snprintf(label, sizeof label, "cell %zu/%zu (%.0f mT)", c + 1, cells_.size(), plan.flux_density * 1e3);
        scene_->stages.clear();
        Stage magnetise;
        magnetise.name = std::string(label) + ": magnetising";
        magnetise.steps = static_cast<long>(std::ceil(spec_.magnetise_max / dt));
        magnetise.observe_every = std::max(1L, static_cast<long>(std::llround(spec_.magnetise_check_every / dt)));
        scene_->stages.push_back(magnetise);
        for (std::size_t k = 0; k < plan.rates.size(); ++k) {
            Stage rate;
            rate.name = std::string(label) + ": rate " + std::to_string(k + 1) + "/" +
                        std::to_string(plan.rates.size()) + " (" + format_number(plan.rates[k], 4) + " 1/s)";
            rate.steps = plan.steps[k] > 0
                             ? plan.steps[k]
                             : std::max(1L, static_cast<long>(std::ceil(plan.strains[k] / plan.rates[k] / dt)));
            rate.observe_every = std::max(1L, rate.steps / spec_.samples_per_rate);
            rate.keep_forces = true;  // a rate changes settings only; the first prepares after freezing
            rate.on_start = [this, k, v = plan.wall_speeds[k]](System& s, bool fresh) { start_rate(s, k, v, fresh); };
            scene_->stages.push_back(rate);
        }
        scene_->output = output_plan(spec_.output);
        scene_->output.checkpoint_path = checkpoint_path(spec_, options_);
    }

    // Magnetisation criterion: at every check, the contacts per grain and the mean |cos| of
    // contact normals to the field are recorded; the chains have settled when, over the last
    // `window` checks, each varies by less than `tolerance` of its mean (and min_duration has
    // passed). max_duration stops it regardless, and the report says so.
    void observe_magnetisation(const System& s, long step_in_stage) {
        CellProgress& cur = *progress_.current;
        cur.max_overlap = std::max(cur.max_overlap, s.contact_stats.max_overlap_ratio);
        cur.magnetise_steps = step_in_stage;
        const ChainState cs = chain_state(s, spec_.field_direction);
        cur.magnetise_log.push_back({s.time, cs.contacts_per_grain, cs.mean_abs_cos});
        const long min_steps = static_cast<long>(std::ceil(spec_.magnetise_min / s.dt));
        const auto window = static_cast<std::size_t>(spec_.magnetise_window);
        if (step_in_stage < min_steps || cur.magnetise_log.size() < window) return;
        auto spread = [&](double MagnetiseCheck::*value) {
            double lo = 1e300, hi = -1e300, sum = 0;
            for (std::size_t k = cur.magnetise_log.size() - window; k < cur.magnetise_log.size(); ++k) {
                const double v = cur.magnetise_log[k].*value;
                lo = std::min(lo, v);
                hi = std::max(hi, v);
                sum += v;
            }
            const double mean = sum / window;
            return mean > 0 ? (hi - lo) / mean : 0.0;
        };
        cur.settled = spread(&MagnetiseCheck::contacts_per_grain) < spec_.magnetise_tolerance &&
                      spread(&MagnetiseCheck::mean_abs_cos) < spec_.magnetise_tolerance;
    }

    // The magnetisation's record, once it has ended (settled or at max_duration).
    void record_magnetisation(const System& s) {
        CellProgress& cur = *progress_.current;
        const ChainState cs = chain_state(s, spec_.field_direction);
        cur.magnetisation = {
            {"settled", cur.settled},
            {"max_overlap_ratio_seen", cur.max_overlap},
            {"duration_s", cur.magnetise_steps * s.dt},
            {"steps", cur.magnetise_steps},
            {"contacts_per_grain", cs.contacts_per_grain},
            {"mean_abs_cos_to_field", cs.mean_abs_cos},
            {"criterion", "contacts per grain and mean |cos| of contact normals to the field each vary by less than " +
                              format_number(spec_.magnetise_tolerance) + " of their mean over the last " +
                              format_number(spec_.magnetise_window) + " checks, one every " +
                              format_number(spec_.magnetise_check_every) + " s, after at least " +
                              format_number(spec_.magnetise_min) + " s; at most " + format_number(spec_.magnetise_max) +
                              " s"}};
        if (!cur.settled && options_.progress)
            std::fprintf(stderr, "[%s] warning: chains had not settled after %.3g s (max_duration); shearing anyway\n",
                         options_.label.c_str(), cur.magnetise_steps * s.dt);
    }

    // Rate k's start: the first ends the magnetisation and freezes the rafts; every rate sets its
    // boundaries and flow (again on resume: the checkpoint does not hold the flow).
    void start_rate(System& s, std::size_t k, double wall_speed, bool fresh) {
        if (fresh) {
            CellProgress& cur = *progress_.current;
            if (k == 0) {
                record_magnetisation(s);
                freeze(s);
            }
            cur.upper.clear();
            cur.lower.clear();
            cur.bulk.clear();
            cur.max_overlap = 0;
            if (spec_.lees_edwards) step_affine_profile(s, 2 * wall_speed / spec_.cell.z);
        }
        apply_rate(s, wall_speed);
        rate_started_ = Clock::now();
    }

    // The top and bottom layers (grain centres within raft_thickness of a wall) become rafts.
    void freeze(System& s) const {
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

    // A Lees-Edwards rate starts with every grain on the new affine profile (its x velocity changed
    // by the change of rate times its height from the centre), as the sliding images are at once.
    // Started from rest, the grains next to the boundary would meet images moving at rate x Z
    // (the whole box's velocity difference) instead of rate x d, a collision the step was not
    // chosen for. Applied once per rate (fresh), not on resume: the checkpoint holds the velocities.
    static void step_affine_profile(System& s, double new_rate) {
        const double z_mid = 0.5 * (s.domain.lo.z + s.domain.hi.z);
        const double height = s.domain.hi.z - s.domain.lo.z;
        const double change = new_rate - s.domain.shear_velocity / height;
        for (std::size_t i = 0; i < s.particles.size(); ++i)
            s.particles.velocity[i].x += change * (s.particles.position[i].z - z_mid);
    }

    void apply_rate(System& s, double v) const {
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

    // A stress sample (every total/samples_per_rate steps and at the rate's last), and at its last
    // step the rate's record.
    void observe_rate(const System& s, std::size_t c, std::size_t k, long step_in_stage) {
        CellProgress& cur = *progress_.current;
        cur.max_overlap = std::max(cur.max_overlap, s.contact_stats.max_overlap_ratio);
        ShearStress st;
        if (spec_.lees_edwards) {
            // No rafts: the flow-curve stress is the virial of the whole periodic box.
            st.bulk = st.upper = lees_edwards_stress(s);
        } else {
            st = shear_stress(s, 1, 0, wall_index(s, "top"), wall_index(s, "bottom"), spec_.raft_thickness,
                              spec_.cell.z - spec_.raft_thickness);
        }
        cur.upper.push_back(st.upper);
        if (!spec_.lees_edwards) cur.lower.push_back(st.lower);
        cur.bulk.push_back(st.bulk);
        if (step_in_stage == scene_->stages[k + 1].steps) record_rate(s, c, k, step_in_stage);
    }

    void record_rate(const System& s, std::size_t c, std::size_t k, long total) {
        CellProgress& cur = *progress_.current;
        const CellPlan& plan = cells_[c];
        auto window = [&](const std::vector<double>& all) {
            const std::size_t keep =
                std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(all.size() * spec_.window_fraction)));
            return block_average(std::vector<double>(all.end() - std::min(keep, all.size()), all.end()), spec_.blocks);
        };
        const BlockAverage up = window(cur.upper), bulk = window(cur.bulk);
        // Where the stress settles (MSER), against where the averaged window starts: a series still
        // drifting into the window biases the mean, and the report says so.
        const double strain = total * s.dt * plan.rates[k];
        const Settling settling = settling_of(cur.upper, strain, up);
        nlohmann::json rate = {{"rate_1_s", plan.rates[k]},
                               {"wall_speed_m_s", plan.wall_speeds[k]},
                               {"steps", total},
                               {"strain", strain},
                               {"steady_from_strain", settling.strain},
                               {"steady_before_window", settling.before_window},
                               {"drift_in_window_Pa", settling.drift.change},
                               {"drift_error_Pa", settling.drift.error},
                               {"drifting_in_window", settling.drifting},
                               {"sample_every_steps", scene_->stages[k + 1].observe_every},
                               {"stress_Pa", up.mean},
                               {"error_Pa", up.error},
                               {"blocks", up.blocks},
                               {"samples_averaged", up.samples},
                               {"stress_source", spec_.lees_edwards ? "virial of the Lees-Edwards box" : "upper raft"},
                               {"bulk_stress_Pa", bulk.mean},
                               {"bulk_error_Pa", bulk.error},
                               {"series_upper_Pa", cur.upper},
                               {"max_overlap_ratio_seen", cur.max_overlap},
                               {"wall_time_s", seconds_since(rate_started_)}};
        add_dimensionless(s, plan, k, up.mean, rate);
        if (!spec_.lees_edwards) {
            const BlockAverage lo = window(cur.lower);
            rate["lower_raft_stress_Pa"] = lo.mean;
            rate["lower_raft_error_Pa"] = lo.error;
        }
        cur.rates.push_back(rate);
        if (options_.progress)
            std::fprintf(stderr, "[%s] rate %.4g 1/s: stress %.4g +- %.2g kPa (%s)\n", options_.label.c_str(),
                         plan.rates[k], up.mean * 1e-3, up.error * 1e-3,
                         spec_.lees_edwards ? "Lees-Edwards virial" : "upper raft");
        if (!settling.steady() && options_.progress) warn_unsettled(k, settling, strain);
    }

    // What a rheologist compares flow curves by (shear/dimensionless.hpp), and the structure at the
    // rate's end: contacts per grain and how closely their normals follow the field.
    void add_dimensionless(const System& s, const CellPlan& plan, std::size_t k, double stress,
                           nlohmann::json& rate) const {
        const double beta = clausius_mossotti(s.materials.at(0).relative_permeability);
        const double scale = magnetic_stress_scale(plan.flux_density, beta);
        const double mason = mason_number(spec_.viscosity, plan.rates[k], plan.flux_density, beta);
        rate["mason_number"] = std::isfinite(mason) ? nlohmann::json(mason) : nlohmann::json();
        rate["magnetic_stress_scale_Pa"] = scale;
        rate["stress_over_magnetic_scale"] = scale > 0 ? nlohmann::json(stress / scale) : nlohmann::json();
        const ChainState cs = chain_state(s, spec_.field_direction);
        rate["contacts_per_grain"] = cs.contacts_per_grain;
        rate["mean_abs_cos_to_field"] = cs.mean_abs_cos;
    }

    // A rate not steady in its averaged window (settling inside it, or still drifting through it):
    // its mean holds part of the transient, and the warning names the key to raise.
    void warn_unsettled(std::size_t k, const Settling& settling, double strain) const {
        const std::string advice =
            unsettled_advice(ladder_length_key(k, spec_.steps_first > 0), settling, strain, spec_.window_fraction);
        if (settling.drifting)
            std::fprintf(stderr,
                         "[%s] warning: rate %zu: the stress still drifts by %.3g +- %.2g kPa across the averaged "
                         "window (the last %.0f %% of %.3g strain); its mean is not a steady stress: %s\n",
                         options_.label.c_str(), k + 1, settling.drift.change * 1e-3, settling.drift.error * 1e-3,
                         100 * spec_.window_fraction, strain, advice.c_str());
        else
            std::fprintf(stderr,
                         "[%s] warning: rate %zu: the stress settles %.3g strain into the rate, inside the averaged "
                         "window (the last %.0f %% of %.3g); its mean holds part of the transient: %s\n",
                         options_.label.c_str(), k + 1, settling.strain, 100 * spec_.window_fraction, strain,
                         advice.c_str());
    }

    static int wall_index(const System& s, const std::string& name) {
        for (std::size_t k = 0; k < s.walls.size(); ++k)
            if (s.walls[k].name == name) return static_cast<int>(k);
        return -1;
    }

    // A finished cell: its record joins the study's, and (unless it was the last) a checkpoint
    // between cells keeps it.
    void finish_cell(std::size_t c) {
        const CellProgress& cur = *progress_.current;
        const System& s = scene_->system;
        nlohmann::json done = {
            {"name", cells_[c].name}, {"flux_density_T", cells_[c].flux_density}, {"grains", s.particles.size()},
            {"timestep_s", s.dt},     {"rafts", nlohmann::json::array()},         {"magnetisation", cur.magnetisation},
            {"rates", cur.rates}};
        for (const Raft& r : s.rafts) done["rafts"].push_back({{"name", r.name}, {"grains", r.members}});
        progress_.cells.push_back(done);
        progress_.current.reset();
        // The study is complete: run() deletes the checkpoint. Before a field sweep it is kept
        // between the cells, so a resume goes on to the sweep.
        if (c + 1 == cells_.size() && spec_.sweep_fields.empty()) return;
        const nlohmann::json history = {
            {"mode", options_.label}, {"stage_log", nlohmann::json::array()}, {"state", checkpoint_state()}};
        write_checkpoint(checkpoint_path(spec_, options_), scene_->resolved, s,
                         ProtocolPosition{scene_->stages.size(), 0, false}, history);
    }

    const ShearSpec& spec_;
    ShearOptions options_;
    std::vector<CellPlan> cells_;
    StudyProgress progress_;
    std::unique_ptr<Scene> scene_;
    ProtocolPosition resume_at_;
    nlohmann::json resumed_stage_log_;
    bool resumed_ = false;
    CellSpeed speed_;
    Clock::time_point t0_, rate_started_;
};
}  // namespace

ShearOutcome run_shear_study(const ShearSpec& spec, const ShearOptions& options) {
    Study study(spec, options);
    return study.run();
}

ShearOutcome resume_shear_study(const std::string& checkpoint, const ShearOptions& options, ShearSpec& spec_out) {
    const CheckpointHeader header = read_checkpoint_header(checkpoint);
    if (header.history.contains("shear_input"))  // the progress as a JSON object of its own, before the run loop
        throw SceneError("--resume", checkpoint +
                                         " was written by an older mrjam (a shear checkpoint of before the shared "
                                         "run loop); rerun the study from its scene");
    const nlohmann::json* state =
        header.history.is_object() && header.history.contains("state") ? &header.history["state"] : nullptr;
    if (!state || !state->contains("shear_input"))
        throw SceneError("--resume", checkpoint + " is not a shear checkpoint (it was written by another mode)");
    spec_out = read_shear_spec((*state)["shear_input"], (*state)["tier"].get<std::string>());
    Study study(spec_out, options);
    study.resume(checkpoint);
    return study.run();
}

}  // namespace mrjam
