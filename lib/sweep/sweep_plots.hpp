#pragma once
// The sweep file's plots: an output against a swept key, a line per value of another, as SVG
// next to the table. Over a seed axis each point is the aggregate: the share of yes with its 95 %
// Wilson interval, or the mean with the seeds' standard deviation as bars. When other keys take
// several values, one picture per combination of them, its title naming them.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sweep/sweep_spec.hpp"

namespace mrjam {

// Writes DIR/plot_OUTPUT_vs_KEY[_N].svg for every plot of the spec; returns the files written.
std::vector<std::string> write_sweep_plots(const SweepSpec& spec, const nlohmann::json& table, const std::string& dir);

}  // namespace mrjam
