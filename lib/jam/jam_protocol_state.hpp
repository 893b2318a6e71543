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

// The magnetised structure at one settle check (protocol/order closed_first).
struct SettleSample {
    double time = 0;
    double coordination = 0;     // mean contacts per grain
    double magnetic_energy = 0;  // J, the grains' energy in the applied field (observers.hpp)
};

struct JamProtocolState {
    ThroatFlux flux{0.0};
    double base_rate = 0;       // the no-field flux (second half of the flow period), grains/s
    double arrest_time = -1;    // from judged_from to the start of the low-flux window, s
    double release_start = -1;  // when the field went off after the arrest, s
    // When the judged period began (s): the pressure applied (closed first) or the field switched
    // on (open first); -1 before. Time to arrest and grains passed count from here.
    double judged_from = -1;
    // Closed first: the settle checks, whether they found the structure settled, and when the
    // magnetisation ended (-1 before).
    std::vector<SettleSample> settle_history;
    bool settled = false;
    double magnetise_end = -1;
    // Grains passed when the judged period began (named for field-on, open first; the checkpoint
    // keeps the key) and at the arrest.
    long passed_at_switch_on = 0, passed_at_arrest = 0;
    bool jammed = false, released = false, steady = false;
    bool undetermined = false;  // no grain crossed during the no-field flow: nothing to compare with
    // Grains the carrier would bring across the throat over the reference period if nothing
    // stopped them (grains per length of tube times the bore speed times the period): with many
    // expected and none crossing, the throat clogged; with few, the flow is too slow to tell.
    double reference_expected = 0;
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
