#include "run/runner.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "integrator.hpp"
#include "observers.hpp"
#include "run/interrupt.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

int raft_index(const System& s, const std::string& name) {
    for (std::size_t r = 0; r < s.rafts.size(); ++r)
        if (s.rafts[r].name == name) return static_cast<int>(r);
    return -1;
}

// Start-of-stage actions. Forming and releasing rafts changes membership, so it happens once;
// velocities and flows are settings and are re-applied when a run resumes mid-stage.
void start_stage(System& s, const Stage& st, bool membership_changes) {
    if (membership_changes) {
        for (const auto& name : st.release) {
            const int r = raft_index(s, name);
            if (r < 0)
                throw std::runtime_error("stage '" + st.name + "' releases raft '" + name +
                                         "', which was never formed");
            for (auto& m : s.particles.raft)
                if (m == r) m = -1;
            s.rafts[r].members = 0;
        }
        for (const auto& f : st.form_rafts) {
            int r = raft_index(s, f.name);
            if (r < 0) {
                s.rafts.push_back(Raft{f.name, f.velocity, {}, 0});
                r = static_cast<int>(s.rafts.size() - 1);
            }
            for (std::size_t i = 0; i < s.particles.size(); ++i) {
                // Positions are wrapped into a periodic box only when the neighbour list is
                // rebuilt; a grain that crossed a periodic face since then is judged by its image
                // inside the box, as the region means it.
                Vec3 x = s.particles.position[i];
                s.domain.wrap(x);
                bool inside = true;
                const Region& g = f.region;
                if (g.kind == Region::Kind::box) {
                    for (int k = 0; k < 3; ++k) inside = inside && x[k] >= g.lo[k] && x[k] <= g.hi[k];
                } else {
                    inside = g.contains_sphere(x, 0.0, s.domain);
                }
                if (inside && s.particles.raft[i] < 0) {
                    s.particles.raft[i] = static_cast<std::int16_t>(r);
                    ++s.rafts[r].members;
                }
            }
        }
    }
    for (const auto& f : st.form_rafts) s.rafts[raft_index(s, f.name)].velocity = f.velocity;
    for (const auto& [name, v] : st.raft_velocities) {
        const int r = raft_index(s, name);
        if (r < 0)
            throw std::runtime_error("stage '" + st.name + "' sets the velocity of raft '" + name +
                                     "', which was never formed");
        s.rafts[r].velocity = v;
    }
    for (const auto& [name, v] : st.wall_velocities)
        for (auto& w : s.walls)
            if (w.name == name) w.velocity = v;
    if (membership_changes) {
        const double far = 10.0 * norm(s.domain.length()) + 1.0;
        for (const auto& name : st.remove_walls)
            for (auto& w : s.walls)
                if (w.name == name) {
                    w.point -= w.normal * far;
                    w.velocity = {};
                    w.near.valid = false;
                }
    }
    if (st.flow) s.flow = st.flow;
    if (st.on_start) st.on_start(s, membership_changes);
}

// Steps until the next event the step count fixes, at most `left` and at most 64 (so wall-clock
// checks, progress and Ctrl-C stay responsive); observers are called every `observe_every`
// steps of `observe_step` (the run's step, or the stage's; 0: no observer), snapshots and
// step-counted checkpoints at multiples of the run's `step`.
long steps_until_event(const Scene& scene, long left, long step, long observe_step, long observe_every) {
    long chunk = std::min(left, 64L);
    auto limit_to_multiple = [&](long at, long every) {
        if (every > 0) chunk = std::min(chunk, every - at % every);
    };
    limit_to_multiple(observe_step, observe_every);
    if (scene.output.snapshots) limit_to_multiple(step, scene.output.snapshot_every);
    limit_to_multiple(step, scene.output.checkpoint_every_steps);
    return std::max(1L, chunk);
}

std::string checkpoint_path_of(const Scene& scene) {
    if (!scene.output.checkpoint_path.empty()) return scene.output.checkpoint_path;
    return default_checkpoint_path(scene.output.directory);
}

nlohmann::json timestep_json(const Scene& scene) {
    const TimestepLimits& l = scene.limits;
    auto finite_or_null = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"used_s", scene.system.dt},          {"rayleigh_s", finite_or_null(l.rayleigh)},
            {"hertz_s", finite_or_null(l.hertz)}, {"drag_relaxation_s", finite_or_null(l.drag)},
            {"critical_s", l.critical},           {"limiting", l.limiting},
            {"stable_limit_s", l.stable_limit},   {"characteristic_speed_m_s", scene.characteristic_speed}};
}

}  // namespace

std::string default_checkpoint_path(const std::string& output_directory) {
    return (std::filesystem::path(output_directory) / "checkpoint.mrjam").string();
}

void write_json_file(const std::string& path, const nlohmann::json& value) {
    const std::filesystem::path p(path);
    if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp);
        if (!out) throw std::runtime_error("cannot write " + tmp);
        out << value.dump(2) << '\n';
        if (!out) throw std::runtime_error("failed writing " + tmp);
    }
    std::filesystem::rename(tmp, path);
}

void prepare_output_directory(const std::string& directory, const std::string& json_path) {
    if (directory.empty()) throw SceneError(json_path, "must name a directory (\".\" for the current one)");
    std::error_code ec;
    std::filesystem::create_directories(directory, ec);
    if (ec || !std::filesystem::is_directory(directory))
        throw SceneError(json_path, "cannot create the directory " + directory +
                                        (ec ? " (" + ec.message() + ")" : " (a file is in the way)") +
                                        ": choose another");
}

void check_checkpoint_path(const std::string& path, const std::string& json_path) {
    const std::filesystem::path p(path);
    if (path.empty() || std::filesystem::is_directory(p) || !p.has_filename())
        throw SceneError(
            json_path,
            "'" + path +
                "' is not a file name the checkpoint can be written to; name a file, e.g. out/checkpoint.mrjam");
    const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
    prepare_output_directory(dir.string(), json_path);
    if (access(dir.c_str(), W_OK) != 0)
        throw SceneError(json_path, "the directory " + dir.string() +
                                        " is not writable: the checkpoint could not be saved on Ctrl-C; "
                                        "choose another path");
}

void discard_checkpoint(const std::string& path) {
    std::error_code ignored;  // none written (a short run): nothing to delete
    std::filesystem::remove(path, ignored);
    // A temporary file a killed run left half written goes too.
    std::filesystem::remove(path + ".tmp", ignored);
}

namespace {

// One call of run_protocol: the stages from a position, with the report, the checkpoints, the
// snapshots, the progress lines and Ctrl-C handled between chunks of steps.
class ProtocolRun {
public:
    ProtocolRun(Scene& scene, const RunOptions& options, const StepObserver& observer)
        : scene_(scene), s_(scene.system), options_(options), observer_(observer) {}

    RunOutcome run(ProtocolPosition pos) {
        install_interrupt_handler();
        prepare_output_directory(scene_.output.directory, "/output/directory");
        checkpoint_ = checkpoint_path_of(scene_);
        check_checkpoint_path(checkpoint_,
                              scene_.output.checkpoint_path.empty() ? "/output/directory" : "/output/checkpoint/path");
        start_report();
        stage_log_ = options_.resumed_stage_log.is_array() ? options_.resumed_stage_log : nlohmann::json::array();
        total_ = scene_.total_steps();
        for (std::size_t k = 0; k < pos.stage && k < scene_.stages.size(); ++k) done_before_ += scene_.stages[k].steps;
        done_before_ += pos.step_in_stage;
        // A checkpoint does not store the background flow: a resumed run restores the one the stages
        // before its own had set (its own stage sets it again in start_stage).
        for (std::size_t k = 0; k < pos.stage && k < scene_.stages.size(); ++k)
            if (scene_.stages[k].flow) s_.flow = scene_.stages[k].flow;
        try {
            for (std::size_t k = pos.stage; k < scene_.stages.size(); ++k)
                if (!run_stage(k, pos)) {
                    status_ = "interrupted";
                    break;
                }
        } catch (const BlowUp& e) {
            status_ = "failed";
            outcome_.report["error"] = e.what();
            outcome_.exit_status = 3;
        }
        return finish(pos);
    }

private:
    void start_report() {
        nlohmann::json& report = outcome_.report;
        report["mrjam_version"] = MRJAM_VERSION;
        report["mode"] = options_.mode;
        report["scene_file"] = options_.scene_path;
        report["seed"] = scene_.seed;
        report["threads"] = s_.threads;
        report["inputs"] = scene_.resolved;
        report["fidelity"] = scene_.fidelity;
        report["timestep"] = timestep_json(scene_);
        report["warnings"] = scene_.warnings;
        // Said before the run too: one about the step (a drag-limited one) changes how long it takes.
        if (options_.progress)
            for (const std::string& w : scene_.warnings)
                std::fprintf(stderr, "[%s] warning: %s\n", options_.mode.c_str(), w.c_str());
    }

    nlohmann::json history() const {
        if (!options_.checkpoint_state) return stage_log_;
        return nlohmann::json{
            {"mode", options_.mode}, {"stage_log", stage_log_}, {"state", options_.checkpoint_state()}};
    }

    // Stage k from `pos` (its start, or where a checkpoint left it). False: interrupted, with
    // `pos` where to resume.
    bool run_stage(std::size_t k, ProtocolPosition& pos) {
        const Stage& st = scene_.stages[k];
        const bool fresh = !(k == pos.stage && pos.stage_started);
        start_stage(s_, st, fresh);
        // A resumed stage keeps the neighbour list and forces of its checkpoint, so the run
        // continues exactly as if it had not stopped.
        if (fresh && !st.keep_forces) prepare(s_);
        long i = (k == pos.stage) ? pos.step_in_stage : 0;
        pos = ProtocolPosition{k, i, true};
        bool ended_early = false;
        while (i < st.steps && !ended_early) {
            ended_early = step_chunk(k, i);
            pos.step_in_stage = i;
            if (ended_early) break;
            between_chunks(k, i, pos);
            if (interrupt_requested()) break;
        }
        // A stage its criterion has just ended is finished even if Ctrl-C came in the same
        // step: a checkpoint inside it would make a resumed run test the criterion again.
        if (interrupt_requested() && !ended_early && i < st.steps) return false;
        stage_log_.push_back({{"name", st.name},
                              {"steps", i},
                              {"ended_early", ended_early},
                              {"end_time_s", s_.time},
                              {"state", state_summary(s_)}});
        pos = ProtocolPosition{k + 1, 0, false};
        if (options_.checkpoint_each_stage) {
            write_checkpoint(checkpoint_, scene_.resolved, s_, pos, history());
            last_checkpoint_ = Clock::now();
        }
        return !(interrupt_requested() && k + 1 < scene_.stages.size());
    }

    // Steps run in chunks that end at every event fixed by the step count (stage end, snapshot,
    // step-counted checkpoint), so the fused integrator pass is used without moving any event; a
    // per-step observer gets chunks of one. Then the observer, the modifiers and the stage's
    // criterion; true: the criterion ended the stage.
    bool step_chunk(std::size_t k, long& i) {
        const Stage& st = scene_.stages[k];
        const bool hooks = observer_ || !options_.modifiers.empty() || options_.stage_finished;
        const bool own = st.observe_every > 0;  // counted from the stage's first step
        const long every = hooks ? (own ? st.observe_every : std::max(1L, options_.observe_every)) : 0;
        const long chunk = steps_until_event(scene_, st.steps - i, s_.step, own ? i : s_.step, every);
        grain_steps_ += static_cast<double>(chunk) * static_cast<double>(s_.particles.size());
        advance_steps(s_, chunk);
        i += chunk;
        done_before_ += chunk;
        steps_advanced_ += chunk;
        const bool due = every > 0 && (own ? i % every == 0 || i == st.steps : s_.step % every == 0);
        if (!due) return false;
        if (observer_) observer_(s_, k, i);
        for (const Modifier& m : options_.modifiers) m.apply(s_, k);
        if (options_.stage_finished && options_.stage_finished(s_, k)) {
            done_before_ += st.steps - i;  // the skipped steps count as done for the ETA
            return true;
        }
        return false;
    }

    // Snapshots, checkpoints and progress, as the step count and the clock call for them.
    void between_chunks(std::size_t k, long i, const ProtocolPosition& pos) {
        const OutputPlan& out = scene_.output;
        if (out.snapshots && s_.step % out.snapshot_every == 0) {
            const auto path = std::filesystem::path(out.directory) /
                              ("snapshot_" + std::to_string(s_.step) + snapshot_extension(out.snapshot_format));
            write_snapshot(path.string(), out.snapshot_format, s_.particles, s_.domain, s_.step, s_.time);
        }
        const bool ck_steps = out.checkpoint_every_steps > 0 && s_.step % out.checkpoint_every_steps == 0;
        if (ck_steps || seconds_since(last_checkpoint_) > out.checkpoint_every_seconds) {
            write_checkpoint(checkpoint_, scene_.resolved, s_, pos, history());
            last_checkpoint_ = Clock::now();
        }
        if (options_.progress && seconds_since(last_progress_) > out.progress_interval_s) {
            print_progress(k, i);
            last_progress_ = Clock::now();
        }
    }

    void print_progress(std::size_t k, long i) const {
        const Stage& st = scene_.stages[k];
        const double elapsed = seconds_since(t0_);
        const double rate = steps_advanced_ / std::max(elapsed, 1e-9);
        const double grain_rate = grain_steps_ / std::max(elapsed, 1e-9);
        // Where a stage can end on a criterion (a jam's arrest or steady flow), the time left to
        // its last step is a bound, not an estimate: say so.
        std::fprintf(stderr,
                     "[%s] stage %zu/%zu '%s' step %ld/%ld (%.1f%% of the run), t = %.4g s, %.3g grain-steps/s, "
                     "ETA %s%.0f s\n",
                     options_.mode.c_str(), k + 1, scene_.stages.size(), st.name.c_str(), i, st.steps,
                     100.0 * done_before_ / std::max(total_, 1L), s_.time, grain_rate,
                     options_.stage_finished ? "at most " : "", (total_ - done_before_) / std::max(rate, 1e-9));
    }

    RunOutcome finish(const ProtocolPosition& pos) {
        nlohmann::json& report = outcome_.report;
        if (status_ == "interrupted") {
            write_checkpoint(checkpoint_, scene_.resolved, s_, pos, history());
            report["checkpoint"] = checkpoint_;
            report["resume_with"] = "mrjam " + options_.mode + " --resume " + checkpoint_;
            outcome_.exit_status = 130;
            std::fprintf(stderr, "[%s] interrupted at step %ld; checkpoint written to %s\n", options_.mode.c_str(),
                         s_.step, checkpoint_.c_str());
        }
        // The checkpoints written against an interruption (every few minutes) go; those asked for
        // by step count are the user's and stay.
        if (status_ == "complete" && scene_.output.checkpoint_every_steps == 0) discard_checkpoint(checkpoint_);
        const double wall = seconds_since(t0_);
        report["status"] = status_;
        report["partial"] = status_ != "complete";
        report["results"] = state_summary(s_);
        report["results"]["stages"] = stage_log_;
        outcome_.speed = RunSpeed{steps_advanced_, grain_steps_, wall};
        report["performance"] = performance_json(outcome_.speed, s_.threads);
        report["wall_time_s"] = wall;
        if (!options_.report_path.empty()) write_json_file(options_.report_path, report);
        return outcome_;
    }

    Scene& scene_;
    System& s_;
    const RunOptions& options_;
    const StepObserver& observer_;
    const Clock::time_point t0_ = Clock::now();
    Clock::time_point last_progress_ = t0_, last_checkpoint_ = t0_;
    std::string checkpoint_;
    RunOutcome outcome_;
    nlohmann::json stage_log_;
    std::string status_ = "complete";
    long total_ = 0;
    long done_before_ = 0;     // steps of the whole run done, skipped ones included (for the ETA)
    long steps_advanced_ = 0;  // steps this call really ran
    // Grain-steps really run: a modifier may take grains out (a jam batch's outlet), so the count
    // is summed chunk by chunk rather than taken as the steps times the grains at the start.
    double grain_steps_ = 0;
};

}  // namespace

nlohmann::json performance_json(const RunSpeed& speed, int threads) {
    return {{"steps_run", speed.steps_run},
            {"grain_steps_per_s", speed.grain_steps / std::max(speed.wall_s, 1e-9)},
            {"core_us_per_grain_step", speed.wall_s * threads * 1e6 / std::max(1.0, speed.grain_steps)}};
}

RunOutcome run_protocol(Scene& scene, const RunOptions& options, ProtocolPosition pos, const StepObserver& observer) {
    return ProtocolRun(scene, options, observer).run(pos);
}

}  // namespace mrjam
