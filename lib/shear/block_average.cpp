#include "shear/block_average.hpp"

#include <cmath>

namespace mrjam {

BlockAverage block_average(const std::vector<double>& samples, std::size_t blocks) {
    BlockAverage r;
    const std::size_t n = samples.size();
    if (n == 0) return r;
    const std::size_t b = std::max<std::size_t>(1, std::min(blocks, n));
    const std::size_t len = n / b;
    const std::size_t first = n - b * len;
    std::vector<double> means(b, 0.0);
    for (std::size_t k = 0; k < b; ++k) {
        for (std::size_t i = 0; i < len; ++i) means[k] += samples[first + k * len + i];
        means[k] /= static_cast<double>(len);
    }
    double mean = 0;
    for (double m : means) mean += m;
    mean /= static_cast<double>(b);
    double var = 0;
    for (double m : means) var += (m - mean) * (m - mean);
    r.mean = mean;
    r.blocks = b;
    r.samples = b * len;
    r.means = means;
    r.error = b > 1 ? std::sqrt(var / static_cast<double>(b - 1) / static_cast<double>(b)) : 0.0;
    return r;
}

}  // namespace mrjam
