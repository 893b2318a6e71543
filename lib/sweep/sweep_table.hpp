#pragma once
// The sweep's results table: one row per point (its values at the axes' keys, its state and the
// report values the sweep file names), and over the seeds of a `seed` axis one aggregate row per
// remaining combination: for yes/no values the share of yes with its 95 % Wilson interval, for
// numbers the mean and the sample standard deviation, for words how often each occurred.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sweep/sweep_spec.hpp"

namespace mrjam {

struct SweepRow {
    SweepPoint point;
    std::string folder;     // relative to the sweep's folder
    std::string state;      // pending, running, done or failed
    nlohmann::json report;  // null unless done
};

// The table as JSON: {"keys", "outputs", "rows": [{"point", "state", "values", "outputs"}],
// "aggregates": [...] (with a seed axis)}. Throws SceneError naming /outputs/NAME when no done
// point's report has that path.
nlohmann::json sweep_table(const SweepSpec& spec, const std::vector<SweepRow>& rows);

// The rows as CSV: point, state, one column per key, one per output.
std::string sweep_table_csv(const nlohmann::json& table);

// The value at a report path ("results/jammed"); null when absent.
nlohmann::json report_value(const nlohmann::json& report, const std::string& path);

}  // namespace mrjam
