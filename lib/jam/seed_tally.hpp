#pragma once
// The seeds of one case, as `mrjam jam --seeds N` and `mrjam design` count them from the seed
// records (jam/jam_results.hpp, jam_seed_record): jams, arrests and their times, and the seeds that
// could not be judged.
#include <nlohmann/json.hpp>
#include <vector>

namespace mrjam {

struct SeedTally {
    int seeds = 0;
    int judged = 0;                    // seeds with a no-field flux to measure an arrest against
    int jams = 0;                      // arrests that stopped the flow (with a hold: and held)
    std::vector<double> arrest_times;  // every judged arrest's, held or not
};

SeedTally tally_seeds(const nlohmann::json& records);

// jam_probability, arrest_probability, their 95 % intervals (null with no seed judged) and
// undetermined_seeds.
nlohmann::json seed_probabilities(const SeedTally& tally);

}  // namespace mrjam
