#pragma once
// The default thread count of every command: the cores this process may run on (its affinity
// mask, as OpenMP reads it), or OMP_NUM_THREADS when the user set it. Two threads run the
// standard tier's 44 um valve 1.6 times faster than one on this project's idle 2-core machines
// and 1.5 times beside other work (docs/notes/jam_speed.md); a run stays bit for bit the same for
// a given thread count.
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>

namespace mrjam {

inline int machine_threads() {
    if (const char* env = std::getenv("OMP_NUM_THREADS")) {
        char* end = nullptr;
        const long n = std::strtol(env, &end, 10);
        if (end != env && (*end == '\0' || *end == ',') && n >= 1 && n <= 1024) return static_cast<int>(n);
    }
    const int procs = omp_get_num_procs();
    return procs < 1 ? 1 : (procs > 1024 ? 1024 : procs);
}

// `--threads` left out: the count is chosen once the grains are known (threads_for).
inline constexpr int kAutoThreads = 0;

// Grains a thread needs before it pays for itself: each step's parallel loops wake and park the
// other threads, a fixed cost per loop that a small scene does not cover. Two threads against
// one, the quick shear cell: 0.60 times as fast at 569 grains, 1.07-1.39 times at 1,808, 1.33-1.43
// at 3,626; the 5,463-grain quick valve 1.25 times (docs/notes/jam_speed.md, "Threads by the
// scene's size"). At 800 a second thread starts at 1,600 grains.
inline constexpr std::size_t kGrainsPerThread = 800;

// The threads a scene of `grains` runs on: `requested` when the user gave it (> 0), or
// OMP_NUM_THREADS when set; otherwise the machine's cores, one per kGrainsPerThread grains at most.
inline int threads_for(std::size_t grains, int requested) {
    if (requested > 0) return requested;
    const int cores = machine_threads();
    if (std::getenv("OMP_NUM_THREADS")) return cores;
    const std::size_t by_size = std::max<std::size_t>(1, grains / kGrainsPerThread);
    return static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(cores), by_size));
}

}  // namespace mrjam
