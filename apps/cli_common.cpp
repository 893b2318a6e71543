#include "cli_common.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

#include "integrator.hpp"
#include "run/runner.hpp"
#include "scene/scene_node.hpp"

namespace mrjam::cli {

void ensure_passive_openmp_wait(char** argv) {
    if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
    if (setenv("OMP_WAIT_POLICY", "passive", 1) != 0) return;
    execv("/proc/self/exe", argv);
}

void prepare_output_file(const std::string& path, const std::string& option, const std::vector<std::string>& inputs) {
    namespace fs = std::filesystem;
    if (path.empty()) throw SceneError(option, "is empty: give a file name such as report.json");
    // "--report --quiet" would write a report named --quiet: a value that looks like an option
    // is a missing value (a file that really starts with '-' can be written ./-name).
    if (path[0] == '-')
        throw SceneError(option, "got '" + path + "', which looks like an option: give " + option + " a file name (./" +
                                     path + " if that is meant)");
    const fs::path p(path);
    if (!p.has_filename() || fs::is_directory(p))
        throw SceneError(option, path + " is a directory: give a file name such as " + (p / "report.json").string());
    // The same file: one path through a link or a "./", or (not written yet) the same path.
    auto same_file = [&](const std::string& input) {
        std::error_code e1, e2, e3;
        if (fs::equivalent(p, input, e1)) return true;
        const fs::path a = fs::weakly_canonical(p, e2), b = fs::weakly_canonical(input, e3);
        return !e2 && !e3 && a == b;
    };
    for (const std::string& input : inputs)
        if (!input.empty() && same_file(input))
            throw SceneError(option, path + " is also this command's input " + input +
                                         ": writing it would lose that; give another file");
    if (p.has_parent_path()) prepare_output_directory(p.parent_path().string(), option);
}

int run_cli(CLI::App& app, int argc, char** argv, const int& exit_status) {
    // CLI11 answers a mistyped subcommand with "A subcommand is required": name it, and the known ones.
    if (argc > 1 && argv[1][0] != '-') {
        std::string known;
        bool found = false;
        for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
            found = found || sub->get_name() == argv[1];
            known += (known.empty() ? "" : ", ") + sub->get_name();
        }
        if (!found) {
            std::cerr << "error: unknown subcommand '" << argv[1] << "'; the subcommands are " << known
                      << " (mrjam --help)\n";
            return kExitBadInput;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : kExitBadInput;
    } catch (const SceneError& e) {
        std::cerr << "error in scene: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const BlowUp& e) {
        std::cerr << "error: " << e.what() << "\n";
        return kExitBlowUp;
    } catch (const SetupInterrupted& e) {
        std::cerr << "[mrjam] " << e.what() << "\n";
        return kExitInterrupted;
    } catch (const std::exception& e) {
        std::cerr << "error: " << e.what() << "\n";
        return kExitError;
    }
    return exit_status;
}

}  // namespace mrjam::cli
