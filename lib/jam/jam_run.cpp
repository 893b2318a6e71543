#include "jam/jam_run.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

#include "contact_clusters.hpp"
#include "fluid/valve_flow.hpp"
#include "jam/axial_resistance.hpp"
#include "jam/batch_outlet.hpp"
#include "jam/coupled_flow.hpp"
#include "jam/jam_checkpoint.hpp"
#include "jam/jam_picture.hpp"
#include "jam/jam_protocol_state.hpp"
#include "jam/jam_protocol_steps.hpp"
#include "jam/jam_results.hpp"
#include "jam/jam_snapshots.hpp"
#include "jam/throat_span.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/drag_term.hpp"

namespace mrjam {

namespace {

std::unique_ptr<CoupledFlow> make_coupled_flow(const JamScene& js, double viscosity) {
    CoupledFlowSettings c;
    c.slab_half_thickness = js.slab_half_thickness;
    c.z_lo = -js.valve.upstream_length;
    c.z_hi = js.valve.downstream_length;
    c.cell_length = js.flow.cell_length;
    c.rings = js.flow.rings;
    c.feed_fraction = js.feed_fraction;
    c.supply_pressure = js.flow.supply_pressure;
    c.viscosity = viscosity;
    c.bore_speed = js.flow.bore_speed;
    c.wall_gap = js.flow.wall_gap;
    c.jet_length = js.flow.jet_length;
    return std::make_unique<CoupledFlow>(js.valve, c);
}

// The engine scene of a seed, built fresh or (resuming) from the checkpoint's scene and state.
Scene build_jam_scene(const JamScene& js, long long seed, const JamRunOptions& options,
                      const std::optional<JamCheckpoint>& checkpoint, std::unique_ptr<CoupledFlow>& coupled) {
    nlohmann::json engine = js.engine_scene;
    engine["seed"] = seed;
    BuildOptions build;
    build.threads = options.threads;
    build.fidelity = js.tier;
    if (checkpoint) {
        // As `mrjam run --resume`: the grains, lists and step come from the checkpoint.
        build.insert_grains = false;
        engine = checkpoint->header.resolved_scene;
    }
    // The engine scene is generated: a packing it cannot make is the jam scene's volume fraction
    // (or size table), named as the user wrote it rather than by the generated scene's path.
    Scene scene = [&] {
        try {
            return build_scene(engine, build);
        } catch (const SceneError& e) {
            throw as_jam_key(e, js.protocol);
        }
    }();
    // The coupled flow replaces the engine scene's prescribed one before anything reads it.
    if (js.flow.coupled) {
        coupled = make_coupled_flow(js, carrier_viscosity(scene.system));
        scene.system.flow = coupled->field();
    }
    try {
        if (checkpoint)
            restore_scene(options.resume_checkpoint, scene);
        else
            choose_timestep(scene);
    } catch (const SceneError& e) {
        throw as_jam_key(e, js.protocol);
    }
    return scene;
}

// One seed's run: the engine scene, the protocol's state, and the hooks the runner calls (an
// observer counting the flux, modifiers for the outlet and the carrier flow, the protocol's
// stage criterion, the checkpoint state).
class JamRun {
public:
    JamRun(const JamScene& js, long long seed, const JamRunOptions& options)
        : js_(js), p_(js.protocol), seed_(seed), options_(options) {
        if (!options.resume_checkpoint.empty()) checkpoint_ = read_jam_checkpoint(options.resume_checkpoint);
        if (checkpoint_ && checkpoint_->campaign_only)  // only `mrjam jam --resume` starts its seed afresh
            throw SceneError("--resume", options.resume_checkpoint +
                                             " holds a `mrjam jam --seeds` campaign's record, not a run's state: "
                                             "resume it with `mrjam jam --resume`");
        scene_ = build_jam_scene(js, seed, options, checkpoint_, coupled_);
        System& s = scene_.system;
        check_observation_interval(p_, s.dt);
        for (const std::string& w : {short_jet_warning(js), saturated_field_warning(js)})
            if (options.progress && !w.empty()) std::cerr << "[jam] warning: " << w << "\n";
        if (options.progress)
            std::cerr << "[jam] " << s.particles.size() << " grains, time step " << s.dt * 1e9 << " ns\n";
        // The magnet is switched on after the no-field flow and off when the flow has arrested.
        field_ = std::make_shared<SwitchedField>(s.magnetic.field, p_.flow_time);
        s.magnetic.field = field_;
        for (const auto& w : s.walls)
            if (w.kind == Wall::Kind::passage || w.kind == Wall::Kind::slot_passage) valve_wall_ = &w;
        valve_flow_ = std::dynamic_pointer_cast<ValveFlow>(s.flow);
        if (js.batch_supply)
            outlet_.emplace(s, js.valve.downstream_length, js.valve.throat_end_z(), js.largest_diameter);
        if (!options.snapshot_directory.empty())
            snapshots_ = JamSnapshots(options.snapshot_directory, options.snapshot_every, seed);
        if (p_.magnetise_viscosity_share < 1) set_closed_period_viscosity();
    }

    JamOutcome run() {
        RunOptions run;
        run.mode = "jam";
        run.progress = options_.progress;
        run.observe_every = p_.observe_every;
        add_modifiers(run);
        run.stage_finished = [this](const System& sys, std::size_t stage) { return stage_finished(sys, stage); };
        run.checkpoint_state = [this] {
            return nlohmann::json{{"protocol", protocol_state()}, {"campaign", options_.campaign}};
        };
        ProtocolPosition start;
        if (checkpoint_) {
            restore_protocol_state(checkpoint_->state);
            start = checkpoint_->header.position;
            run.resumed_stage_log = checkpoint_->stage_log;
        }
        const RunOutcome outcome = run_protocol(scene_, run, start, [this](const System& sys, std::size_t, long) {
            observe(sys);
            snapshots_.observe(sys);
        });
        if (outcome.exit_status == 0) snapshots_.write_tagged(scene_.system, "end");
        return outcome_of(outcome);
    }

private:
    // Read-only: the grains' crossings of the throat, and a line per 0.1 ms of simulated time
    // (what a user watches for is the flux).
    void observe(const System& sys) {
        st_.flux.observe(sys);
        if (!options_.progress || sys.time < next_report_) return;
        next_report_ = sys.time + 0.1e-3;
        const double rate = st_.flux.rate(0.1e-3);
        std::cerr << "[jam] t = " << sys.time * 1e3 << " ms: grain flux " << rate << " /s";
        if (st_.base_rate > 0)
            std::cerr << " (" << std::lround(100 * rate / st_.base_rate) << " % of the no-field flux)";
        if (js_.flow.pressure_driven && (coupled_ || valve_flow_))
            std::cerr << ", flow scale " << st_.flow_state.scale << ", densest cell " << st_.flow_state.max_fraction;
        std::cerr << "\n";
    }

    void add_modifiers(RunOptions& run) {
        // A finite batch's outlet takes out the grains past it; the observer has counted their
        // crossing already (the outlet is past the throat, so none is lost).
        if (outlet_) run.modifiers.push_back({"batch_outlet", [this](System& sys, std::size_t) { drain(sys); }});
        if (coupled_ || valve_flow_)
            run.modifiers.push_back(
                {"carrier_flow", [this](System& sys, std::size_t stage) { update_flow(sys, stage); }});
    }

    // The fast-forwarded closed period: the carrier at its share of the viscosity while the
    // grains are magnetised at rest, at its own in every other stage. Set as each stage starts
    // (also when a run resumes mid-stage), so the stage's first step and the carrier flow's first
    // update under pressure see the right viscosity.
    void set_closed_period_viscosity() {
        for (std::size_t k = 0; k < scene_.stages.size(); ++k) {
            Stage& stage = scene_.stages[k];
            const double share = carrier_viscosity_share(p_, k);
            stage.on_start = [share, before = std::move(stage.on_start)](System& sys, bool fresh) {
                if (before) before(sys, fresh);
                if (DragTerm* drag = sys.terms.find<DragTerm>()) drag->set_viscosity_share(share);
            };
        }
    }

    void drain(System& sys) {
        st_.drained += static_cast<long>(outlet_->drain(sys, st_.flux));
        st_.upstream_now = 0;
        for (const Vec3& x : sys.particles.position) st_.upstream_now += x.z < 0;
        if (st_.upstream_at_start < 0) st_.upstream_at_start = st_.upstream_now;
    }

    // The carrier flow follows the supply: from the arrest on it rises to the hold pressure
    // (protocol/hold_pressure and its ramp; the same pressure by default); closed first it is cut
    // while the grains are magnetised (the fluid at rest).
    void update_flow(System& sys, std::size_t stage) {
        const double supply =
            jam_phase(p_, stage) == JamPhase::magnetise ? 0.0
            : st_.jammed ? p_.supply_after_arrest(sys.time - arrest_called_at(st_, p_), js_.flow.supply_pressure)
                         : js_.flow.supply_pressure;
        st_.flow_state = coupled_ ? coupled_->update(sys, supply)
                                  : resistance_.update(sys, *valve_flow_, js_.flow.pressure_driven, supply);
        if (js_.flow.pressure_driven)
            st_.flow_history.push_back(
                {sys.time, st_.flow_state.scale, st_.flow_state.stretch_pressure, st_.flow_state.max_fraction});
    }

    // The protocol's criterion; the arch is looked at when the flow arrests (after the release
    // it has let go): the clusters, whether the largest spans the throat, and the picture.
    bool stage_finished(const System& sys, std::size_t stage) {
        const bool was_jammed = st_.jammed;
        const bool done = protocol_stage_finished(st_, js_, *field_, sys, jam_phase(p_, stage), options_.progress);
        if (st_.jammed && !was_jammed) {
            snapshots_.write_tagged(sys, "arrest");
            st_.arrest_view = look_at_clusters(sys);
        }
        return done;
    }

    ClusterView look_at_clusters(const System& sys) {
        const ContactClusters clusters = contact_clusters(sys);
        ClusterView v;
        v.valid = true;
        v.largest = clusters.size.empty() ? 0 : static_cast<long>(clusters.size[0]);
        v.count = static_cast<long>(clusters.size.size());
        v.spans = valve_wall_ ? cluster_spans_throat(sys, clusters, js_.valve, *valve_wall_) : false;
        // A picture that cannot be written costs a warning, never the run.
        if (!options_.picture_path.empty() && sys.particles.size() > 0) try {
                write_throat_picture(options_.picture_path, sys, clusters, js_.valve);
            } catch (const std::exception& e) {
                picture_error_ = e.what();
            }
        return v;
    }

    // Everything the protocol carries from one observation to the next that the engine's
    // checkpoint does not: restored, it makes the resumed run take the same decisions. The
    // protocol's state plus what lives in the field, the flow and the snapshot writer.
    nlohmann::json protocol_state() const {
        const double off = field_->switch_off_time();
        nlohmann::json state = st_.save();
        state["seed"] = seed_;
        state["field_off_s"] = std::isfinite(off) ? nlohmann::json(off) : nlohmann::json(nullptr);
        state["drag_factors"] = valve_flow_ ? valve_flow_->drag_factors() : std::vector<double>{};
        if (coupled_)
            state["coupled_flow"] = {{"axial_speed", coupled_->field()->axial_speed()},
                                     {"drag_factors", coupled_->field()->drag_factors()}};
        state["snapshots"] = snapshots_.save();
        return state;
    }

    void restore_protocol_state(const nlohmann::json& saved) {
        st_.restore(saved);
        if (!saved.at("field_off_s").is_null()) field_->switch_off_at(saved["field_off_s"].get<double>());
        if (valve_flow_) {
            // The cells' factors and scale as the last observation left them: the steps up to the
            // next observation use them.
            valve_flow_->set_scale(st_.flow_state.scale);
            const auto factors = saved.at("drag_factors").get<std::vector<double>>();
            if (!factors.empty()) resistance_.apply(*valve_flow_, factors);
        }
        if (coupled_) {
            const nlohmann::json& cf = saved.at("coupled_flow");
            coupled_->field()->set_field(cf.at("axial_speed").get<std::vector<double>>(),
                                         cf.at("drag_factors").get<std::vector<double>>());
        }
        snapshots_.restore(saved.at("snapshots"));
    }

    JamOutcome outcome_of(const RunOutcome& outcome) {
        const System& s = scene_.system;
        const bool incomplete = outcome.exit_status != 0;
        JamOutcome out;
        out.report = outcome.report;
        out.exit_status = outcome.exit_status;
        out.jammed = st_.jammed;
        out.time_to_arrest = st_.arrest_time;
        // Clusters at the arrest if there was one, otherwise as the run ended (the picture too).
        const ClusterView view = st_.arrest_view.valid ? st_.arrest_view : look_at_clusters(s);
        const bool blew_up = out.report.value("status", "") == "failed";  // the runner's BlowUp (exit status 3)
        write_jam_results(out.report, st_, view, js_, coupled_ ? coupled_->cells() : resistance_.cells(),
                          valve_flow_.get(), incomplete, blew_up);
        out.stops_flow = out.report["results"]["stops_flow"].get<bool>();
        if (coupled_) write_coupled_slices(out.report["results"], *coupled_);
        if (outlet_) write_batch_results(out.report, st_, *outlet_, s.particles.size());
        if (snapshots_.enabled()) out.report["outputs"]["snapshots"] = snapshots_.written();
        if (!picture_error_.empty())
            out.report["warnings"].push_back("the throat picture was not written: " + picture_error_);
        else if (!options_.picture_path.empty() && s.particles.size() > 0)
            out.report["outputs"]["throat_picture"] = options_.picture_path;
        return out;
    }

    const JamScene& js_;
    const JamProtocol& p_;
    long long seed_;
    const JamRunOptions& options_;
    std::optional<JamCheckpoint> checkpoint_;
    std::unique_ptr<CoupledFlow> coupled_;
    Scene scene_;
    std::shared_ptr<SwitchedField> field_;
    const Wall* valve_wall_ = nullptr;
    // The carrier flow's resistance cells (lib/jam/axial_resistance.hpp): with the pressure
    // option they set the flow; with the prescribed flow they only measure what it would push
    // an arrested bed with. (A slot's flow has no cells: null valve_flow_.)
    std::shared_ptr<ValveFlow> valve_flow_;
    AxialResistance resistance_{js_.valve,
                                js_.slab_half_thickness,
                                -js_.valve.upstream_length,
                                js_.valve.downstream_length,
                                js_.flow.cell_length,
                                js_.feed_fraction,
                                js_.flow.supply_pressure};
    std::optional<BatchOutlet> outlet_;  // a finite batch's outlet (model/supply "batch"); none for the periodic feed
    JamSnapshots snapshots_;
    JamProtocolState st_;
    double next_report_ = 0.2e-3;  // the first line once a full 0.1 ms window of flux exists
    std::string picture_error_;
};

}  // namespace

JamOutcome run_jam(const JamScene& js, long long seed, const JamRunOptions& options) {
    return JamRun(js, seed, options).run();
}

}  // namespace mrjam
