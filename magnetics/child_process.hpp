#pragma once
// Runs a solver program (GetDP) as a child process with its output in a log file, without a
// shell, so that mrjam stays in charge of it: Ctrl-C sent to mrjam alone (not to its process
// group) stops the child too, and a child never outlives mrjam (it gets SIGTERM if mrjam dies).
#include <filesystem>
#include <string>
#include <vector>

namespace mrjam::magnetics {

struct ChildResult {
    int wait_status = 0;         // as from waitpid
    bool stopped_by_us = false;  // mrjam was interrupted (run/interrupt.hpp) and stopped the child
};

// argv[0] is the program's path. Throws std::runtime_error when the child cannot be started.
ChildResult run_child(const std::vector<std::string>& argv, const std::filesystem::path& log);

}  // namespace mrjam::magnetics
