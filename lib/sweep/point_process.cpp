#include "sweep/point_process.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "run/interrupt.hpp"

namespace mrjam {

std::string own_executable() {
    std::error_code ec;
    const auto path = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error("cannot find this program's executable (/proc/self/exe): " + ec.message());
    return path.string();
}

ProcessResult run_point_process(const std::string& program, const std::vector<std::string>& args,
                                const std::string& log_path, const std::function<void()>& while_waiting) {
    const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log < 0) throw std::runtime_error("cannot open " + log_path + ": " + std::strerror(errno));
    std::vector<std::string> words{program};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);

    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(log);
        throw std::runtime_error(std::string("cannot start a point's process: ") + std::strerror(errno));
    }
    if (pid == 0) {  // the child: only async-signal-safe calls until exec
        ::dup2(log, STDOUT_FILENO);
        ::dup2(log, STDERR_FILENO);
        ::execv(program.c_str(), argv.data());
        ::_exit(127);
    }
    ::close(log);
    ProcessResult result;
    bool passed_on = false;
    int status = 0;
    for (;;) {
        const pid_t done = ::waitpid(pid, &status, WNOHANG);
        if (done == pid) break;
        if (done < 0 && errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        if (interrupt_requested() && !passed_on) {
            ::kill(pid, SIGINT);  // the child checkpoints and exits 130
            passed_on = true;
        }
        if (while_waiting) while_waiting();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.interrupted = passed_on || interrupt_requested() || result.exit_status == 130;
    return result;
}

}  // namespace mrjam
