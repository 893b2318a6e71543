#pragma once
// Runs one sweep point as its own `mrjam` process: a point that crashes or blows up takes only
// itself down, its output goes to its own log, and the same process runs a point alone on a
// cluster node. The child stays in the sweep's process group, so a Ctrl-C at the terminal reaches
// it too and it writes its checkpoint; an interrupt sent to the sweep alone is passed on to it.
#include <functional>
#include <string>
#include <vector>

namespace mrjam {

struct ProcessResult {
    int exit_status = 0;       // the program's, or 128 + the signal that ended it
    bool interrupted = false;  // ended by (or after passing on) an interrupt: to be resumed, not failed
    double wall_seconds = 0;
};

// Runs `program` with `args` (argv[1..]), stdout and stderr appended to `log_path`, and waits,
// calling `while_waiting` every 50 ms. Throws std::runtime_error if the process cannot be started.
ProcessResult run_point_process(const std::string& program, const std::vector<std::string>& args,
                                const std::string& log_path, const std::function<void()>& while_waiting = {});

// This program's own executable (/proc/self/exe resolved).
std::string own_executable();

}  // namespace mrjam
