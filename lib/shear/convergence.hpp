#pragma once
// The convergence study (`mrjam shear SCENE --converge`): the study's scene run at several cell
// sizes and several seeds at each, every run a point of a sweep (lib/sweep) run as its own mrjam
// process in OUTPUT_DIRECTORY/convergence/points/, resumable by rerunning the command. For each
// size the seeds' flow curves are averaged rate by rate, with the larger of two errors: the seeds'
// spread (their standard error) and the runs' own block errors propagated, since the block error
// of one run misses the structure that differs from seed to seed (2.6 % quoted where five runs
// of one small cell scattered by 11 %). The Bingham fit of the averaged curve is the size's
// yield stress, its error the larger of the fit's and the seeds' Bingham values' standard error.
// The study has converged from the smallest size at which every step to the next larger size
// changes the yield stress by less than the combined error of the two; the converged value is
// the error-weighted mean over those sizes.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "shear/shear_cell.hpp"
#include "shear/shear_spec.hpp"

namespace mrjam {

struct ConvergenceOutcome {
    int exit_status = 0;     // 0, 1 some runs failed (named in the manifest), 130 interrupted
    std::string status;      // complete, failed, interrupted
    nlohmann::json results;  // sizes, converged, yield_stress_Pa ... (see docs/shear.md)
    std::string directory;   // the sweep's folder: points, manifest, table
    double wall_time = 0;
};

ConvergenceOutcome run_convergence(const ShearSpec& spec, const ShearOptions& options);

// One size's runs: their reports (results as `mrjam shear` writes them) to the size's figures.
nlohmann::json size_summary(const ShearSpec& spec, double edge, const std::vector<nlohmann::json>& reports);

// The sizes' summaries (increasing edges) to the study's verdict: converged, from which edge, the value.
nlohmann::json convergence_verdict(const std::vector<nlohmann::json>& sizes);

}  // namespace mrjam
