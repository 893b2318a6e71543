#pragma once
// Values that parse and sit in their ranges but cannot run as meant, caught before the first step
// and named by their key (a gravity or a starting speed of 1e308 used to blow up at step 1,
// naming a grain): speeds against the time step, a grain's weight against the contact stiffness.
#include "scene/scene.hpp"

namespace mrjam {

// Refuses (SceneError) a batch whose grains start fast enough to cross half their radius in one
// step (/grains/B: its velocity or random_velocity), a gravity under which a grain would fall
// a tenth of its radius in one step, or whose weight alone would press the heaviest grain into a
// neighbour past run/max_overlap_fraction (/gravity). Call once the step is chosen.
void check_plausible_motion(const Scene& scene);

}  // namespace mrjam
