#include "sweep/sweep_run.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "core/machine_threads.hpp"
#include "run/interrupt.hpp"
#include "scene/scene_file.hpp"
#include "scene/scene_node.hpp"
#include "sweep/point_process.hpp"
#include "sweep/point_queue.hpp"
#include "sweep/sweep_plots.hpp"
#include "sweep/sweep_spec.hpp"
#include "sweep/sweep_table.hpp"

namespace mrjam {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// A file the sweep wrote itself (state, registry, report); null if absent or cut short.
json read_state_file(const fs::path& path) { return read_own_json_file(path.string()); }

// A temporary name no other process (a shard on this or another machine) uses.
fs::path temporary_for(const fs::path& path) {
    char host[64] = "";
    gethostname(host, sizeof host - 1);
    return path.string() + ".tmp." + host + "." + std::to_string(getpid());
}

// Written whole or not at all: a kill mid-write leaves the previous file.
void write_text_file(const fs::path& path, const std::string& text) {
    const fs::path tmp = temporary_for(path);
    {
        std::ofstream out(tmp);
        out << text;
        if (!out) throw std::runtime_error("failed writing " + tmp.string());
    }
    fs::rename(tmp, path);
}

void write_json_file(const fs::path& path, const json& value) { write_text_file(path, value.dump(1) + "\n"); }

std::string numbered_folder(std::size_t n) {
    char b[16];
    std::snprintf(b, sizeof b, "p%04zu", n);
    return b;
}

// A sweep run: what it sweeps, how, and how its points run.
struct Sweep {
    const SweepSpec& spec;
    const SweepOptions& o;
    const SweepEngine& engine;

    fs::path folder_of(const json& entry) const {
        return fs::absolute(fs::path(o.out_dir) / engine.points_directory / entry["folder"].get<std::string>());
    }
    std::string relative_folder(const json& entry) const {
        return (fs::path(engine.points_directory) / entry["folder"].get<std::string>()).generic_string();
    }
};

// The paths at which two sweep files differ, for the refusal's message.
std::string differences(const json& before, const json& now) {
    std::string out;
    std::set<std::string> seen;
    for (const json& op : json::diff(before, now)) {
        const std::string path = op["path"].get<std::string>();
        if (seen.insert(path).second) out += (out.empty() ? "" : ", ") + (path.empty() ? std::string("/") : path);
        if (seen.size() == 8) return out + ", ...";
    }
    return out;
}

// DIR/sweep.json: the sweep file and each point's folder, so folders keep their points when
// --extend adds new ones. Returns the registry's points, in folder order.
json open_registry(const Sweep& sw, const std::vector<SweepPoint>& points, bool writer) {
    const SweepOptions& o = sw.o;
    const SweepSpec& spec = sw.spec;
    const fs::path dir(o.out_dir), file = dir / "sweep.json";
    json registry = read_state_file(file);
    if (registry.is_null()) {
        std::error_code ec;
        if (writer && !sw.engine.directory_holds_other_files && fs::exists(dir, ec) && !fs::is_empty(dir, ec))
            throw SceneError("--out", o.out_dir + " holds files that are not a sweep's: choose a new or empty folder");
        if (o.collect) throw SceneError("--out", o.out_dir + " holds no sweep to collect");
        registry = {{"sweep", spec.source}, {"points", json::array()}};
    } else if (registry["sweep"] != spec.source) {
        if (!o.extend)
            throw SceneError("--out", o.out_dir + " was written by another sweep file (it differs at " +
                                          differences(registry["sweep"], spec.source) +
                                          "): use a new folder, or --extend to add only new points");
        for (const char* k : {"mode", "args", "scene"})
            if (registry["sweep"].value(k, json()) != spec.source.value(k, json()))
                throw SceneError(std::string("/") + k,
                                 "differs from the sweep in " + o.out_dir +
                                     ": --extend adds points, it does not change the scene or the mode");
        registry["sweep"] = spec.source;
    }
    std::set<std::string> known;
    for (const json& p : registry["points"]) known.insert(p["values"].dump());
    for (const SweepPoint& p : points)
        if (!known.count(p.values.dump())) {
            const std::size_t n = registry["points"].size();
            const std::string folder = sw.engine.folder_name ? sw.engine.folder_name(n, p.values) : numbered_folder(n);
            registry["points"].push_back({{"folder", folder}, {"values", p.values}});
        }
    if (!o.collect && writer) {
        fs::create_directories(dir / sw.engine.points_directory);
        write_json_file(file, registry);
    }
    return registry["points"];
}

// What a point's run is: fresh, or resumed from the checkpoint its mode left in out/.
std::vector<std::string> point_command(const SweepSpec& spec, const SweepOptions& o, const fs::path& folder) {
    const std::string mode = spec.command.front();
    std::vector<std::string> args = spec.command;
    fs::path checkpoint;
    std::error_code ec;
    if (mode != "design" && mode != "magnetics" && fs::is_directory(folder / "out", ec))
        for (const auto& e : fs::directory_iterator(folder / "out"))
            if (e.path().extension() == ".mrjam") checkpoint = e.path();
    if (!checkpoint.empty()) {
        args.insert(args.end(), {"--resume", checkpoint.string()});  // the run keeps its own settings
    } else {
        args.push_back((folder / "scene.json").string());
        if (mode == "design" && fs::exists(folder / "out", ec)) args.push_back("--resume");
        args.insert(args.end(), spec.args.begin(), spec.args.end());
    }
    args.insert(args.end(), {"--report", (folder / "report.json").string()});
    // Without a count (one point at a time, none given) each run chooses from its own grains.
    if (mode != "magnetics" && o.threads > 0) args.insert(args.end(), {"--threads", std::to_string(o.threads)});
    return args;
}

std::string last_line(const fs::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line))
        if (!line.empty()) last = line;
    return last;
}

// A value as a progress line shows it: words as written, numbers to 6 figures (4e-05, not
// 3.9999999999999996e-05), lists of them in brackets.
std::string shown(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number_float()) {
        char b[32];
        std::snprintf(b, sizeof b, "%.6g", v.get<double>());
        return b;
    }
    if (!v.is_array()) return v.dump();
    std::string out = "[";
    for (const json& e : v) out += (out.size() > 1 ? "," : "") + shown(e);
    return out + "]";
}

std::string describe(const json& values) {
    std::string out;
    for (const auto& [k, v] : values.items()) out += (out.empty() ? "" : ", ") + k + "=" + shown(v);
    return out;
}

struct Tally {
    std::size_t to_run = 0, ran = 0, failed = 0;
    double wall = 0;
};

// A log's lines as they are written, passed on to stderr.
class LogEcho {
public:
    explicit LogEcho(fs::path log) : log_(std::move(log)) {
        std::error_code ec;
        offset_ = fs::exists(log_, ec) ? fs::file_size(log_, ec) : 0;  // an earlier attempt's lines were shown then
    }
    void pass_on() {
        std::ifstream in(log_, std::ios::binary);
        if (!in.seekg(static_cast<std::streamoff>(offset_))) return;
        std::string line;
        while (std::getline(in, line) && !in.eof()) {  // whole lines only: the rest is still being written
            std::cerr << line << "\n";
            offset_ += line.size() + 1;
        }
    }

private:
    fs::path log_;
    std::uintmax_t offset_ = 0;
};

// The default point: its own mrjam process, its output in its log (and on stderr when echoed).
ProcessResult run_point_as_process(const Sweep& sw, const fs::path& folder,
                                   const std::function<void()>& while_waiting) {
    const fs::path log = folder / "log.txt";
    LogEcho echo(log);
    const auto wait = [&] {
        if (sw.engine.echo_output) echo.pass_on();
        while_waiting();
    };
    const ProcessResult r =
        run_point_process(own_executable(), point_command(sw.spec, sw.o, folder), log.string(), wait);
    if (sw.engine.echo_output) echo.pass_on();
    return r;
}

// Runs one point; false if the sweep was interrupted during it. `shared` guards the tally and the
// terminal when points run side by side.
bool run_point(const Sweep& sw, const json& entry, Tally& tally, PointQueue& queue, std::mutex& shared) {
    const SweepSpec& spec = sw.spec;
    const SweepOptions& o = sw.o;
    const fs::path folder = sw.folder_of(entry);
    fs::create_directories(folder);
    json state = read_state_file(folder / "state.json");
    if (state.is_null()) state = {{"state", "pending"}, {"attempts", 0}};
    SweepPoint point{0, entry["values"]};
    if (!fs::exists(folder / "scene.json"))
        write_json_file(folder / "scene.json", point_scene(spec, point, (folder / "out").string()));
    state["state"] = "running";
    state["attempts"] = state["attempts"].get<int>() + 1;
    write_json_file(folder / "state.json", state);
    // Rank 0 of an MPI sweep keeps handing out points while its own runs.
    const auto serve = [&queue] { queue.serve(); };
    const ProcessResult r =
        sw.engine.run_point ? sw.engine.run_point(point, folder, serve) : run_point_as_process(sw, folder, serve);
    state["wall_s"] = state.value("wall_s", 0.0) + r.wall_seconds;
    state["exit_status"] = r.exit_status;
    state.erase("error");
    if (r.interrupted) {
        state["state"] = "pending";
    } else if (r.exit_status == 0 && fs::exists(folder / "report.json")) {
        state["state"] = "done";
    } else {
        state["state"] = "failed";
        if (fs::exists(folder / "log.txt")) state["error"] = last_line(folder / "log.txt");
    }
    write_json_file(folder / "state.json", state);
    if (r.interrupted) return false;
    const std::lock_guard<std::mutex> lock(shared);
    ++tally.ran;
    tally.failed += state["state"] == "failed";
    tally.wall += r.wall_seconds;
    if (o.progress) {
        const double left = tally.wall / static_cast<double>(tally.ran) *
                            static_cast<double>(tally.to_run - tally.ran) / std::max(1, o.jobs);
        std::cerr << "[" << sw.engine.label
                  << (queue.size() > 1 ? " rank " + std::to_string(queue.rank()) : std::string()) << "] ";
        if (queue.size() == 1) std::cerr << tally.ran << "/" << tally.to_run << " ";
        std::cerr << entry["folder"].get<std::string>() << " (" << describe(entry["values"])
                  << "): " << state["state"].get<std::string>() << " in " << static_cast<long>(r.wall_seconds) << " s";
        if (tally.failed) std::cerr << "; " << tally.failed << " failed";
        if (queue.size() == 1 && tally.ran < tally.to_run)
            std::cerr << "; about " << static_cast<long>(left / 60 + 0.5) << " min left";
        std::cerr << "\n";
    }
    return true;
}

// The points handed out by the queue, `jobs` at a time in worker threads that each wait on a
// point's process; returns whether the sweep was interrupted.
bool run_points(const Sweep& sw, const std::vector<const json*>& mine, Tally& tally, PointQueue& queue, int jobs) {
    std::mutex shared;
    bool interrupted = false;
    const auto work = [&] {
        for (;;) {
            std::optional<std::size_t> k;
            {
                const std::lock_guard<std::mutex> lock(shared);
                if (interrupted || interrupt_requested()) return;
                k = queue.next();
            }
            if (!k) return;
            if (!run_point(sw, *mine[*k], tally, queue, shared)) {
                const std::lock_guard<std::mutex> lock(shared);
                interrupted = true;
            }
        }
    };
    if (jobs <= 1) {
        work();
    } else {
        std::vector<std::thread> workers;
        for (int j = 0; j < jobs; ++j) workers.emplace_back(work);
        for (std::thread& w : workers) w.join();
    }
    return interrupted || interrupt_requested();
}

// The points of the current sweep file, by their values (the registry may hold more: a file
// accepted with --extend that dropped a value keeps that value's folders).
std::set<std::string> current_values(const std::vector<SweepPoint>& points) {
    std::set<std::string> current;
    for (const SweepPoint& p : points) current.insert(p.values.dump());
    return current;
}

// DIR/manifest.json, table.json and table.csv from every point's folder.
void write_results(const Sweep& sw, const std::vector<SweepPoint>& points, const json& registry_points) {
    const SweepSpec& spec = sw.spec;
    const fs::path dir(sw.o.out_dir);
    std::vector<SweepRow> rows;
    json manifest{{"points", json::array()}};
    const std::set<std::string> current = current_values(points);
    for (const json& entry : registry_points) {
        if (!current.count(entry["values"].dump())) continue;
        const fs::path folder = sw.folder_of(entry);
        json state = read_state_file(folder / "state.json");
        if (state.is_null()) state = {{"state", "pending"}, {"attempts", 0}};
        SweepRow row{SweepPoint{0, entry["values"]}, sw.relative_folder(entry), state["state"].get<std::string>(),
                     json()};
        if (row.state == "done") row.report = read_state_file(folder / "report.json");
        rows.push_back(row);
        json m = state;
        m["folder"] = row.folder;
        m["values"] = entry["values"];
        manifest["points"].push_back(m);
    }
    json table = sweep_table(spec, rows);
    table["plots"] = json::array();
    for (const std::string& f : write_sweep_plots(spec, table, dir.string()))
        table["plots"].push_back(fs::path(f).filename().string());
    write_json_file(dir / "manifest.json", manifest);
    write_json_file(dir / "table.json", table);
    write_text_file(dir / "table.csv", sweep_table_csv(table));
}

// The registry's points this process may run: not done, in the current sweep, in its shard.
std::vector<const json*> points_to_run(const Sweep& sw, const std::vector<SweepPoint>& points,
                                       const json& registry_points) {
    const SweepOptions& o = sw.o;
    const std::set<std::string> current = current_values(points);
    std::vector<const json*> mine;
    for (std::size_t n = 0; n < registry_points.size() && !o.collect; ++n) {
        const json& entry = registry_points[n];
        const json state = read_state_file(sw.folder_of(entry) / "state.json");
        const bool done = !state.is_null() && state["state"] == "done";
        if (!done && current.count(entry["values"].dump()) && static_cast<int>(n % o.shards) == o.shard)
            mine.push_back(&entry);
    }
    return mine;
}

}  // namespace

json read_point_state(const fs::path& folder) { return read_state_file(folder / "state.json"); }

std::string sweep_changed_at(const fs::path& directory, const json& source) {
    const json registry = read_state_file(directory / "sweep.json");
    if (!registry.is_object() || !registry.contains("sweep") || registry["sweep"] == source) return "";
    return differences(registry["sweep"], source);
}

int run_sweep(const SweepOptions& options) {
    if (options.shards < 1 || options.shard < 0 || options.shard >= options.shards)
        throw SceneError("--shard", "I/N with 0 <= I < N, e.g. 0/4 for the first of four shards");
    const json file = read_json_file(options.sweep_path);
    const SweepSpec spec = read_sweep(file, fs::absolute(options.sweep_path).parent_path().string());
    return run_sweep_spec(spec, options, SweepEngine{});
}

int run_sweep_spec(const SweepSpec& spec, const SweepOptions& options, const SweepEngine& engine, bool* is_leader) {
    SweepOptions o = options;
    const Sweep sw{spec, o, engine};
    const std::vector<SweepPoint> points = sweep_points(spec);
    if (points.size() > kMostPointsUnasked && !o.yes && !o.collect)
        throw SceneError("--yes", "the sweep has " + std::to_string(points.size()) + " points (more than " +
                                      std::to_string(kMostPointsUnasked) + "): confirm with --yes");
    const std::unique_ptr<PointQueue> queue = engine.spread_over_ranks ? make_point_queue() : make_local_queue();
    if (is_leader) *is_leader = queue->leader();
    if (o.jobs < 1) throw SceneError("--jobs", "give at least 1");
    if (o.jobs > 1 && queue->size() > 1)
        throw SceneError("--jobs", "runs points side by side in one process: under mpirun, start more ranks instead");
    // Only processes run side by side; a mode's own points run one at a time in it.
    if (engine.run_point) o.jobs = 1;
    // Ranks on one node would share its cores: one thread each unless told; jobs share them too.
    // One point at a time takes the automatic count (threads_for: by the point's grains).
    if (o.threads <= 0)
        o.threads = queue->size() > 1 ? 1 : (o.jobs > 1 ? std::max(1, machine_threads() / o.jobs) : kAutoThreads);
    // The leader writes the registry; the others read it once it is there.
    json registry_points = queue->leader() ? open_registry(sw, points, true) : json();
    queue->synchronise();
    if (!queue->leader()) registry_points = open_registry(sw, points, false);
    install_interrupt_handler();
    const std::vector<const json*> mine = points_to_run(sw, points, registry_points);
    queue->set_count(mine.size());
    queue->synchronise();  // every process has read the states before any point runs
    Tally tally;
    tally.to_run = mine.size();
    if (o.progress && !o.collect && queue->leader())
        std::cerr << "[" << engine.label << "] " << points.size() << " points, " << points.size() - mine.size()
                  << " done or in other shards; running " << mine.size()
                  << (queue->size() > 1 ? " on " + std::to_string(queue->size()) + " ranks" : std::string())
                  << (o.jobs > 1 ? ", " + std::to_string(o.jobs) + " at a time, " + std::to_string(o.threads) +
                                       " thread(s) each"
                                 : std::string())
                  << "\n";
    const bool interrupted = run_points(sw, mine, tally, *queue, o.jobs);
    queue->finish();
    if (queue->leader()) write_results(sw, points, registry_points);
    if (interrupted) {
        if (o.progress && queue->leader() && engine.label == "sweep")
            std::cerr << "[sweep] interrupted: rerun the same command to continue\n";
        return 130;
    }
    return tally.failed > 0 ? 1 : 0;
}

}  // namespace mrjam
