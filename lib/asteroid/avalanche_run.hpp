#pragma once
// `mrjam asteroid avalanche`: section 4.4 of the source on the engine. Three stages: the column
// settles behind its gate in uniform gravity; the field (along gravity) is switched on and the
// magnetised grains rearrange; the gate is taken away and the grains run out until they are at
// rest (or the run-out time ends). The heap's profile, angle of repose (one fit and, where the
// slope bends, its upper and lower halves), volume and run-out are reported beside Table 4.5.
#include <string>

#include "asteroid/avalanche_spec.hpp"
#include "asteroid/coalesce_run.hpp"

namespace mrjam {

CoalesceOutcome run_avalanche(const AvalancheSpec& spec, const CoalesceOptions& options);
CoalesceOutcome resume_avalanche(const std::string& checkpoint, const CoalesceOptions& options);

}  // namespace mrjam
