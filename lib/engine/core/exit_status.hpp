#pragma once
// The exit statuses every subcommand uses, and the library functions that run a whole job
// (a design, a sweep) return.

namespace mrjam {

inline constexpr int kExitOk = 0;
inline constexpr int kExitError = 1;          // a fault: a solver that failed, a file that could not be written
inline constexpr int kExitBadInput = 2;       // input refused, with the key and the fix named
inline constexpr int kExitBlowUp = 3;         // a run went unstable (its report says why)
inline constexpr int kExitInterrupted = 130;  // Ctrl-C: the work done is saved, and how to resume is said

}  // namespace mrjam
