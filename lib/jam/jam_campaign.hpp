#pragma once
// `mrjam jam` as a library function: a jam scene over N seeds (independent packings), each run
// as jam_run.hpp runs one, tallied into the jam probability with its interval; or, at the
// continuum tier, the Bingham plug. Resumable: every checkpoint carries the campaign's record
// (the scene, the seed running, the seeds done), so `--resume` goes on where it stopped.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

namespace mrjam {

struct JamCampaignRequest {
    std::string scene_path;  // the scene file ("" when resuming)
    nlohmann::json scene;    // its contents, as read
    std::string resume;      // the checkpoint to resume from ("" for a fresh campaign)
    std::string report_path = "jam_report.json";
    std::string fidelity = "standard";
    int seeds = 1;
    bool seeds_given = false;  // said by the user (the continuum tier refuses it)
    int threads = 1;
    bool progress = true;
    std::string snapshots;                 // VTK snapshot directory ("" for none)
    std::string snapshot_every;            // as the user wrote it ("" for 20 frames)
    std::function<void(int)> before_seed;  // for tests: called with each seed's index before it is built
};

// Runs the campaign and writes its report. Returns the exit status: 0 complete, 1 no seed could
// be judged, 3 a run blew up, 130 interrupted (the partial report says how to resume). Bad input
// is thrown as SceneError, naming the key or the option.
int run_jam_campaign(const JamCampaignRequest& request);

}  // namespace mrjam
