#pragma once
// `mrjam design`: the whole chain for a valve designer. For each constriction: solve the EPM's
// field (magnetics/), write its field map, run the jam predictor in that field over the design's
// seeds, estimate the open valve's flow rate at the supply pressure; then name the widest
// constriction that still jams reliably. Progress is saved after every field solve and seed, so
// an interrupted design resumes where it stopped.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "magnetics/epm_field.hpp"

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

// Solves one constriction's field. The default is GetDP through magnetics::compute_epm_field; a
// test gives its own (an analytic field) to run the chain without the FEM.
using FieldSolver = std::function<magnetics::EpmField(const magnetics::EpmFieldRequest&)>;

// Runs the design and writes its report. Returns the exit status: 0 complete, 2 bad input (also
// thrown as SceneError, naming the key), 3 a jam run blew up, 130 interrupted (the report holds
// what is done and how to resume).
int run_design(const DesignRequest& request, const FieldSolver& solve_field = {});

}  // namespace mrjam
