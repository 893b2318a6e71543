// `mrjam jam --resume` and `--snapshots`: a jam run continued from a checkpoint taken in any
// phase of its protocol (or of its seeds) ends bit for bit as the uninterrupted run, and the
// snapshots carry each grain's contact cluster.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <tuple>
#include <utility>

#include "core/machine_threads.hpp"
#include "jam/jam_campaign.hpp"
#include "run/interrupt.hpp"
#include "test_support.hpp"

using namespace mrjam_test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A 0.65 mm stretch of valve with a short constriction in a 2-diameter slab: about 1500 grains, a
// second of work per seed. `arrest_fraction` 0.95 makes the field's slowing of the flux count as
// an arrest, so the release phase is run too. The pressure-driven flow at a low supply pressure
// (10 kPa) throttles the flow during the run (its scale moves between about 0.3 and 1), so its
// controller's state must survive a resume as well.
// Open first by default (the flow, field_on and release phases); closed first adds a brief
// magnetisation at rest (settle checks every 0.01 ms, at most 0.03 ms) before the pressure.
json tiny_scene(const std::string& out, long checkpoint_every, bool closed_first = false) {
    json scene = {{"valve", {{"constriction", "30x"}, {"taper_length", "0.3 mm"}, {"throat_length", "0.1 mm"}}},
                  {"fluid", {{"flow", "pressure"}, {"supply_pressure", "10 kPa"}}},
                  {"field", {{"type", "uniform"}, {"flux_density", "230 mT"}}},
                  // The grains' own masses: the fixture's arrest and give-way times were set with them (the
                  // quick tier's heavier fine grains shift them; their cost is measured on real cases).
                  {"model",
                   {{"upstream_length", "0.45 mm"},
                    {"downstream_length", "0.2 mm"},
                    {"slab_thickness_diameters", 2},
                    {"heavier_below", "0 um"}}},
                  {"protocol",
                   {{"order", "open_first"},
                    {"flow_time", "0.06 ms"},
                    {"max_time", "0.03 ms"},
                    {"arrest_window", "0.008 ms"},
                    {"arrest_fraction", 0.95},
                    {"release_time", "0.015 ms"},
                    {"observe_every_steps", 20}}},
                  {"output", {{"directory", out}}}};
    if (checkpoint_every > 0) scene["output"]["checkpoint"] = {{"every_steps", checkpoint_every}};
    if (closed_first)
        scene["protocol"].update(
            {{"order", "closed_first"}, {"magnetise_time", "0.03 ms"}, {"settle_window", "0.01 ms"}});
    return scene;
}

Result jam(const TempDir& dir, const std::string& name, const json& scene, const std::string& extra) {
    write_text(dir.file(name + ".json"), scene.dump());
    return mrjam_test::mrjam(dir, "jam " + quote(dir.file(name + ".json")) + " --report " +
                                      quote(dir.file(name + "_report.json")) + " --fidelity quick --quiet " + extra);
}

// Resumes run NAME from the checkpoint it left in out_NAME and returns the resumed run's report.
json resumed_report(const TempDir& dir, const std::string& name) {
    const std::string ck = dir.file("out_" + name + "/checkpoint.mrjam");
    REQUIRE(fs::exists(ck));
    const Result resumed = mrjam_test::mrjam(
        dir, "jam --resume " + quote(ck) + " --report " + quote(dir.file(name + "_resumed.json")) + " --quiet");
    CAPTURE(resumed.err);
    REQUIRE(resumed.exit_code == 0);
    return json::parse(slurp(dir.file(name + "_resumed.json")));
}

// The results that must not depend on an interruption: everything but the wall-clock numbers.
json comparable(json report) {
    report.erase("wall_time_s");
    report.erase("performance");
    report.erase("resumed_from");
    report.erase("outputs");
    report["results"]["flux_history"].erase("partial");
    return report;
}

// Steps of each stage (flow, field_on, release) in a finished report.
std::vector<long> stage_steps(const json& report) {
    std::vector<long> steps;
    for (const auto& st : report["results"]["stages"]) steps.push_back(st["steps"].get<long>());
    return steps;
}

// The int32 big-endian array NAME of a legacy VTK file (a FIELD array "NAME 1 N int").
std::vector<std::int32_t> legacy_int_array(const std::string& file, const std::string& name) {
    const std::string header = "\n" + name + " 1 ";
    const auto at = file.find(header);
    REQUIRE(at != std::string::npos);
    const auto line_end = file.find('\n', at + 1);
    const std::size_t n = std::stoul(file.substr(at + header.size()));
    std::vector<std::int32_t> values(n);
    REQUIRE(line_end + 1 + 4 * n <= file.size());
    for (std::size_t i = 0; i < n; ++i) {
        const auto* b = reinterpret_cast<const unsigned char*>(file.data() + line_end + 1 + 4 * i);
        values[i] = static_cast<std::int32_t>((std::uint32_t{b[0]} << 24) | (std::uint32_t{b[1]} << 16) |
                                              (std::uint32_t{b[2]} << 8) | b[3]);
    }
    return values;
}

}  // namespace

TEST_SUITE("cli") {
    TEST_CASE("jam --resume: a checkpoint in any phase, or in a later seed, ends as the uninterrupted run") {
        TempDir dir;
        const Result full = jam(dir, "full", tiny_scene(dir.file("out_full"), 0), "--seeds 2");
        CAPTURE(full.err);
        REQUIRE(full.exit_code == 0);
        const json a = json::parse(slurp(dir.file("full_report.json")));
        const std::vector<long> steps = stage_steps(a);
        REQUIRE(steps.size() == 3);
        // Without an arrest the release phase ends at its first observation and this test would not
        // reach it; the scene is made so that the field's slowing counts as one.
        REQUIRE(a["results"]["jammed"] == true);
        // The flow was throttled at some point, so a lost flow scale would change the run.
        double lowest = 1;
        for (const auto& row : a["results"]["flow_history"]["rows"]) lowest = std::min(lowest, row[1].get<double>());
        REQUIRE(lowest < 0.9);
        // An arrest under pressure-driven flow reports how much fluid the closed valve still passes.
        REQUIRE(a["results"]["closed_flow_share"].is_number());
        CHECK(a["results"]["closed_flow_share"].get<double>() > 0.0);
        CHECK(a["seeds"][0]["closed_flow_share"] == a["results"]["closed_flow_share"]);
        CHECK(a["seeds"][0]["flux_share_last_window"] == a["results"]["flux_share_last_window"]);
        // The report is seed 1's: seed 2's warnings (here its own sparse arrest window) join it,
        // named by their seed; they used to reach stderr only.
        REQUIRE_FALSE(a["seeds"][1]["warnings"].empty());
        for (const auto& w : a["seeds"][1]["warnings"])
            CHECK(a["warnings"].dump().find(json("seed " + std::to_string(a["seeds"][1]["seed"].get<long long>()) +
                                                 ": " + w.get<std::string>())
                                                .dump()) != std::string::npos);
        const long total = steps[0] + steps[1] + steps[2];

        // One checkpoint per run (every N steps with 2N beyond the run's end), placed in the
        // no-field flow, with the field on, and in the release. With two seeds the first seed's
        // checkpoint is overwritten by the second's, so that resume starts inside seed 2 and must
        // still report seed 1's results and the jam probability over both; the single-seed cases
        // compare everything but the statistics over seeds.
        struct Case {
            std::string phase;
            long start, end;
            int seeds;
        };
        for (const Case& c : {Case{"flow", 0, steps[0], 1}, Case{"field_on", steps[0], steps[0] + steps[1], 2},
                              Case{"release", steps[0] + steps[1], total, 1}}) {
            CAPTURE(c.phase);
            const long every = (std::max(c.start, total / 2) + c.end) / 2 + 1;  // inside the phase, and 2N > total
            // The scene's stage lengths must leave a single checkpoint in every phase, or this
            // phase would go unchecked.
            REQUIRE_MESSAGE(every < c.end, "the stage lengths leave no single checkpoint in " << c.phase);
            const std::string name = "cut_" + c.phase;
            const Result cut =
                jam(dir, name, tiny_scene(dir.file("out_" + name), every), "--seeds " + std::to_string(c.seeds));
            REQUIRE(cut.exit_code == 0);
            const std::string ck = dir.file("out_" + name + "/checkpoint.mrjam");
            const json b = resumed_report(dir, name);
            CHECK(b["resumed_from"] == ck);
            // It continued, not restarted: fewer steps run than the whole protocol.
            if (c.seeds == 1)
                CHECK(b["performance"]["steps_run"].get<long>() < a["performance"]["steps_run"].get<long>());
            // Inputs, flux history, arrest and release, the flow scale, clusters, energies: all
            // identical, bit for bit.
            json ra = comparable(a)["results"], rb = comparable(b)["results"];
            if (c.seeds == 1)
                for (const char* key : {"jam_probability", "jam_probability_95ci", "arrest_probability_95ci",
                                        "time_to_arrest_mean_s", "time_to_arrest_std_s"}) {
                    ra.erase(key);
                    rb.erase(key);
                }
            CHECK(rb == ra);
            json inputs_a = a["inputs_jam"], inputs_b = b["inputs_jam"];
            inputs_a.erase("output");  // the directory and the checkpoint interval differ on purpose
            inputs_b.erase("output");
            CHECK(inputs_b == inputs_a);
            if (c.seeds == 2) CHECK(b["seeds"] == a["seeds"]);
            // `mrjam run` would continue the engine without the protocol: it points to jam instead;
            // and a resume cannot change the tier or the seeds it was started with.
            if (c.phase == "flow") {
                const Result reseeded = mrjam_test::mrjam(dir, "jam --resume " + quote(ck) + " --seeds 3 --quiet");
                CHECK(reseeded.exit_code == 2);
                CHECK(reseeded.err.find("--seeds") != std::string::npos);
                const Result run = mrjam_test::mrjam(
                    dir, "run --resume " + quote(ck) + " --report " + quote(dir.file("run.json")) + " --quiet");
                CHECK(run.exit_code == 2);
                CHECK(run.err.find("mrjam jam --resume") != std::string::npos);
            }
        }
        // Not a jam checkpoint: refused naming --resume.
        write_text(dir.file("not.mrjam"), "nothing");
        const Result bad = mrjam_test::mrjam(dir, "jam --resume " + quote(dir.file("not.mrjam")) + " --quiet");
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("--resume") != std::string::npos);
    }

    // Closed first the grains are magnetised at rest before the pressure: a checkpoint while they
    // settle, or under pressure, resumes to the same settle checks, arrest and release.
    TEST_CASE(
        "jam --resume: closed first, a checkpoint while magnetising or under pressure ends as the uninterrupted run") {
        TempDir dir;
        const Result full = jam(dir, "full", tiny_scene(dir.file("out_full"), 0, true), "");
        CAPTURE(full.err);
        REQUIRE(full.exit_code == 0);
        const json a = json::parse(slurp(dir.file("full_report.json")));
        const std::vector<long> steps = stage_steps(a);
        REQUIRE(steps.size() == 4);  // flow, magnetise, pressure, release
        CHECK(a["results"]["order"] == "closed_first");
        const json& magnetisation = a["results"]["magnetisation"];
        REQUIRE(magnetisation["history"]["rows"].size() >= 2);
        // The pressure is applied when the magnetisation ended, and the judged period counts from there.
        CHECK(a["results"]["judged_from_s"].get<double>() >= 0.06e-3);
        // The fluid is at rest while the grains are magnetised: the flow scale is 0 in that period.
        const double magnetised_until = a["results"]["judged_from_s"].get<double>();
        long resting = 0;
        for (const auto& row : a["results"]["flow_history"]["rows"])
            if (row[0].get<double>() > 0.0605e-3 && row[0].get<double>() < magnetised_until) {
                CHECK(row[1].get<double>() == 0.0);
                ++resting;
            }
        CHECK(resting > 0);
        const long total = steps[0] + steps[1] + steps[2] + steps[3];
        for (const auto& [phase, start, end] :
             {std::tuple<std::string, long, long>{"magnetise", steps[0], steps[0] + steps[1]},
              {"pressure", steps[0] + steps[1], steps[0] + steps[1] + steps[2]}}) {
            CAPTURE(phase);
            const long every = (std::max(start, total / 2) + end) / 2 + 1;  // inside the phase, and 2N > total
            REQUIRE(every > start);  // the brief stages put half the run inside the magnetisation
            REQUIRE(every < end);
            const std::string name = "cut_" + phase;
            REQUIRE(jam(dir, name, tiny_scene(dir.file("out_" + name), every, true), "").exit_code == 0);
            CHECK(comparable(resumed_report(dir, name))["results"] == comparable(a)["results"]);
        }
    }

    // A settle tolerance no structure meets: the magnetisation runs its full time, the pressure goes
    // on at its end, and the report warns with the criterion's values.
    TEST_CASE("jam: closed first, a structure that has not settled by magnetise_time is said so") {
        TempDir dir;
        json scene = tiny_scene(dir.file("out"), 0, true);
        scene["protocol"]["settle_tolerance"] = 1e-12;
        const Result r = jam(dir, "unsettled", scene, "");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("unsettled_report.json")));
        const json& res = report["results"];
        CHECK(res["magnetisation"]["settled"] == false);
        CHECK(res["judged_from_s"].get<double>() == doctest::Approx(0.06e-3 + 0.03e-3).epsilon(1e-12));
        CHECK(report["warnings"].dump().find("had not settled by protocol/magnetise_time (0.03 ms)") !=
              std::string::npos);
    }

    // A run checkpointed half-way through the field period and resumed must end as the
    // uninterrupted one; `scene(out, checkpoint_every)` builds the variant. Returns the full run's report.
    json resumed_mid_field_matches(const TempDir& dir, const std::function<json(const std::string&, long)>& scene) {
        const Result full = jam(dir, "full", scene(dir.file("out_full"), 0), "");
        CAPTURE(full.err);
        REQUIRE(full.exit_code == 0);
        const json a = json::parse(slurp(dir.file("full_report.json")));
        const std::vector<long> steps = stage_steps(a);
        REQUIRE(steps.size() == 3);
        const long every = steps[0] + steps[1] / 2;
        REQUIRE(2 * every > steps[0] + steps[1] + steps[2]);
        const Result cut = jam(dir, "cut", scene(dir.file("out_cut"), every), "");
        REQUIRE(cut.exit_code == 0);
        const std::string ck = dir.file("out_cut/checkpoint.mrjam");
        REQUIRE(fs::exists(ck));
        const Result resumed = mrjam_test::mrjam(
            dir, "jam --resume " + quote(ck) + " --report " + quote(dir.file("resumed.json")) + " --quiet");
        CAPTURE(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        const json b = json::parse(slurp(dir.file("resumed.json")));
        json ra = comparable(a)["results"], rb = comparable(b)["results"];
        CHECK(rb == ra);
        return a;
    }

    TEST_CASE("jam --resume: the coupled flow's field survives a checkpoint") {
        // The tiny scene with the two-way coupled flow (its jet needs 0.35 mm past the throat centre):
        // the slices' speeds and drag factors between observations live in the checkpoint's protocol
        // state, so a run resumed with the field on ends as the uninterrupted one.
        TempDir dir;
        const json a = resumed_mid_field_matches(dir, [](const std::string& out, long every) {
            json s = tiny_scene(out, every);
            s["fluid"] = {{"flow", "coupled"}, {"supply_pressure", "10 kPa"}};
            s["model"]["downstream_length"] = "0.35 mm";
            return s;
        });
        CHECK(a["results"]["flow_model"].get<std::string>().rfind("coupled", 0) == 0);
        CHECK(a["results"]["coupled_slices"]["rows"].size() > 5);
    }

    TEST_CASE(
        "jam --resume: a finite batch resumes with its drained grains, counts, held magnetic forces and flow lookups") {
        // The checkpoint holds fewer grains than the scene filled, and the batch's counts live in the
        // protocol state: the resumed run drains on from there and ends as the uninterrupted one.
        // The magnetic forces are evaluated and the carrier flow looked up every 3 steps: the
        // held forces, lookups and their ages are state too, checkpointed with the grains and
        // compacted with them as the batch drains.
        TempDir dir;
        const json a = resumed_mid_field_matches(dir, [](const std::string& out, long every) {
            json s = tiny_scene(out, every);
            s["model"]["downstream_length"] = "0.35 mm";
            s["model"]["supply"] = "batch";
            s["model"]["magnetic_update_interval"] = 3;
            s["model"]["flow_lookup_interval"] = 3;
            return s;
        });
        const json& b = a["results"]["batch"];
        CHECK(b["grains_drained"].get<long>() > 0);
        CHECK(a["results"]["magnetic"]["update_interval_steps"] == 3);
        CHECK(a["results"]["magnetic"]["steps_with_held_forces"].get<long>() > 0);
        CHECK(a["results"]["carrier_flow"]["lookup_interval_steps"] == 3);
        CHECK(a["results"]["carrier_flow"]["steps_with_held_lookups"].get<long>() > 0);
        // The tiny scene arrests (arrest_fraction 0.95): the count at the arrest lies between the
        // first and the last, and a batch mostly gone upstream by then is flagged as a feed run out.
        REQUIRE(a["results"]["jammed"] == true);
        const long start = b["upstream_of_throat_centre_at_start"],
                   at_arrest = b["upstream_of_throat_centre_at_arrest"];
        CHECK(at_arrest <= start);
        CHECK(at_arrest >= b["upstream_of_throat_centre_at_end"].get<long>());
        CHECK((a["warnings"].dump().find("feed ran out") != std::string::npos) == (2 * at_arrest < start));
    }

    // protocol/hold_time keeps the field on after the arrest, then the release test runs as before.
    // The tiny scene arrests; with a hold the release stage must run about hold / dt steps with the
    // magnet still on before it goes off (without a hold: at most the one step that switches it), and
    // the report must say whether the grains stayed put over the hold. The hold raises the supply
    // from 10 to 40 kPa (protocol/hold_pressure) through the same circuit, so the flow scale, at most
    // 1 at the scene's supply, may reach past it from the arrest on and only then.
    TEST_CASE("jam: a hold keeps the field on after the arrest before the release test") {
        TempDir dir;
        const double hold = 0.01e-3;
        json scene = tiny_scene(dir.file("out_hold"), 0);
        scene["protocol"]["hold_time"] = "0.01 ms";
        scene["protocol"]["hold_pressure"] = "40 kPa";
        const Result with_hold = jam(dir, "hold", scene, "");
        CAPTURE(with_hold.err);
        REQUIRE(with_hold.exit_code == 0);
        const json a = json::parse(slurp(dir.file("hold_report.json")));
        const json& res = a["results"];
        REQUIRE(res["jammed"] == true);
        // Steps of the release stage with the magnet on (the magnetic state's counts are cumulative).
        auto on_in_release = [](const json& stages) {
            REQUIRE(stages.size() == 3);
            auto off = [&](int k) { return stages[k]["state"]["magnetic"]["steps_with_magnet_off"].get<long>(); };
            return stages[2]["steps"].get<long>() - (off(2) - off(1));
        };
        const double dt = res["timestep_s"].get<double>();
        CHECK(std::abs(on_in_release(res["stages"]) - hold / dt) <= 2);
        REQUIRE(res["hold"].is_object());
        const double share = res["hold"]["flux_share"].get<double>();
        // Held: below the scene's arrest_fraction (0.95) on average, and never given way.
        CHECK(res["hold"]["held"].get<bool>() == (share < 0.95 && res["hold"]["gave_way_after_s"].is_null()));
        CHECK(res["hold"]["closed_flow_share_at_end"].is_number());
        CHECK(res["hold"]["pressure_Pa"].get<double>() == rel(40e3));
        // When the bed gave way: never, if no grain passed over the hold, although the grains passed
        // in the arrest's own last window (up to 95 % of the no-field flux here) must not count;
        // otherwise within the hold, at the hold's supply (a step).
        const json& gave_way = res["hold"]["gave_way_after_s"];
        if (share == 0) {
            CHECK(gave_way.is_null());
            CHECK(res["hold"]["gave_way_at_pressure_Pa"].is_null());
        } else if (gave_way.is_number()) {
            CHECK(gave_way.get<double>() > 0);
            CHECK(gave_way.get<double>() <= hold * (1 + 1e-9));
            CHECK(res["hold"]["gave_way_at_pressure_Pa"].get<double>() == rel(40e3));
        }
        // The flux with the field on, window by window: whole arrest windows from field-on up to the
        // arrest's call, none from the hold (which the history also covers).
        const json& shares = res["flux_share_with_field"];
        const double window = shares["window_s"].get<double>(), on = res["field_switched_on_s"].get<double>();
        const double called = on + res["time_to_arrest_s"].get<double>() + window;
        CHECK(window == rel(0.008e-3));
        CHECK(shares["rows"].size() == static_cast<std::size_t>(std::floor((called - on) / window * (1 + 1e-9))));
        for (const auto& row : shares["rows"]) CHECK(row[0].get<double>() <= called * (1 + 1e-12));
        if (!shares["rows"].empty())
            CHECK(res["flux_share_last_window"].get<double>() == shares["rows"].back()[1].get<double>());
        // The flow scale: never above 1 before the arrest, above it after (the tiny scene's "arrest"
        // at 95 % of the no-field flux leaves the grains flowing, so 4x the pressure drives more flow).
        const double arrest_at = res["field_switched_on_s"].get<double>() + res["time_to_arrest_s"].get<double>();
        double before = 0, after = 0;
        for (const auto& row : res["flow_history"]["rows"]) {
            double& peak = row[0].get<double>() < arrest_at ? before : after;
            peak = std::max(peak, row[1].get<double>());
        }
        CHECK(before <= 1.0);
        CHECK(after > 1.5);
        // The outcome and the jam probability follow the hold: a broken hold is no jam.
        const bool held = res["hold"]["held"].get<bool>();
        CHECK(res["stops_flow"] == held);
        CHECK((res["outcome"] == "fail-no-hold") == !held);
        CHECK(res["jam_probability"].get<double>() == (held ? 1.0 : 0.0));
        CHECK(res["arrest_probability"].get<double>() == 1.0);
        // One seed says little: Wilson's 95 % interval for 1 of 1 is [1 / (1 + z^2), 1], for 0 of 1
        // [0, z^2 / (1 + z^2)].
        const double z2 = 1.959963984540054 * 1.959963984540054;
        const json one_of_one = json::array({1 / (1 + z2), 1.0}), none_of_one = json::array({0.0, z2 / (1 + z2)});
        for (const auto& [key, expected] : {std::pair{"arrest_probability_95ci", one_of_one},
                                            std::pair{"jam_probability_95ci", held ? one_of_one : none_of_one}}) {
            CAPTURE(key);
            REQUIRE(res[key].size() == 2);
            for (int b = 0; b < 2; ++b)
                CHECK(res[key][b].get<double>() == doctest::Approx(expected[b].get<double>()).epsilon(1e-12));
        }
        REQUIRE(a["seeds"].size() == 1);
        CHECK(a["seeds"][0]["stops_flow"] == held);
        CHECK(a["seeds"][0]["hold"] == res["hold"]);
        // The same scene without a hold: the field goes off at the arrest, and no "hold" is reported.
        const Result plain = jam(dir, "plain", tiny_scene(dir.file("out_plain"), 0), "");
        REQUIRE(plain.exit_code == 0);
        const json b = json::parse(slurp(dir.file("plain_report.json")));
        CHECK(on_in_release(b["results"]["stages"]) <= 1);
        CHECK_FALSE(b["results"].contains("hold"));
    }

    // The tiny scene's arrest (the field's slowing of the flux) pushed at 20 times the supply that
    // it formed under: 200 kPa drives the open flow 20 times faster, and a bed that at best halves it
    // passes grains faster than the no-field flow did, so it gives way within 0.03 ms; the report must
    // say when, and at what supply, and count it as no jam. With the same rise spread over the hold
    // (protocol/hold_pressure_ramp), the supply at the give-way is the ramp's value at that time.
    TEST_CASE(
        "jam: a bed pushed far past its closing pressure gives way, and the report says when and at what supply") {
        TempDir dir;
        const double hold = 0.03e-3, ramp = 0.03e-3, supply = 10e3, raised = 200e3;
        for (const bool ramped : {false, true}) {
            CAPTURE(ramped);
            json scene = tiny_scene(dir.file(ramped ? "out_ramp" : "out_step"), 0);
            scene["protocol"]["hold_time"] = "0.03 ms";
            scene["protocol"]["hold_pressure"] = "200 kPa";
            if (ramped) scene["protocol"]["hold_pressure_ramp"] = "0.03 ms";
            const std::string name = ramped ? "ramp" : "step";
            const Result r = jam(dir, name, scene, "");
            CAPTURE(r.err);
            REQUIRE(r.exit_code == 0);
            const json res = json::parse(slurp(dir.file(name + "_report.json")))["results"];
            REQUIRE(res["jammed"] == true);
            REQUIRE(res["hold"]["gave_way_after_s"].is_number());
            const double after = res["hold"]["gave_way_after_s"].get<double>();
            CHECK(after > 0);
            CHECK(after <= hold * (1 + 1e-9));
            const double expected = ramped ? supply + std::min(1.0, after / ramp) * (raised - supply) : raised;
            CHECK(res["hold"]["gave_way_at_pressure_Pa"].get<double>() == rel(expected));
            if (ramped) CHECK(res["hold"]["gave_way_at_pressure_Pa"].get<double>() < raised);
            CHECK(res["hold"]["held"] == false);
            CHECK(res["outcome"] == "fail-no-hold");
            CHECK(res["jam_probability"].get<double>() == 0.0);
        }
    }

    // A run that blows up says why on the terminal (the cause and its fixes), not only in the
    // report, with exit code 3: grains of 1 MPa cannot hold the flow's impacts.
    TEST_CASE("jam: a blow-up stops the run with its cause on stderr and exit code 3") {
        TempDir dir;
        json scene = tiny_scene(dir.file("out_soft"), 0);
        scene["material"] = {{"youngs_modulus", "1 MPa"}};
        scene["protocol"]["observe_every_steps"] = 1;  // the soft grains' long step still observes a window 4 times
        const Result r = jam(dir, "soft", scene, "");
        CHECK(r.exit_code == 3);
        CHECK(r.err.find("blow-up") != std::string::npos);
        CHECK(r.err.find("youngs_modulus") != std::string::npos);
        const json report = json::parse(slurp(dir.file("soft_report.json")));
        CHECK(report["status"] == "failed");
        CHECK(report["error"].get<std::string>().find("blow-up") != std::string::npos);
    }

    // A damaged checkpoint is refused as bad input to --resume (exit 2), not read past an array's
    // end: here the velocity array (the second per-grain array, after the positions) is cut 100
    // grains short, its length field made to match.
    TEST_CASE("jam --resume: a checkpoint whose per-grain arrays disagree is refused") {
        TempDir dir;
        REQUIRE(jam(dir, "run", tiny_scene(dir.file("out"), 200), "").exit_code == 0);
        std::string bytes = slurp(dir.file("out/checkpoint.mrjam"));
        auto u64 = [&](std::size_t at) {
            std::uint64_t v;
            std::memcpy(&v, bytes.data() + at, sizeof v);
            return v;
        };
        // The positions: a length n followed by n Vec3 (24 bytes) and the velocities' length n.
        std::size_t velocities = 0;
        for (std::size_t at = 0; velocities == 0 && at + 8 <= bytes.size(); ++at) {
            const std::uint64_t n = u64(at);
            if (n > 100 && n < 1000000 && at + 16 + 24 * n <= bytes.size() && u64(at + 8 + 24 * n) == n)
                velocities = at + 8 + 24 * n;
        }
        REQUIRE(velocities > 0);
        const std::uint64_t shorter = u64(velocities) - 100;
        std::memcpy(bytes.data() + velocities, &shorter, sizeof shorter);
        bytes.erase(velocities + 8, 24 * 100);
        mrjam_test::reseal_checkpoint(bytes);  // past the checksum, to the arrays' own check
        write_text(dir.file("damaged.mrjam"), bytes);
        const Result r = mrjam_test::mrjam(dir, "jam --resume " + quote(dir.file("damaged.mrjam")) + " --report " +
                                                    quote(dir.file("damaged_report.json")) + " --quiet");
        CAPTURE(r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("--resume") != std::string::npos);
        CHECK(r.err.find("per-grain arrays of different lengths") != std::string::npos);
    }

    TEST_CASE("jam --seeds: Ctrl-C while a later seed places its grains keeps the seeds done for --resume") {
        TempDir dir;
        const Result full = jam(dir, "full", tiny_scene(dir.file("out_full"), 0), "--seeds 2");
        REQUIRE(full.exit_code == 0);
        // The same campaign in this process, the interrupt raised as seed 2 is built: its packing
        // stops at once (SetupInterrupted), before it has any state a checkpoint could hold.
        mrjam::JamCampaignRequest req;
        req.scene_path = dir.file("cut.json");
        req.scene = tiny_scene(dir.file("out_cut"), 0);
        write_text(req.scene_path, req.scene.dump());
        req.report_path = dir.file("cut_report.json");
        req.fidelity = "quick";
        req.seeds = 2;
        req.threads = mrjam::machine_threads();  // as the command's runs (bit for bit per thread count)
        req.progress = false;
        req.before_seed = [](int k) {
            if (k == 1) mrjam::request_interrupt();
        };
        struct ClearAfter {  // the flag is process-wide: later tests must not see it, whatever happens here
            ~ClearAfter() { mrjam::clear_interrupt(); }
        };
        int status = 0;
        {
            ClearAfter clear;
            status = mrjam::run_jam_campaign(req);
        }
        CHECK(status == 130);
        const json partial = json::parse(slurp(req.report_path));
        CHECK(partial["status"] == "interrupted");
        REQUIRE(partial["seeds"].size() == 1);  // seed 1 kept
        CHECK(partial["resume_note"].get<std::string>().find("afresh") != std::string::npos);
        CHECK(partial["resume_with"].get<std::string>().find("jam --resume") == 6);
        // `mrjam run --resume` cannot take it (it holds no engine state), and says so.
        const Result run_resume = mrjam_test::mrjam(dir, "run --resume " + quote(dir.file("out_cut/checkpoint.mrjam")) +
                                                             " --report " + quote(dir.file("run.json")) + " --quiet");
        CHECK(run_resume.exit_code == 2);
        // The usual resume command finishes it as the uninterrupted campaign.
        const json resumed = resumed_report(dir, "cut");
        const json a = json::parse(slurp(dir.file("full_report.json")));
        CHECK(comparable(resumed)["seeds"] == comparable(a)["seeds"]);
        CHECK(comparable(resumed)["results"] == comparable(a)["results"]);
    }

    TEST_CASE("jam: Ctrl-C keeps a checkpoint that --resume finishes as the uninterrupted run") {
        TempDir dir;
        const Result full = jam(dir, "full", tiny_scene(dir.file("out_full"), 0), "");
        REQUIRE(full.exit_code == 0);
        const json a = json::parse(slurp(dir.file("full_report.json")));
        write_text(dir.file("cut.json"), tiny_scene(dir.file("out_cut"), 0).dump());
        const Result cut =
            mrjam_test::mrjam_interrupted(dir,
                                          "jam " + quote(dir.file("cut.json")) + " --report " +
                                              quote(dir.file("cut_report.json")) + " --fidelity quick --quiet",
                                          std::max(0.05, 0.5 * a["wall_time_s"].get<double>()),
                                          [&](const Result&) { return fs::exists(dir.file("cut_report.json")); });
        REQUIRE(cut.exit_code == 130);
        const json c = json::parse(slurp(dir.file("cut_report.json")));
        CHECK(c["results"]["flux_history"]["partial"] == true);
        // No outcome is claimed before the protocol has ended.
        CHECK(c["results"]["outcome"].get<std::string>().rfind("incomplete", 0) == 0);
        CHECK(c["resume_with"].get<std::string>().find("mrjam jam --resume") != std::string::npos);
        const Result resumed = mrjam_test::mrjam(dir, "jam --resume " + quote(c["checkpoint"].get<std::string>()) +
                                                          " --report " + quote(dir.file("resumed.json")) + " --quiet");
        CAPTURE(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        const json b = json::parse(slurp(dir.file("resumed.json")));
        CHECK(b["results"]["flux_history"]["partial"] == false);
        CHECK(comparable(b)["results"] == comparable(a)["results"]);
        // Once complete, the checkpoint is gone: resumed again it would run the end again.
        CHECK_FALSE(fs::exists(c["checkpoint"].get<std::string>()));
    }

    TEST_CASE("jam --snapshots: VTK files in time, at arrest and at the end, with the contact clusters") {
        TempDir dir;
        const Result r = jam(dir, "snap", tiny_scene(dir.file("out"), 0),
                             "--snapshots " + quote(dir.file("vtk")) + " --snapshot-every 2e-5");  // plain seconds
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("snap_report.json")));
        const double t_end = report["results"]["simulated_time_s"].get<double>();
        int series = 0;
        for (const auto& entry : fs::directory_iterator(dir.file("vtk")))
            if (entry.path().filename().string().find("_step") != std::string::npos) ++series;
        // One at the first observation and one per 0.02 ms after it; the last multiple of 0.02 ms
        // may fall after the last observation (every 20 steps), so it may be missing.
        const int due = static_cast<int>(std::floor(t_end / 0.02e-3)) + 1;
        CHECK(series <= due);
        CHECK(series >= due - 1);
        CHECK(series >= 3);
        CHECK(report["outputs"]["snapshots"].size() == static_cast<std::size_t>(series) + 2);
        REQUIRE(report["results"]["jammed"] == true);
        for (const char* tag : {"arrest", "end"}) {
            CAPTURE(tag);
            const std::string file = slurp(dir.file(std::string("vtk/seed1_") + tag + ".vtk"));
            const auto cluster = legacy_int_array(file, "cluster");
            const auto size = legacy_int_array(file, "cluster_size");
            REQUIRE(cluster.size() == size.size());
            REQUIRE(!cluster.empty());
            // Every grain's cluster_size is the number of grains with its label, and label 0 is the
            // largest cluster.
            std::map<std::int32_t, std::int32_t> count;
            for (auto c : cluster) ++count[c];
            std::int32_t largest = 0;
            for (auto [label, n] : count) largest = std::max(largest, n);
            CHECK(count[0] == largest);
            for (std::size_t i = 0; i < cluster.size(); ++i) REQUIRE(size[i] == count[cluster[i]]);
        }
        // The report names the clusters as they were at the arrest: the arrest snapshot's largest.
        CHECK(report["results"]["clusters_seen_at"] == "arrest");
        const auto arrest_cluster = legacy_int_array(slurp(dir.file("vtk/seed1_arrest.vtk")), "cluster_size");
        CHECK(*std::max_element(arrest_cluster.begin(), arrest_cluster.end()) ==
              report["results"]["largest_cluster"].get<int>());
        // Bad interval: refused, naming the option.
        const Result bad = jam(dir, "bad", tiny_scene(dir.file("out_bad"), 0),
                               "--snapshots " + quote(dir.file("v2")) + " --snapshot-every '3 kg'");
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("--snapshot-every") != std::string::npos);
        // An interval below the time's resolution hung the run (signals too): refused, as are more
        // than 2000 frames, a frame interval past the run, and a snapshot directory that is a file.
        for (const std::string every : {"1e-300", "1e-12", "1"}) {
            CAPTURE(every);
            const Result tiny = jam(dir, "tiny", tiny_scene(dir.file("out_tiny"), 0),
                                    "--snapshots " + quote(dir.file("v3")) + " --snapshot-every " + every);
            CHECK(tiny.exit_code == 2);
            CHECK(tiny.err.find("--snapshot-every") != std::string::npos);
        }
        write_text(dir.file("a_file"), "x");
        const Result onto_file =
            jam(dir, "onto_file", tiny_scene(dir.file("out_file"), 0), "--snapshots " + quote(dir.file("a_file")));
        CHECK(onto_file.exit_code == 2);
        CHECK(onto_file.err.find("--snapshots") != std::string::npos);
        // An interval without snapshots to space would be ignored: refused too.
        const Result alone = jam(dir, "alone", tiny_scene(dir.file("out_alone"), 0), "--snapshot-every 2e-5");
        CHECK(alone.exit_code == 2);
        CHECK(alone.err.find("--snapshot-every") != std::string::npos);
    }

}  // TEST_SUITE
