#include "design/design_workflow.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>

#include "core/exit_status.hpp"
#include "design/design_progress.hpp"
#include "design/design_scenes.hpp"
#include "design/design_summary.hpp"
#include "magnetics/getdp_problem.hpp"
#include "run/interrupt.hpp"
#include "run/runner.hpp"
#include "scene/scene_file.hpp"
#include "scene/scene_node.hpp"
#include "sweep/sweep_run.hpp"

namespace mrjam {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kConstrictionKey = "constrictions/0";

// The design's constrictions as a sweep: the design file with one constriction, that entry swept
// over the list; tabulated and plotted by jam probability, open flow and the field at the throat.
SweepSpec constriction_sweep(const DesignSpec& spec, const std::string& jam_tier) {
    SweepSpec s;
    s.command = {"design"};
    s.args = {"--fidelity", jam_tier};
    s.base_scene = spec.design;
    s.base_scene["constrictions"] = json::array({spec.design["constrictions"][0]});
    s.base_directory = spec.base_directory;
    SweepAxis axis;
    axis.keys = {kConstrictionKey};
    for (const json& c : spec.design["constrictions"]) axis.values.push_back({c});
    s.axes = {axis};
    s.outputs = {{"jam_probability", "row/jam_probability", "row/jam_probability_95ci"},
                 {"open_flow_ml_min", "row/open_flow_rate_ml_min"},
                 {"throat_B_T", "row/B_on_axis/throat_centre_T"}};
    // Presets plot by their number (Nx: a throat N times 44 um wide), diameters in metres.
    const std::string x_label = "constriction (Nx: throat of N x 44 um)";
    s.plots = {{"jam_probability", kConstrictionKey, "", "Jam probability against the constriction", x_label,
                "jam probability over the seeds (95 % Wilson interval)"},
               {"open_flow_ml_min", kConstrictionKey, "", "Open valve's flow at the supply pressure", x_label,
                "open flow (ml/min)"}};
    s.source = {{"design", spec.design}, {"fidelity", jam_tier}};
    return s;
}

// What the constrictions' folders say once the sweep has run.
struct DesignResults {
    json rows = json::array();  // the finished constrictions' rows, in the design's order
    std::string widest;         // the widest that jams reliably ("" for none)
    json interrupted_at;        // where the interrupted constriction stopped
    json failed_at;             // where the first constriction that failed stopped
    int failed_status = kExitOk;
};

class DesignWorkflow {
public:
    DesignWorkflow(const DesignRequest& request, FieldSolver solve)
        : req_(request), spec_(read_design_spec(request.design, request.scene_path)), solve_(std::move(solve)) {
        if (req_.resume) {
            progress_ =
                read_design_progress(spec_.output_directory, req_.design, req_.fidelity_given ? req_.fidelity : "");
            req_.fidelity = progress_.fidelity;
        } else {
            progress_.inputs = req_.design;
            progress_.fidelity = req_.fidelity;
        }
        magnetics_tier_ = req_.fidelity == "paper" ? "paper" : "standard";  // 2D is too far off to design with
        resume_hint_ = "mrjam design " + req_.scene_path + " --resume --report " + req_.report_path;
    }

    int run() {
        if (!solve_) {
            if (magnetics::find_getdp().empty()) {
                std::cerr << "error: getdp was not found on PATH; install it with `apt-get install getdp`\n";
                return kExitBadInput;
            }
            solve_ = [](const magnetics::EpmFieldRequest& r) { return magnetics::compute_epm_field(r); };
        }
        check_design_scenes(spec_, magnetics_tier_, req_.fidelity);
        prepare_output_directory(spec_.output_directory.string(), "/output/directory");
        // Ctrl-C from here on writes the design report of what is done (exit 130); without the
        // handler, an interrupt during a field solve would end the process with nothing written.
        install_interrupt_handler();
        if (!req_.resume) forget_earlier_design();
        save_progress();
        const int status = run_sweep_spec(constriction_sweep(spec_, req_.fidelity), sweep_options(), engine());
        save_progress();
        return finish(status, collect());
    }

private:
    fs::path folder(std::size_t c) const { return spec_.output_directory / spec_.constrictions[c].first; }

    std::size_t index_of(const json& values) const {
        const json& name = values.at(kConstrictionKey);
        for (std::size_t c = 0; c < spec_.constrictions.size(); ++c)
            if (name == spec_.design["constrictions"][c]) return c;
        throw std::logic_error("design: a sweep point that is not one of the design's constrictions");
    }

    // A fresh design in a directory that held another starts every constriction again.
    void forget_earlier_design() const {
        for (const char* f : {"sweep.json", "manifest.json", "table.json", "table.csv"})
            fs::remove(spec_.output_directory / f);
        for (std::size_t c = 0; c < spec_.constrictions.size(); ++c) {
            fs::remove(folder(c) / "state.json");
            fs::remove(folder(c) / "report.json");
            fs::remove(constriction_progress_path(folder(c)));
        }
    }

    SweepOptions sweep_options() const {
        SweepOptions o;
        o.out_dir = spec_.output_directory.string();
        o.threads = req_.threads;
        o.progress = req_.progress;
        o.yes = true;  // the list is the user's own
        return o;
    }

    // The constrictions run here, one after another, in folders named by the constriction.
    SweepEngine engine() {
        SweepEngine e;
        e.label = "design";
        e.points_directory = "";
        e.directory_holds_other_files = true;
        e.spread_over_ranks = false;
        e.folder_name = [this](std::size_t, const json& values) { return spec_.constrictions[index_of(values)].first; };
        e.run_point = [this](const SweepPoint& point, const fs::path& dir, const std::function<void()>&) {
            ConstrictionRequest r;
            r.index = index_of(point.values);
            r.folder = dir;
            r.jam_tier = req_.fidelity;
            r.magnetics_tier = magnetics_tier_;
            r.threads = req_.threads;
            r.progress = req_.progress;
            r.resume = req_.resume;
            const auto start = std::chrono::steady_clock::now();
            ProcessResult result;
            result.exit_status = run_constriction(spec_, r, solve_);
            result.interrupted = result.exit_status == kExitInterrupted;
            result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return result;
        };
        return e;
    }

    DesignResults collect() const {
        DesignResults out;
        double widest_diameter = 0;
        for (std::size_t c = 0; c < spec_.constrictions.size(); ++c) {
            const json state = read_point_state(folder(c));
            const json report = read_own_json_file((folder(c) / "report.json").string());
            if (state.is_object() && state.value("state", "") == "done" && report.contains("row")) {
                const json& row = report["row"];
                out.rows.push_back(row);
                const json& p = row["jam_probability"];
                // Seeds without a no-field flux are left out; a constriction with none judged cannot be named.
                if (p.is_number() && p.get<double>() >= spec_.required_jam_probability &&
                    spec_.constrictions[c].second > widest_diameter) {
                    widest_diameter = spec_.constrictions[c].second;
                    out.widest = spec_.constrictions[c].first;
                }
            } else if (report.value("status", "") == "interrupted") {
                out.interrupted_at = report["stopped"];
            } else if (report.contains("stopped") && out.failed_at.is_null()) {
                out.failed_at = report["stopped"];
                out.failed_status = state.is_object() ? state.value("exit_status", kExitError) : kExitError;
            }
        }
        return out;
    }

    int finish(int sweep_status, const DesignResults& r) const {
        if (sweep_status == kExitInterrupted) {
            write_report("interrupted", r, r.interrupted_at);
            std::cerr << "[design] interrupted";
            if (r.interrupted_at.is_object())
                std::cerr << " at the " << r.interrupted_at.value("stage", std::string("run")) << " for "
                          << r.interrupted_at.value("constriction", std::string());
            std::cerr << "; the constrictions finished before it are in " << req_.report_path
                      << "; continue with: " << resume_hint_ << "\n";
            return kExitInterrupted;
        }
        if (sweep_status != kExitOk) {
            write_report("failed", r, r.failed_at);
            std::cerr << "[design] a constriction did not finish (" << table_path() << " names it); the others are in "
                      << req_.report_path << "\n";
            return r.failed_status == kExitOk ? kExitError : r.failed_status;
        }
        write_report("complete", r, json());
        if (req_.progress)
            std::cerr << "[design] widest constriction that jams reliably: " << (r.widest.empty() ? "none" : r.widest)
                      << "; report " << req_.report_path << "; table " << table_path() << "\n";
        return kExitOk;
    }

    std::string table_path() const { return (spec_.output_directory / "table.csv").string(); }

    double wall_time() const {
        return progress_.wall_time_s +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    }

    // The design report: what every constriction that finished says, and where the others stopped.
    void write_report(const std::string& status, const DesignResults& r, const json& stopped) const {
        json plots = json::array();
        const json table = read_own_json_file((spec_.output_directory / "table.json").string());
        if (table.is_object() && table.contains("plots"))
            for (const json& p : table["plots"])
                plots.push_back((spec_.output_directory / p.get<std::string>()).string());
        const DesignSummary summary = write_design_summary(r.rows, r.widest, spec_.output_directory / "summary.svg");
        json report = {{"mrjam_version", MRJAM_VERSION},
                       {"mode", "design"},
                       {"status", status},
                       {"scene_file", req_.scene_path},
                       {"inputs", req_.design},
                       {"inputs_design", spec_.resolved},
                       {"fidelity", {{"jam_tier", req_.fidelity}, {"magnetics_tier", magnetics_tier_}}},
                       {"results",
                        {{"constrictions", r.rows},
                         {"widest_reliable_constriction", r.widest.empty() ? json(nullptr) : json(r.widest)},
                         {"required_jam_probability", spec_.required_jam_probability},
                         {"open_flow_model",
                          "Krieger-Dougherty suspension viscosity, Poiseuille bore and throat, "
                          "sharp orifice loss (C_d 0.61); mineral oil 850 kg/m3"}}},
                       {"table", table_path()},
                       {"plots", plots},
                       {"wall_time_s", wall_time()}};
        if (!summary.svg_path.empty())
            report["summary_figure"] = {
                {"svg", summary.svg_path},
                {"png", summary.png_path},
                {"field_of", summary.field_of.empty() ? json(nullptr) : json(summary.field_of)}};
        if (!stopped.is_null()) report["stopped"] = stopped;
        if (status == "interrupted") report["resume_with"] = resume_hint_;
        if (req_.resume) report["resumed"] = true;
        write_json_file(req_.report_path, report);
    }

    // The design file, tier and the wall time so far: what a resume must match and adds to.
    void save_progress() const {
        DesignProgress saved = progress_;
        saved.wall_time_s = wall_time();
        write_design_progress(spec_.output_directory, saved);
    }

    DesignRequest req_;
    DesignSpec spec_;
    FieldSolver solve_;
    DesignProgress progress_;
    std::string magnetics_tier_, resume_hint_;
    std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace

int run_design(const DesignRequest& request, const FieldSolver& solve_field) {
    return DesignWorkflow(request, solve_field).run();
}

}  // namespace mrjam
