#pragma once
// How much carrier fluid an arrested valve still lets through (pressure-driven flow only). A jam
// stops the grains; whether it stops the fluid depends on how tightly the arrested bed packs, and
// a designer needs both. The share is the mean flow scale over the arrest window (the low-flux
// window that called the arrest) over its mean in the no-field reference period (the second half
// of the flow period, where the no-field grain flux is measured too). The protocol switches the
// field off right after the arrest window, so that window is all of the closed valve a run sees:
// the share is the leak at the moment of arrest, before any further consolidation of the bed.
#include <vector>

#include "jam/axial_resistance.hpp"

namespace mrjam {

// Mean flow scale of the samples taken in [t0, t1] (the observations are equally spaced in steps,
// and the time step is fixed, so this is the time average); NaN when no sample falls in it.
double mean_flow_scale(const std::vector<FlowSample>& history, double t0, double t1);

// The closed valve's flow as a share of the open (no-field) flow: mean over
// [arrest_start, arrest_start + window] over mean over [flow_time / 2, flow_time]; NaN when
// either holds no sample.
double closed_flow_share(const std::vector<FlowSample>& history, double flow_time, double arrest_start, double window);

}  // namespace mrjam
