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

}  // namespace mrjam
