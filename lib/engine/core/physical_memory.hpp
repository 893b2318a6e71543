#pragma once
// The machine's physical memory, which the grain-count limit (geometry/size_distribution.cpp) and
// the pair-list estimate (lib/scene/memory_estimate.cpp) both bound input-controlled sizes by.
#include <unistd.h>

namespace mrjam {

// In bytes; 0 if the system does not say.
inline double physical_memory_bytes() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? static_cast<double>(pages) * page : 0.0;
}

}  // namespace mrjam
