#pragma once
// The mean and the sample standard deviation (n - 1) of a set of values: the spread of
// independent runs (seeds, sweep points), where each run is one sample.
#include <cmath>
#include <vector>

namespace mrjam {

struct MeanSd {
    double mean = 0;
    double sd = 0;  // 0 for fewer than two values
};

inline MeanSd mean_and_sd(const std::vector<double>& v) {
    MeanSd r;
    if (v.empty()) return r;
    for (double x : v) r.mean += x;
    r.mean /= static_cast<double>(v.size());
    if (v.size() < 2) return r;
    double ss = 0;
    for (double x : v) ss += (x - r.mean) * (x - r.mean);
    r.sd = std::sqrt(ss / static_cast<double>(v.size() - 1));
    return r;
}

}  // namespace mrjam
