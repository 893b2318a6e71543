// `mrjam sweep` (lib/sweep/): the sweep file's axes and refusals, the table's aggregates, and
// the command's resume, refusal of a changed file, --extend and shards, on the jam mode's
// continuum tier (a Bingham plug, a fraction of a second a point).
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "core/proportion_interval.hpp"
#include "scene/scene_node.hpp"
#include "sweep/sweep_plots.hpp"
#include "sweep/sweep_spec.hpp"
#include "sweep/sweep_table.hpp"
#include "test_support.hpp"

namespace {
using json = nlohmann::json;

json base_scene() {
    return {{"seed", 1}, {"valve", {{"constriction", "20x"}}}, {"fluid", {{"supply_pressure", "105 kPa"}}}};
}

json sweep_file(json axes) { return {{"mode", "jam"}, {"scene", base_scene()}, {"axes", std::move(axes)}}; }

// The path the refusal names.
std::string refused_at(const json& file) {
    try {
        mrjam::read_sweep(file, ".");
    } catch (const mrjam::SceneError& e) {
        return e.path();
    }
    return "(accepted)";
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("sweep: ranges keep the unit both ends are written in; log ranges are geometric") {
        const auto lin = mrjam::range_values({{"from", "150 mT"}, {"to", "600 mT"}, {"count", 4}}, "/axes/0");
        CHECK(lin == std::vector<json>{"150 mT", "300 mT", "450 mT", "600 mT"});
        const auto log = mrjam::range_values({{"from", 1}, {"to", 100}, {"count", 3}, {"spacing", "log"}}, "/a");
        REQUIRE(log.size() == 3);
        CHECK(log[1].get<double>() == doctest::Approx(10.0).epsilon(1e-12));
        CHECK(mrjam::range_values({{"from", 2}, {"to", 5}, {"count", 1}}, "/a") == std::vector<json>{2.0});
    }

    TEST_CASE("sweep: axes combine as a product, the last fastest; zipped keys move together") {
        const json file = sweep_file({{{"key", "valve/constriction"}, {"values", {"20x", "30x"}}},
                                      {{"keys", {"seed", "fluid/supply_pressure"}},
                                       {"values", {{1, "50 kPa"}, {2, "105 kPa"}, {3, "200 kPa"}}}}});
        const mrjam::SweepSpec spec = mrjam::read_sweep(file, ".");
        const auto points = mrjam::sweep_points(spec);
        REQUIRE(points.size() == 6);
        CHECK(points[0].values ==
              json{{"valve/constriction", "20x"}, {"seed", 1}, {"fluid/supply_pressure", "50 kPa"}});
        CHECK(points[1].values["seed"] == 2);
        CHECK(points[1].values["fluid/supply_pressure"] == "105 kPa");
        CHECK(points[3].values["valve/constriction"] == "30x");
        const json scene = mrjam::point_scene(spec, points[4], "/tmp/p4");
        CHECK(scene["valve"]["constriction"] == "30x");
        CHECK(scene["fluid"]["supply_pressure"] == "105 kPa");
        CHECK(scene["seed"] == 2);
        CHECK(scene["output"]["directory"] == "/tmp/p4");
    }

    TEST_CASE("sweep: bad sweep files are refused at the key that is wrong") {
        const json ok_axis = {{"key", "seed"}, {"values", {1}}};
        CHECK(refused_at(sweep_file({ok_axis})) == "(accepted)");
        CHECK(refused_at(sweep_file({{{"key", "valve/constrction"}, {"values", {"20x"}}}})) == "/axes/0/key");
        CHECK(refused_at(sweep_file({{{"key", "seed"}, {"values", json::array()}}})) == "/axes/0/values");
        CHECK(refused_at(sweep_file(
                  {{{"key", "fluid/supply_pressure"}, {"from", "50 kPa"}, {"to", "0.2 MPa"}, {"count", 3}}})) ==
              "/axes/0/to");
        CHECK(refused_at(sweep_file({{{"key", "seed"}, {"from", 1}, {"to", 3}, {"count", 0}}})) == "/axes/0/count");
        CHECK(refused_at(sweep_file({ok_axis, ok_axis})) == "/axes/1");
        CHECK(refused_at(sweep_file(json::array())) == "/axes");
        json bad_mode = sweep_file({ok_axis});
        bad_mode["mode"] = "jamm";
        CHECK(refused_at(bad_mode) == "/mode");
        json owned_arg = sweep_file({ok_axis});
        owned_arg["args"] = {"--threads", "2"};
        CHECK(refused_at(owned_arg) == "/args/0");
        json unknown = sweep_file({ok_axis});
        unknown["axis"] = 1;
        CHECK(refused_at(unknown) == "/axis");
    }

    TEST_CASE("sweep: the table aggregates over seeds: yes/no with the Wilson interval, numbers with mean and sd") {
        json file = sweep_file(
            {{{"key", "valve/constriction"}, {"values", {"20x", "40x"}}}, {{"key", "seed"}, {"values", {1, 2, 3}}}});
        file["outputs"] = {{"jammed", "results/jammed"}, {"hold", "results/hold_Pa"}};
        const mrjam::SweepSpec spec = mrjam::read_sweep(file, ".");
        std::vector<mrjam::SweepRow> rows;
        const bool jammed[6] = {true, true, false, false, false, false};
        const double hold[6] = {100, 110, 120, 1, 2, 3};
        for (const auto& p : mrjam::sweep_points(spec))
            rows.push_back({p,
                            "p" + std::to_string(p.index),
                            p.index == 5 ? "failed" : "done",
                            {{"results", {{"jammed", jammed[p.index]}, {"hold_Pa", hold[p.index]}}}}});
        const json table = mrjam::sweep_table(spec, rows);
        REQUIRE(table["aggregates"].size() == 2);
        const json& a20 = table["aggregates"][0]["outputs"];
        CHECK(a20["jammed"]["yes"] == 2);
        CHECK(a20["jammed"]["of"] == 3);
        const mrjam::ProportionInterval ci = mrjam::wilson_interval(2, 3);
        CHECK(a20["jammed"]["ci95"][0].get<double>() == doctest::Approx(ci.low));
        CHECK(a20["hold"]["mean"].get<double>() == doctest::Approx(110));
        CHECK(a20["hold"]["sd"].get<double>() == doctest::Approx(10));
        // The failed point is left out of its group's figures.
        const json& a40 = table["aggregates"][1];
        CHECK(a40["done"] == 2);
        CHECK(a40["outputs"]["hold"]["mean"].get<double>() == doctest::Approx(1.5));
        CHECK(table["rows"][5]["outputs"]["hold"].is_null());
        // An output no report has is a mistake in the sweep file.
        file["outputs"]["typo"] = "results/jamed";
        CHECK_THROWS_AS(mrjam::sweep_table(mrjam::read_sweep(file, "."), rows), mrjam::SceneError);
        const std::string csv = mrjam::sweep_table_csv(table);
        CHECK(csv.find("point,state,valve/constriction,seed,hold,jammed\n") == 0);
        CHECK(csv.find("p5,failed,40x,3,,\n") != std::string::npos);
    }

    TEST_CASE("sweep: plots draw each line's points with their intervals; bad plot keys are refused") {
        json file = sweep_file({{{"key", "fluid/supply_pressure"}, {"values", {"50 kPa", "100 kPa"}}},
                                {{"key", "valve/constriction"}, {"values", {"20x", "40x"}}},
                                {{"key", "seed"}, {"values", {1, 2}}}});
        file["outputs"] = {{"jammed", "results/jammed"}};
        file["plots"] = {{{"output", "jammed"}, {"x", "fluid/supply_pressure"}, {"lines", "valve/constriction"}}};
        const mrjam::SweepSpec spec = mrjam::read_sweep(file, ".");
        std::vector<mrjam::SweepRow> rows;
        for (const auto& p : mrjam::sweep_points(spec))  // jams at 20x only, at both pressures
            rows.push_back({p, "p", "done", {{"results", {{"jammed", p.values["valve/constriction"] == "20x"}}}}});
        mrjam_test::TempDir dir("mrjam_sweep_plot");
        const auto files = mrjam::write_sweep_plots(spec, mrjam::sweep_table(spec, rows), dir.path.string());
        REQUIRE(files.size() == 1);
        const std::string svg = mrjam_test::slurp(files[0]);
        CHECK(svg.find("valve/constriction = 20x") != std::string::npos);
        CHECK(svg.find("valve/constriction = 40x") != std::string::npos);
        CHECK(svg.find("fluid/supply_pressure (Pa)") != std::string::npos);
        CHECK(svg.find("share of the seeds, 95 % interval") != std::string::npos);
        // Two pressures x two constrictions, each a share of its two seeds.
        std::size_t circles = 0, at = 0;
        while ((at = svg.find("<circle", at)) != std::string::npos) ++circles, ++at;
        CHECK(circles == 4 + 2);  // and the legend's two markers
        for (const json& bad :
             {json{{"output", "held"}, {"x", "seed"}}, json{{"output", "jammed"}, {"x", "seed"}},
              json{{"output", "jammed"}, {"x", "valve/constriction"}, {"lines", "valve/constriction"}}}) {
            json f = file;
            f["plots"] = {bad};
            CHECK(refused_at(f).rfind("/plots/0", 0) == 0);
        }
    }
}

#ifdef MRJAM_BINARY
namespace {

// A jam sweep on the continuum tier: constrictions x 2 supply pressures x 2 seeds (cheap).
json continuum_sweep(const std::vector<std::string>& constrictions) {
    const json scene = {
        {"seed", 1},
        {"valve", {{"constriction", "20x"}}},
        {"grains", {{"psd", "44um"}, {"volume_fraction", 0.345}}},
        {"fluid", {{"viscosity", "0.16 Pa s"}, {"flow", "pressure"}, {"supply_pressure", "105 kPa"}}},
        {"field", {{"type", "uniform"}, {"flux_density", "230 mT"}}},
        {"continuum",
         {{"yield_stress", json::array({json::array({"100 mT", "5 kPa"}), json::array({"300 mT", "20 kPa"})})}}},
        {"output", {{"directory", "out"}}}};
    return {{"mode", "jam"},
            {"args", {"--fidelity", "continuum"}},
            {"scene", scene},
            {"axes",
             {{{"key", "valve/constriction"}, {"values", constrictions}},
              {{"key", "fluid/supply_pressure"}, {"values", {"50 kPa", "2 MPa"}}},
              {{"key", "seed"}, {"values", {1, 2}}}}},
            {"outputs", {{"jammed", "results/jammed"}, {"holds_Pa", "results/continuum/hold_pressure_Pa"}}}};
}

json table_rows(const mrjam_test::TempDir& dir, const std::string& out) {
    json t = json::parse(mrjam_test::slurp(dir.file(out + "/table.json")));
    for (json& r : t["rows"]) r.erase("point");  // folders may be numbered differently
    return t["rows"];
}

int attempts(const mrjam_test::TempDir& dir, const std::string& out, const std::string& folder) {
    return json::parse(mrjam_test::slurp(dir.file(out + "/points/" + folder + "/state.json")))["attempts"];
}

std::string sweep(const mrjam_test::TempDir& dir, const json& file, const std::string& name) {
    mrjam_test::write_text(dir.file(name), file.dump(1));
    return mrjam_test::quote(dir.file(name));
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("sweep: runs every point, a rerun runs none, a changed file is refused, --extend adds") {
        mrjam_test::TempDir dir("mrjam_sweep");
        const std::string file = sweep(dir, continuum_sweep({"20x", "40x"}), "s.json");
        const auto first = mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("out"));
        REQUIRE_MESSAGE(first.exit_code == 0, first.err);
        const json rows = table_rows(dir, "out");
        REQUIRE(rows.size() == 8);
        for (const json& r : rows) CHECK(r["state"] == "done");
        // The plug's hold depends on the constriction, not on the supply or the seed: the jam does.
        CHECK(rows[0]["outputs"]["holds_Pa"] == rows[3]["outputs"]["holds_Pa"]);
        CHECK(rows[0]["outputs"]["jammed"] != rows[2]["outputs"]["jammed"]);
        const auto again = mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("out"));
        CHECK(again.exit_code == 0);
        CHECK(again.err.find("running 0") != std::string::npos);
        CHECK(attempts(dir, "out", "p0000") == 1);
        CHECK(table_rows(dir, "out") == rows);

        const std::string wider = sweep(dir, continuum_sweep({"20x", "30x", "40x"}), "s.json");
        const auto refused = mrjam_test::mrjam(dir, "sweep " + wider + " --out " + dir.file("out"));
        CHECK(refused.exit_code == 2);
        CHECK(refused.err.find("/axes/0/values") != std::string::npos);
        const auto extended = mrjam_test::mrjam(dir, "sweep " + wider + " --out " + dir.file("out") + " --extend");
        REQUIRE_MESSAGE(extended.exit_code == 0, extended.err);
        CHECK(extended.err.find("running 4") != std::string::npos);
        CHECK(attempts(dir, "out", "p0000") == 1);
        CHECK(table_rows(dir, "out").size() == 12);
    }

    TEST_CASE("sweep: two shards and --collect give the serial table; a bad shard is refused") {
        mrjam_test::TempDir dir("mrjam_sweep");
        const std::string file = sweep(dir, continuum_sweep({"20x", "30x"}), "s.json");
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("serial")).exit_code == 0);
        for (const char* shard : {"0/2", "1/2"})
            REQUIRE(
                mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("sharded") + " --shard " + shard)
                    .exit_code == 0);
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("sharded") + " --collect").exit_code ==
                0);
        CHECK(table_rows(dir, "sharded") == table_rows(dir, "serial"));
        // Three points at a time in one process: the same table, each point run once.
        const auto side_by_side = mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("jobs") + " --jobs 3");
        REQUIRE_MESSAGE(side_by_side.exit_code == 0, side_by_side.err);
        CHECK(side_by_side.err.find("3 at a time") != std::string::npos);
        CHECK(table_rows(dir, "jobs") == table_rows(dir, "serial"));
        for (const json& p : json::parse(mrjam_test::slurp(dir.file("jobs/manifest.json")))["points"])
            CHECK(p["attempts"] == 1);
        const auto bad = mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("x") + " --shard 2/2");
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("--shard") != std::string::npos);
        // The sweep file is read as scenes are: a key given twice is refused, naming it.
        mrjam_test::write_text(dir.file("twice.json"), R"({"mode": "jam", "mode": "shear", "scene": {}, "axes": []})");
        const auto twice = mrjam_test::mrjam(
            dir, "sweep " + mrjam_test::quote(dir.file("twice.json")) + " --out " + mrjam_test::quote(dir.file("y")));
        CHECK(twice.exit_code == 2);
        CHECK(twice.err.find("/mode: is given twice") != std::string::npos);
    }

    TEST_CASE("sweep: SIGINT stops the sweep with 130; the rerun finishes it, no point done twice") {
        mrjam_test::TempDir dir("mrjam_sweep");
        const std::string file = sweep(dir, continuum_sweep({"20x", "30x", "40x"}), "s.json");
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("whole")).exit_code == 0);
        const auto stopped = mrjam_test::mrjam(dir, "sweep " + file + " --out " + dir.file("cut"),
                                               " & pid=$!; sleep 0.6; kill -INT $pid; wait $pid");
        CHECK(stopped.exit_code == 130);
        CHECK(stopped.err.find("rerun the same command") != std::string::npos);
        const json partial = json::parse(mrjam_test::slurp(dir.file("cut/manifest.json")));
        int done = 0;
        for (const json& p : partial["points"]) done += p["state"] == "done";
        CHECK(done < 12);
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("cut")).exit_code == 0);
        CHECK(table_rows(dir, "cut") == table_rows(dir, "whole"));
        int twice = 0;
        for (const json& p : json::parse(mrjam_test::slurp(dir.file("cut/manifest.json")))["points"]) {
            CHECK(p["attempts"].get<int>() <= 2);
            twice += p["attempts"].get<int>() == 2;  // only the point in flight at the interrupt
        }
        CHECK(twice <= 1);
    }
}

#ifdef MRJAM_MPIRUN
namespace {

// `mpirun -np N mrjam sweep ...` (as root too, on more ranks than cores).
std::string mpirun(int ranks) {
    return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " + mrjam_test::quote(MRJAM_MPIRUN) +
           " --oversubscribe -np " + std::to_string(ranks) + " " + mrjam_test::quote(MRJAM_BINARY) + " sweep ";
}

// A point's report without what names its folder or times it.
json comparable_report(const mrjam_test::TempDir& dir, const std::string& path) {
    json r = json::parse(mrjam_test::slurp(dir.file(path)));
    r.erase("scene_file");
    r.erase("wall_time_s");
    r["inputs_jam"].erase("output");
    return r;
}

int run_shell(const std::string& command) {
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("sweep under mpirun: 2 and 3 ranks give the serial table and the same reports") {
        mrjam_test::TempDir dir("mrjam_sweep_mpi");
        const std::string file = sweep(dir, continuum_sweep({"20x", "30x"}), "s.json");
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("serial")).exit_code == 0);
        for (int ranks : {2, 3}) {
            const std::string out = "np" + std::to_string(ranks);
            REQUIRE(run_shell(mpirun(ranks) + file + " --quiet --out " + mrjam_test::quote(dir.file(out)) + " > " +
                              mrjam_test::quote(dir.file(out + ".log")) + " 2>&1") == 0);
            CHECK(table_rows(dir, out) == table_rows(dir, "serial"));
            for (const char* p : {"p0000", "p0003", "p0007"})
                CHECK(comparable_report(dir, out + "/points/" + p + "/report.json") ==
                      comparable_report(dir, std::string("serial/points/") + p + "/report.json"));
        }
    }

    TEST_CASE("sweep under mpirun: a rank killed mid-sweep loses its point only; the rerun finishes it") {
        mrjam_test::TempDir dir("mrjam_sweep_mpi");
        const std::string file = sweep(dir, continuum_sweep({"20x", "30x", "40x"}), "s.json");
        REQUIRE(mrjam_test::mrjam(dir, "sweep " + file + " --quiet --out " + dir.file("serial")).exit_code == 0);
        const std::string out = mrjam_test::quote(dir.file("cut"));
        // Once four points have folders, SIGKILL the newest rank; mpirun then ends the others.
        const int killed =
            run_shell("(" + mpirun(3) + file + " --quiet --out " + out + " > /dev/null 2>&1 & pid=$!; " +
                      "for i in $(seq 600); do [ \"$(ls " + out + "/points 2>/dev/null | wc -l)\" -ge 4 ] && break; " +
                      "sleep 0.05; done; " + "pkill -9 -P $pid -n; wait $pid)");
        CHECK(killed != 0);
        REQUIRE(run_shell(mpirun(3) + file + " --quiet --out " + out + " > /dev/null 2>&1") == 0);
        CHECK(table_rows(dir, "cut") == table_rows(dir, "serial"));
        int twice = 0;
        for (const json& p : json::parse(mrjam_test::slurp(dir.file("cut/manifest.json")))["points"]) {
            CHECK(p["attempts"].get<int>() <= 2);
            twice += p["attempts"].get<int>() == 2;
        }
        CHECK(twice <= 3);  // at most the points in flight on the three ranks: none done is run again
    }
}
#endif
#endif
