#pragma once
// `mrjam design`: the whole chain for a valve designer. For each constriction
// (design/constriction_run.hpp): solve the EPM's field (magnetics/), write its field map, run the
// jam predictor in that field over the design's seeds, estimate the open valve's flow rate at the
// supply pressure; then name the widest constriction that still jams reliably. The constrictions
// are the points of a sweep (lib/sweep) run in this process, in OUTPUT_DIRECTORY/<constriction>/,
// with the sweep's manifest, table (table.csv) and plots of jam probability and open flow against
// the constriction beside them. Progress is saved after every field solve and seed, so an
// interrupted design resumes where it stopped; a constriction whose run fails does not stop the others.
#include <nlohmann/json.hpp>
#include <string>

#include "design/constriction_run.hpp"

namespace mrjam {

struct DesignRequest {
    std::string scene_path;  // the design file, as the report names it
    nlohmann::json design;   // its contents
    std::string report_path = "design_report.json";
    std::string fidelity = "quick";  // the jam tier: quick, standard or paper
    bool fidelity_given = false;     // said by the user (a resume refuses another tier than its own)
    int threads = 1;
    bool progress = true;  // progress lines on stderr
    bool resume = false;   // continue the interrupted design of this file
};

// Runs the design and writes its report. Returns the exit status: 0 complete, 2 bad input (also
// thrown as SceneError, naming the key), 3 a jam run blew up (1 a field solve failed): the first
// failed constriction's, after the others have run; 130 interrupted (the report holds what is done
// and how to resume).
int run_design(const DesignRequest& request, const FieldSolver& solve_field = {});

}  // namespace mrjam
