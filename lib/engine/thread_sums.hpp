// Per-grain sums (forces, torques, fields) shared by the threads of a pair loop split by owner.
//
// A pair (i, j) adds to both grains, and j may belong to another thread's slice, so each thread
// but the first accumulates into a private array; thread 0 writes straight into the shared one.
// After a barrier each thread adds the private arrays into its own slice of grains, in thread
// order, so a sum is the same from run to run for a given thread count.
//
//   sums.resize(threads);                       // before the parallel region
//   Vec3* f = sums.target(tid, force);          // inside it, per thread
//   ... pair loop over grains [begin, end) ...
//   #pragma omp barrier
//   sums.reduce_into(force, begin, end);
#pragma once

#include <cstddef>
#include <vector>

#include "core/vec3.hpp"

namespace mrjam {

class PerThreadSums {
public:
    void resize(int threads) { buffers_.resize(threads > 1 ? threads : 1); }

    // The array thread `tid` accumulates into: `shared` itself for thread 0, otherwise a zeroed
    // private array of the same size.
    Vec3* target(int tid, std::vector<Vec3>& shared) {
        if (tid == 0) return shared.data();
        buffers_[tid].assign(shared.size(), Vec3{});
        return buffers_[tid].data();
    }

    // Adds the private arrays of threads 1.. into shared[begin, end), in thread order.
    void reduce_into(std::vector<Vec3>& shared, std::size_t begin, std::size_t end) const {
        for (std::size_t other = 1; other < buffers_.size(); ++other) {
            const Vec3* from = buffers_[other].data();
            for (std::size_t i = begin; i < end; ++i) shared[i] += from[i];
        }
    }

private:
    std::vector<std::vector<Vec3>> buffers_;
};

}  // namespace mrjam
