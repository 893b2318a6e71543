#pragma once
// What the simulated asteroid modes (coalesce, spinup, avalanche) share around the run loop: the
// report's envelope, the plot's path beside the report, and reading back a checkpoint the mode wrote.
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/coalesce_run.hpp"
#include "io/checkpoint.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"
#include "system.hpp"

namespace mrjam {

// The runner's report relabelled for the mode: the mode's own scene as `inputs`, the engine scene
// it built as `engine_inputs`, the tier.
nlohmann::json asteroid_report(const RunOutcome& outcome, const char* mode, const nlohmann::json& inputs,
                               const std::string& fidelity);

// REPORT.json -> REPORT_<suffix>.svg, next to it.
std::string plot_beside(const std::string& report_path, const std::string& suffix);

// The heaviest contact cluster drawn along and across the spin axis, coloured by distance from
// its centre of mass, as REPORT_<suffix>.svg next to the report; returns the path, or an empty
// string (and a warning on stderr) if it could not be written: a picture never costs the run.
std::string body_views_beside(const std::string& report_path, const std::string& suffix, const System& s,
                              const std::string& title);

// The checkpoint's header, refused at --resume unless `mode` wrote it.
CheckpointHeader read_mode_checkpoint(const std::string& path, const char* mode);

// A mode's fresh run and its resume, the same for every simulated mode: `Mode` is built from its
// spec and options and has start_fresh(), resume(checkpoint, state, header) and run(); its
// checkpoint's state carries the tier under "fidelity" and the mode's own scene under `input_key`,
// which `read_spec(json, fidelity)` reads back.
template <class Mode, class Spec>
CoalesceOutcome run_fresh(const Spec& spec, const std::string& output_directory, const CoalesceOptions& options) {
    install_interrupt_handler();
    prepare_output_directory(output_directory, "/output/directory");
    Mode m(spec, options);
    m.start_fresh();
    return m.run();
}

template <class Mode, class ReadSpec>
CoalesceOutcome run_resumed(const std::string& checkpoint, const CoalesceOptions& options, const char* mode,
                            const char* input_key, ReadSpec read_spec) {
    const CheckpointHeader header = read_mode_checkpoint(checkpoint, mode);
    const nlohmann::json& state = header.history.at("state");
    CoalesceOptions o = options;
    o.fidelity = state.at("fidelity").get<std::string>();
    const auto spec = read_spec(state.at(input_key), o.fidelity);
    install_interrupt_handler();
    Mode m(spec, o);
    m.resume(checkpoint, state, header);
    return m.run();
}

}  // namespace mrjam
