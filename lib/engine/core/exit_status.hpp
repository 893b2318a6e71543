#pragma once
// The exit statuses every subcommand uses, and the library functions that run a whole job
// (a design, a sweep) return.

#include <stdexcept>

namespace mrjam {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;          // a fault: a solver that failed, a file that could not be written
inline constexpr int kExitBadInput = 2;       // input refused, with the key and the fix named
inline constexpr int kExitBlowUp = 3;         // a run went unstable (its report says why)
inline constexpr int kExitInterrupted = 130;  // Ctrl-C: the work done is saved, and how to resume is said

// Ctrl-C or SIGTERM during a set-up (packing grains) that has nothing to save yet: answered at
// once with exit 130 rather than at the first step, which a long set-up would not reach for minutes.
struct SetupInterrupted : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace mrjam
