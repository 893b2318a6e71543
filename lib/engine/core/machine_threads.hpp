#pragma once
// The default thread count of every command: the cores this process may run on (its affinity
// mask, as OpenMP reads it), or OMP_NUM_THREADS when the user set it. Two threads run the
// standard tier's 44 um valve 1.6 times faster than one on this project's idle 2-core machines
// and 1.5 times beside other work (docs/notes/jam_speed.md); a run stays bit for bit the same for
// a given thread count.
#include <omp.h>

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

}  // namespace mrjam
