#pragma once
// The field sweep of a shear study (/field_sweep, Fig. 2.15): the stress at one rate over a list
// of fields. Each field is a shear study of its own, a point of a sweep (lib/sweep) run as its own
// mrjam process in OUTPUT_DIRECTORY/field_sweep/points/, with the sweep's manifest and table
// beside them: its ladder is the main ladder's first rate (the pre-shear that builds the sheared
// structure; a cell sheared from rest is still stiffening, at 600 mT and 100 1/s half the
// pre-sheared stress after a strain of 0.05), then the sweep's rate. An interrupted study resumes
// its field sweep where it stopped: finished fields are kept, the running one resumes from its
// own checkpoint.
#include <nlohmann/json.hpp>
#include <string>

#include "shear/shear_cell.hpp"
#include "shear/shear_spec.hpp"

namespace mrjam {

// A field's shear scene: the study's scene at that field, with the pre-shear and sweep rate as
// its ladder and no field sweep of its own.
nlohmann::json field_point_scene(const ShearSpec& spec);

struct FieldSweepOutcome {
    int exit_status = 0;                            // 0, 130 interrupted, else the first failed field's
    nlohmann::json rows = nlohmann::json::array();  // the finished fields, in the list's order
    std::string error;                              // what the first failed field's log ends with
};

// Runs (or, `resumed`, continues) the field sweep of `spec`. A fresh study first forgets the
// field sweep an earlier study left in the same output directory.
FieldSweepOutcome run_field_sweep(const ShearSpec& spec, const ShearOptions& options, bool resumed);

}  // namespace mrjam
