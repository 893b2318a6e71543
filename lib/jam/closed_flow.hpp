#pragma once
// How much carrier fluid an arrested valve still lets through (pressure-driven flow only). A jam
// stops the grains; whether it stops the fluid depends on how tightly the arrested bed packs, and
// a designer needs both. The share is the mean flow scale over the arrest window (the low-flux
// window that called the arrest) over its mean in the no-field reference period (the second half
// of the flow period, where the no-field grain flux is measured too): the leak at the moment of
// arrest. Unless the protocol holds the field on after the arrest (protocol/hold_time), the field
// goes off right after that window; with a hold the same share over the hold's last window says
// whether the bed packs on and seals.
#include <vector>

#include "jam/axial_resistance.hpp"

namespace mrjam {

// Mean flow scale of the samples taken in [t0, t1] (the observations are equally spaced in steps,
// and the time step is fixed, so this is the time average); NaN when no sample falls in it.
double mean_flow_scale(const std::vector<FlowSample>& history, double t0, double t1);

// The closed valve's flow as a share of the open (no-field) flow: mean over
// [window_start, window_start + window] over mean over [flow_time / 2, flow_time]; NaN when
// either holds no sample.
double closed_flow_share(const std::vector<FlowSample>& history, double flow_time, double window_start, double window);

}  // namespace mrjam
