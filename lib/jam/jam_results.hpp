#pragma once
// The jam report: results, outcome, hold, magnetisation, the carrier flow's slices and the
// batch's account, and the one-line seed records a campaign prints.

#include <nlohmann/json.hpp>

#include "fluid/valve_flow.hpp"
#include "jam/batch_outlet.hpp"
#include "jam/coupled_flow.hpp"
#include "jam/jam_outcome.hpp"
#include "jam/jam_protocol_state.hpp"
#include "jam/jam_scene.hpp"
#include "jam/throat_span.hpp"

namespace mrjam {

struct JamOutcome;  // jam/jam_run.hpp

// The hold (protocol/hold_time): with the field kept on after the arrest, did the grains stay put,
// and how much fluid does the valve pass at its end? Null until a run has held that long.
nlohmann::json hold_results(const JamProtocolState& st, const JamProtocol& p, double supply_pressure);

// What the run says about the valve, for the outcome's words and the jam probability; `hold` is
// hold_results() (null without a hold, or before the run has held that long).
JamVerdict jam_verdict(const JamProtocolState& st, const JamScene& js, const nlohmann::json& hold, bool incomplete,
                       bool blew_up);

// The report's account of the magnetisation at rest (closed first), with the criterion's values.
nlohmann::json magnetisation_results(const JamProtocolState& st, const JamProtocol& p);

// The report's results: outcome, flux history, arch, and the carrier flow's model and state.
void write_jam_results(nlohmann::json& report, const JamProtocolState& st, const ClusterView& view, const JamScene& js,
                       std::size_t resistance_cells, const ValveFlow* valve_flow, bool incomplete, bool blew_up);

// Where the coupled flow spent the pressure, slice by slice, at its last update.
void write_coupled_slices(nlohmann::json& results, const CoupledFlow& coupled);

// A finite batch's counts (model/supply "batch"), taken at the observations as the flux is. An
// arrest with most of the batch gone upstream may be the feed running out rather than an arch:
// the warning says so.
void write_batch_results(nlohmann::json& report, const JamProtocolState& st, const BatchOutlet& outlet,
                         std::size_t grains_left);

// One seed's line in a campaign (`mrjam jam --seeds`, `mrjam design`): the seed, the run's
// status, outcome, time to arrest, whether it stopped the flow, the hold, the closed valve's leak
// and the seed's warnings.
nlohmann::json jam_seed_record(const JamOutcome& outcome, long long seed);

// A seed record as a progress line says it: "fail-no-hold, arrest at 0.64 ms of field, gave way
// 0.1 ms into the hold", "fail-no-jam, grain flux at 64 % of the no-field flux over the last window".
std::string seed_summary(const nlohmann::json& record);

// The report's warning when the field anywhere exceeds the lone-grain saturation field (where it
// does, a stronger field adds nothing to the magnetic forces); empty otherwise.
std::string saturated_field_warning(const JamScene& scene);

}  // namespace mrjam
