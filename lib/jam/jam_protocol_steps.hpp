#pragma once
// The jam protocol's decisions at each observation (lib/jam/jam_run.cpp calls them from the
// runner's stage criterion): the no-field reference, the settle test of the magnetisation at
// rest, the arrest or steady flow of the judged period, the release; and the checks and
// warnings about the protocol's windows.

#include <optional>
#include <string>
#include <utility>

#include "jam/jam_protocol_state.hpp"
#include "jam/jam_scene.hpp"
#include "magnetic/external_field.hpp"
#include "scene/scene_node.hpp"
#include "system.hpp"

namespace mrjam {

// An arrest is a window whose grain count falls below arrest_fraction of the no-field count.
// With few grains per window a flowing bed's count is zero by chance (Poisson: e^-20 ~ 2e-9 at 20
// grains, e^-5 ~ 7e-3 at 5, tested at every observation), so the arrest may be noise; likewise a
// reference period that would carry fewer than this many grains across says nothing by passing none.
constexpr double kFewestGrainsPerWindow = 20;

// When the arrest was called (the end of its low-flux window): the hold runs from here to the
// release. Only meaningful once st.jammed.
double arrest_called_at(const JamProtocolState& st, const JamProtocol& p);

// What each engine stage is to the protocol (jam_stages): the no-field reference flow, the
// magnetisation at rest (closed first), the judged period (pressure on, or field on open first),
// and the release.
enum class JamPhase { reference, magnetise, judged, release };

JamPhase jam_phase(const JamProtocol& p, std::size_t stage);

// The carrier's viscosity in a stage, as a share of its own: protocol/magnetise_viscosity_share
// while the grains are magnetised at rest (the fast-forwarded closed period), 1 otherwise.
double carrier_viscosity_share(const JamProtocol& p, std::size_t stage);

// The relative change of the mean contact number and of the magnetic energy over the last settle
// window; none before two checks.
std::optional<std::pair<double, double>> last_settle_change(const JamProtocolState& st);

// Closed first: a settle check every protocol/settle_window from the start of the magnetisation.
// Settled once both the mean contact number and the magnetic energy changed by less than
// settle_tolerance over the last window, after at least two windows.
bool magnetised_structure_settled(JamProtocolState& st, const System& sys, const JamProtocol& p);

// The no-field reference, taken once at the first observation after the flow period: its flux
// over the period's second half, and whether none crossed (a clog, or too slow a flow to tell).
void take_reference(JamProtocolState& st, const JamScene& js, const System& sys, bool progress);

// The judged period (pressure on, or field on): an arrest switches the field off after the hold;
// a steady flow ends the period as no jam. True ends the stage.
bool judge_arrest(JamProtocolState& st, const JamProtocol& p, SwitchedField& field, double t);

// The protocol's decision at an observation in `phase`: true ends the engine's current stage.
bool protocol_stage_finished(JamProtocolState& st, const JamScene& js, SwitchedField& field, const System& sys,
                             JamPhase phase, bool progress);

// Closed first, a structure still changing when protocol/magnetise_time ran out met the pressure
// unsettled: said with the criterion's values. Empty otherwise (settled, open first, or not yet there).
std::string unsettled_warning(const JamProtocolState& st, const JamProtocol& p);

// The flux is counted at observations: a window (or the no-field reference, the flow period's
// second half) that holds only a few of them reads the same count at both ends, a zero rate, and
// so a false arrest. Refused before the run, now that the step is known.
void check_observation_interval(const JamProtocol& p, double dt);

// A window of the no-field flux holding fewer than kFewestGrainsPerWindow grains.
std::string sparse_window_warning(double base_rate, const JamProtocol& p);

// A jet (the coupled flow's, or the prescribed converging profile's) cut short by a tube length
// the scene fixed (lib/jam/jam_scene.cpp keeps it): the grains pile up where the stream slows,
// which blew up the 10 um mix, and a 44 um 20x case with a 24 um jet (docs/notes/jam_measurements.md).
std::string short_jet_warning(const JamScene& js);

// An error in the generated engine scene, named by the jam scene's key the user wrote: a packing
// it cannot make is the feed's volume fraction, a stage with too many steps its protocol time
// (the stages of jam_stages(): flow, then magnetise and pressure or field_on, then release).
SceneError as_jam_key(const SceneError& e, const JamProtocol& p);

}  // namespace mrjam
