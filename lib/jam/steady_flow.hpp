#pragma once
// "Run until arrest or steady flow" (section 3.4.4): with the field on, the flow is called
// steady when the grain flux through the throat over the last window and over the window before
// it agree within a tolerance, and (pressure-driven flow) the flow scale has also settled. A
// steady flow that has not arrested by then is taken as no jam, and the run stops early.
//
// What this costs is a rare late arch: the test stops a statistically steady flow, so an arrest
// that would have come later by chance is missed (docs/notes/jam_measurements.md measures it on the bundled cases).
#include <vector>

#include "jam/axial_resistance.hpp"
#include "jam/throat_flux.hpp"

namespace mrjam {

struct SteadyFlowCriterion {
    double window = 0;        // s; 0 switches the test off (the run goes to max_time)
    double tolerance = 0.15;  // relative change of flux and flow scale allowed from one window to the next
};

struct SteadyFlowVerdict {
    bool steady = false;
    double previous_rate = 0, last_rate = 0;  // grains/s over the two windows (0 if not yet two windows)
};

// `field_on`: when the field came on (only the flux with the field counts). `flow_history`:
// the resistance cells' observations (pressure-driven flow), empty for a prescribed flow.
SteadyFlowVerdict steady_flow(const ThroatFlux& flux, const std::vector<FlowSample>& flow_history, double field_on,
                              const SteadyFlowCriterion& criterion);

}  // namespace mrjam
