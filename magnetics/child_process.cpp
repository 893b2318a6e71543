#include "magnetics/child_process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "run/interrupt.hpp"

namespace mrjam::magnetics {

ChildResult run_child(const std::vector<std::string>& argv, const std::filesystem::path& log) {
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    const std::string log_path = log.string();
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("cannot start " + argv[0] + " (fork failed)");
    if (pid == 0) {
        // Only async-signal-safe calls between fork and exec (mrjam may have OpenMP threads).
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (getppid() != parent) _exit(127);  // mrjam died before prctl took effect
        const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0) _exit(126);
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        close(fd);
        execv(args[0], args.data());
        _exit(127);
    }
    ChildResult result;
    // Polled rather than blocked on, so that an interrupt seen by mrjam's handler stops the child.
    for (;;) {
        const pid_t done = waitpid(pid, &result.wait_status, WNOHANG);
        if (done == pid) return result;
        if (done < 0) throw std::runtime_error("lost track of " + argv[0] + " (waitpid failed)");
        if (interrupt_requested() && !result.stopped_by_us) {
            kill(pid, SIGTERM);
            result.stopped_by_us = true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

}  // namespace mrjam::magnetics
