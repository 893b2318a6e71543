#pragma once
// Mean of a correlated time series with an honest error bar: split the series into consecutive
// blocks, average each, and take the standard error of the block means (Flyvbjerg and Petersen
// 1989). Blocks longer than the correlation time are nearly independent, so the error then
// stops depending on the block length; for independent samples it reduces to sigma / sqrt(n).
#include <cstddef>
#include <vector>

namespace mrjam {

struct BlockAverage {
    double mean = 0;
    double error = 0;           // standard error of the mean from the block means (0 for one block)
    std::size_t blocks = 0;     // blocks actually used
    std::size_t samples = 0;    // samples used (a remainder that does not fill a block is dropped from the front)
    std::vector<double> means;  // each block's mean, oldest first
};

// `blocks` blocks of equal length (fewer if there are fewer samples). The oldest samples are the
// ones dropped when the count does not divide, since the newest are closest to steady state.
BlockAverage block_average(const std::vector<double>& samples, std::size_t blocks);

}  // namespace mrjam
