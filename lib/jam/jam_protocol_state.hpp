#pragma once
// What a jam run's protocol carries from one observation to the next beyond the engine's own
// state: the throat's flux count, the arrest and release bookkeeping, the carrier flow's
// controller state and history, and the arch as it was seen at the arrest. It goes into every
// checkpoint (jam/jam_checkpoint.hpp), so a resumed run takes the decisions the uninterrupted
// one would have taken.
#include <nlohmann/json.hpp>
#include <vector>

#include "jam/axial_resistance.hpp"
#include "jam/throat_flux.hpp"

namespace mrjam {

// The contact clusters as the report gives them (valid once looked at).
struct ClusterView {
    long largest = 0, count = 0;
    bool spans = false, valid = false;
};

struct JamProtocolState {
    ThroatFlux flux{0.0};
    double base_rate = 0;       // the no-field flux (second half of the flow period), grains/s
    double arrest_time = -1;    // from field-on to the start of the low-flux window, s
    double release_start = -1;  // when the field went off after the arrest, s
    long passed_at_switch_on = 0, passed_at_arrest = 0;
    bool jammed = false, released = false, steady = false;
    bool undetermined = false;  // no grain crossed during the no-field flow: nothing to compare with
    // A finite batch (model/supply "batch"): grains taken out at the outlet, and those upstream of
    // the throat plane at the first observation, at the arrest and at the latest (-1 before).
    long drained = 0, upstream_at_start = -1, upstream_at_arrest = -1, upstream_now = -1;
    AxialResistanceState flow_state;
    std::vector<FlowSample> flow_history;
    ClusterView arrest_view;

    // As JSON, in the checkpoint's keys (JSON numbers round-trip doubles exactly).
    nlohmann::json save() const;
    // The inverse; checkpoints written before the steady-flow test have no "steady".
    void restore(const nlohmann::json& state);
};

}  // namespace mrjam
