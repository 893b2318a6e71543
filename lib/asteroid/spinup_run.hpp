#pragma once
// `mrjam asteroid spinup`: a body gathered from a cold cloud, settled, then spun up about z in
// steps (section 4.3 of the source, the YORP spin-up): each step adds delta-omega x r to the body
// (the heaviest contact cluster) in the inertial frame; at each step's end the body's spin, mass,
// shape and fragments are recorded, and deformation, shedding and fission are detected against
// the previous step.
#include <string>

#include "asteroid/coalesce_run.hpp"
#include "asteroid/spinup_spec.hpp"

namespace mrjam {

CoalesceOutcome run_spinup(const SpinupSpec& spec, const CoalesceOptions& options);
CoalesceOutcome resume_spinup(const std::string& checkpoint, const CoalesceOptions& options);

}  // namespace mrjam
