#pragma once
// One constriction of a `mrjam design`, a point of the design's sweep over its constrictions:
// solve the EPM's field, write its field map, run the jam predictor in that field over the
// design's seeds, estimate the open valve's flow at the supply pressure. Its folder keeps the
// field map, every seed's jam report, its progress (design_progress.hpp) and, when it ends,
// report.json: {"status", "constriction", "row"} where row is the design report's row, or
// {"status": "interrupted" | "failed", "stopped": {where and why}}.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "design/design_scenes.hpp"
#include "magnetics/epm_field.hpp"

namespace mrjam {

// Solves one constriction's field. The default is GetDP through magnetics::compute_epm_field; a
// test gives its own (an analytic field) to run the chain without the FEM.
using FieldSolver = std::function<magnetics::EpmField(const magnetics::EpmFieldRequest&)>;

struct ConstrictionRequest {
    std::size_t index = 0;         // in the design's list
    std::filesystem::path folder;  // its files
    std::string jam_tier, magnetics_tier;
    int threads = 1;
    bool progress = true;
    bool resume = false;  // continue from the folder's progress record
};

// Runs the constriction, writes folder/report.json and returns the exit status: 0 done, 3 (or
// another run's status) a jam run that stopped, 130 interrupted. Throws SceneError for input the
// jam run refuses once its step is known, named from the design file's root.
int run_constriction(const DesignSpec& spec, const ConstrictionRequest& request, const FieldSolver& solve);

}  // namespace mrjam
