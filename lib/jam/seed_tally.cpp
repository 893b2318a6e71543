#include "jam/seed_tally.hpp"

#include <string>

#include "core/proportion_interval.hpp"

namespace mrjam {

SeedTally tally_seeds(const nlohmann::json& records) {
    SeedTally t;
    for (const auto& run : records) {
        ++t.seeds;
        // A report from before the clog was named ("undetermined": no no-field flux) is left out of
        // the probabilities; a clog now counts as stopping the flow (stops_flow).
        if (run.value("outcome", std::string()) == "undetermined") continue;
        ++t.judged;
        const bool arrested = run["time_to_arrest_s"].is_number();  // a number exactly when the seed arrested
        if (arrested) t.arrest_times.push_back(run["time_to_arrest_s"].get<double>());
        t.jams += run.value("stops_flow", arrested);  // checkpoints from before stops_flow: the arrest alone
    }
    return t;
}

nlohmann::json seed_probabilities(const SeedTally& t) {
    const int arrests = static_cast<int>(t.arrest_times.size());
    auto share = [&](int k) {
        return t.judged > 0 ? nlohmann::json(static_cast<double>(k) / t.judged) : nlohmann::json(nullptr);
    };
    auto interval = [&](int k) {
        if (t.judged == 0) return nlohmann::json(nullptr);
        const ProportionInterval ci = wilson_interval(k, t.judged);
        return nlohmann::json::array({ci.low, ci.high});
    };
    return {{"jam_probability", share(t.jams)},
            {"arrest_probability", share(arrests)},
            {"jam_probability_95ci", interval(t.jams)},
            {"arrest_probability_95ci", interval(arrests)},
            {"undetermined_seeds", t.seeds - t.judged}};
}

}  // namespace mrjam
