#pragma once
// Test helpers shared by the suites: a scratch directory removed at scope exit, reading and
// writing whole files, and running the mrjam executable with its output captured.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>

#include "rel_approx.hpp"
#include "report_schema.hpp"

namespace mrjam_test {

struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& prefix = "mrjam_test") {
        static std::atomic<int> counter{0};
        std::random_device rd;
        path = std::filesystem::temp_directory_path() /
               (prefix + "_" + std::to_string(rd()) + "_" + std::to_string(counter++));
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// The whole file; the test fails here if it cannot be read.
inline std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    REQUIRE_MESSAGE(in.good(), "cannot read " << path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    REQUIRE(out.good());
}

inline std::string quote(const std::string& s) { return "'" + s + "'"; }

// Rewrites the checksum that ends a checkpoint (FNV-1a 64 of every byte before it, the format in
// lib/io/checkpoint.cpp), so a test can damage the state behind it and reach the reader's own
// checks rather than the checksum's.
inline void reseal_checkpoint(std::string& bytes) {
    std::uint64_t sum = 0xcbf29ce484222325ull;
    const std::size_t body = bytes.size() - 8;
    for (std::size_t k = 0; k < body; ++k) sum = (sum ^ static_cast<unsigned char>(bytes[k])) * 0x100000001b3ull;
    std::memcpy(bytes.data() + body, &sum, sizeof sum);
}

// A soft (10 MPa) glass with friction and rolling resistance: the material of the engine's
// bit-for-bit tests, soft enough for a long step and with every contact path in use (the scene
// adds `"contact": {"rolling": "epsd"}`).
inline nlohmann::json soft_rolling_glass() {
    return {{"name", "glass"}, {"density", 2500},         {"youngs_modulus", 1e7}, {"restitution", 0.5},
            {"friction", 0.4}, {"rolling_friction", 0.1}, {"rolling_damping", 0.2}};
}

// Chapter 2's carbonyl iron in silicone oil as a shear cell's `material` block (the contact
// parameters the source fitted to its rheometer data, as in examples/shear_trendler_00-100.json).
inline nlohmann::json chapter2_iron() {
    return {{"density", "7800 kg/m3"}, {"youngs_modulus", "1 GPa"},
            {"poisson_ratio", 0.278},  {"restitution", 0.1},
            {"friction", 0.1},         {"rolling_friction", 0.1},
            {"rolling_damping", 0.1},  {"cohesion_energy_density", "60 kJ/m3"}};
}

struct Result {
    int exit_code = -1;
    std::string out, err;
};

#ifdef MRJAM_BINARY
// Runs `BINARY ARGS` with stdout and stderr captured in files of `dir`. `then` is more shell after
// it (e.g. " & pid=$!; ...; wait $pid" to run it in the background and signal it).
inline Result run_binary(const std::string& binary, const TempDir& dir, const std::string& args,
                         const std::string& then = "") {
    static std::atomic<int> counter{0};
    const int k = counter++;
    const std::string out = dir.file("stdout_" + std::to_string(k)), err = dir.file("stderr_" + std::to_string(k));
    const std::string command = quote(binary) + " " + args + " > " + quote(out) + " 2> " + quote(err) + then;
    const int status = std::system(command.c_str());
    Result r;
    REQUIRE(status != -1);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
}

// The report a command line names with `--report 'PATH'` (quoted as quote() does), or "".
inline std::string report_argument(const std::string& args) {
    const std::string key = "--report '";
    const std::size_t at = args.find(key);
    if (at == std::string::npos) return "";
    const std::size_t end = args.find('\'', at + key.size());
    return end == std::string::npos ? "" : args.substr(at + key.size(), end - at - key.size());
}

// Runs mrjam; a report this run wrote (complete, failed or interrupted) must conform to its
// mode's schema (report_schema.hpp).
inline Result mrjam(const TempDir& dir, const std::string& args, const std::string& then = "") {
    const std::string report = report_argument(args);
    std::error_code ec;
    const auto before = std::filesystem::exists(report, ec) ? std::filesystem::last_write_time(report, ec)
                                                            : std::filesystem::file_time_type::min();
    Result r = run_binary(MRJAM_BINARY, dir, args, then);
    if (!report.empty() && std::filesystem::exists(report, ec) &&
        std::filesystem::last_write_time(report, ec) != before) {
        const std::vector<std::string> errors = report_file_schema_errors(report);
        std::string listed;
        for (const std::string& e : errors) listed += "\n  " + e;
        CHECK_MESSAGE(errors.empty(), "the report " << report << " breaks its schema:" << listed);
    }
    return r;
}

// Runs `mrjam ARGS` and sends it SIGINT `delay` seconds after it starts, as Ctrl-C would. Where
// the signal lands is the machine's timing: a run that finished first is tried again with half the
// delay, one stopped before it had anything to keep (`caught` false) with twice the delay, up to
// six tries. A run the signal never caught fails the test rather than passing with nothing checked;
// a run that failed otherwise is returned for the caller's checks to name.
template <class Caught>
Result mrjam_interrupted(const TempDir& dir, const std::string& args, double delay, Caught caught) {
    for (int attempt = 0; attempt < 6; ++attempt) {
        const Result r = mrjam(dir, args, " & pid=$!; sleep " + std::to_string(delay) + "; kill -INT $pid; wait $pid");
        if (r.exit_code == 130 && caught(r)) return r;
        if (r.exit_code != 0 && r.exit_code != 130) return r;
        MESSAGE("the signal after " << delay << " s " << (r.exit_code == 0 ? "came after the run" : "came too early")
                                    << ": trying again");
        delay = r.exit_code == 0 ? 0.5 * delay : 2 * delay;
    }
    FAIL("the signal never landed inside the run in six tries (the last delay " << delay << " s)");
    return {};
}

#ifdef MRJAM_BENCH_BINARY
// `mrjam-bench ARGS`, the benchmarks' executable.
inline Result mrjam_bench(const TempDir& dir, const std::string& args) {
    return run_binary(MRJAM_BENCH_BINARY, dir, args);
}
#endif

// Writes `scene` as NAME.json and runs `mrjam MODE NAME.json --report NAME_report.json --quiet EXTRA`.
inline Result run_mode(const TempDir& dir, const std::string& mode, const std::string& name,
                       const nlohmann::json& scene, const std::string& extra = "") {
    write_text(dir.file(name + ".json"), scene.dump(2));
    return mrjam(dir, mode + " " + quote(dir.file(name + ".json")) + " --report " +
                          quote(dir.file(name + "_report.json")) + " --quiet " + extra);
}

// Writes `scene` and runs it; the report goes next to it.
inline Result run_scene(const TempDir& dir, const std::string& name, const nlohmann::json& scene,
                        const std::string& extra = "") {
    return run_mode(dir, "run", name, scene, extra);
}

// Expects a mode to refuse the scene: exit code 2, stderr naming `path`, and no report (refused
// before any work).
inline Result expect_mode_refused(const TempDir& dir, const std::string& mode, const std::string& label,
                                  const nlohmann::json& scene, const std::string& path, const std::string& extra = "") {
    CAPTURE(label);
    const Result r = run_mode(dir, mode, label, scene, extra);
    CHECK(r.exit_code == 2);
    CAPTURE(r.err);
    CHECK(r.err.find(path) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file(label + "_report.json")));
    return r;
}

inline Result expect_refused(const TempDir& dir, const std::string& label, const nlohmann::json& scene,
                             const std::string& path) {
    return expect_mode_refused(dir, "run", label, scene, path);
}
#endif

}  // namespace mrjam_test
