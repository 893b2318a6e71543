#pragma once
// The scene of `mrjam asteroid spinup` (docs/asteroid.md, "spinup"): a body gathered from a cold
// cloud (the coalescence scene's blocks), settled, then spun up in steps about z (section 4.3 of
// the source: 100 urad/s every 500 s up to 400 urad/s, then every 3000 s).
#include <nlohmann/json.hpp>
#include <string>

#include "asteroid/coalesce_spec.hpp"

namespace mrjam {

struct SpinupSpec {
    CoalesceSpec body;                    // grains, cloud, forces, output; body.duration is the whole run
    double settle_time = 0;               // s, the cloud gathering and settling before the first step
    double increment = 0;                 // rad/s added at each step
    double early_interval = 0;            // s between steps up to early_until
    double early_until = 0;               // rad/s
    double late_interval = 0;             // s between steps beyond it
    double final_spin = 0;                // rad/s, the last step's target
    double deformation_threshold = 0.02;  // relative change of I_zz or of an axis ratio over a step
    double shedding_threshold = 0.01;     // share of the mass leaving the body over a step
    double fission_threshold = 0.1;       // second body's share of the mass

    int steps() const;             // spin steps
    double target(int k) const;    // rad/s after step k (1-based)
    double interval(int k) const;  // s that step k is held
};

// Reads and checks the scene at a tier (quick: 4,000 grains and steps beyond 400 urad/s held
// 1500 s; standard and paper: 32,662 and the source's 3000 s); throws SceneError naming the key.
SpinupSpec read_spinup_spec(const nlohmann::json& scene, const std::string& fidelity);

}  // namespace mrjam
