// The jam predictor's pieces: flux counting through the throat plane, contact clusters, and the
// command's refusals and report.
#include <doctest/doctest.h>

#include <limits>

#include "contact_clusters.hpp"
#include "core/format.hpp"
#include "io/svg_raster.hpp"
#include "jam/axial_resistance.hpp"
#include "jam/closed_flow.hpp"
#include "jam/jam_outcome.hpp"
#include "jam/jam_protocol_steps.hpp"
#include "jam/jam_results.hpp"
#include "jam/jam_run.hpp"
#include "jam/jam_scene.hpp"
#include "jam/steady_flow.hpp"
#include "jam/throat_flux.hpp"
#include "magnetics/getdp_problem.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/drag_term.hpp"
#include "test_support.hpp"

using namespace mrjam;
using namespace mrjam_test;
using nlohmann::json;

namespace {

// The short tube the command-line runs use: 1.1 mm of tube upstream of the throat, 0.3 mm downstream
// (a few thousand grains at the quick tier). `extra` adds or replaces model keys.
json short_tube(const json& extra = json::object()) {
    json model = {{"upstream_length", "1.1 mm"}, {"downstream_length", "0.3 mm"}};
    model.update(extra);
    return model;
}

// A protocol over in a few hundred quick steps: 0.05 ms without field, at most 0.04 ms magnetised at
// rest (settle checks every 0.01 ms), 0.05 ms under pressure judged on 0.02 ms windows, and 0.02 ms
// to release.
json brief_protocol() {
    return {{"flow_time", "0.05 ms"}, {"magnetise_time", "0.04 ms"}, {"settle_window", "0.01 ms"},
            {"max_time", "0.05 ms"},  {"arrest_window", "0.02 ms"},  {"release_time", "0.02 ms"}};
}

// The design's coarse field solve (seconds with GetDP) and a brief pressure-driven jam run in the
// short tube, for the 30x constriction.
json brief_design(const std::string& output_directory) {
    return {{"constrictions", {"30x"}},
            {"magnetics", {{"mesh", {{"fluid_size", "0.4 mm"}, {"device_size", "1 mm"}, {"far_size", "5 mm"}}}}},
            {"jam", {{"model", short_tube()}, {"fluid", {{"flow", "pressure"}}}, {"protocol", brief_protocol()}}},
            {"output", {{"directory", output_directory}}}};
}

// A jam scene must name its field: the source's 230 mT across the valve unless `scene` gives one.
json with_field(json scene) {
    if (!scene.contains("field")) scene["field"] = {{"type", "uniform"}, {"flux_density", "230 mT"}};
    return scene;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("throat flux: crossings counted with sign, periodic wraps ignored") {
        System s;
        s.domain.lo = {-1, -1, -1};
        s.domain.hi = {1, 1, 1};
        s.particles.position = {{0, 0, -0.1}, {0, 0, 0.2}, {0, 0, 0.9}};
        ThroatFlux flux(0.0);
        flux.observe(s);
        s.time = 1;
        s.particles.position = {{0, 0, 0.05}, {0, 0, -0.05}, {0, 0, -0.95}};  // +1, -1, and a wrap (no crossing)
        flux.observe(s);
        CHECK(flux.passed() == 0);
        s.time = 2;
        s.particles.position = {{0, 0, 0.1}, {0, 0, 0.01}, {0, 0, -0.5}};  // grain 1 crosses forward
        flux.observe(s);
        CHECK(flux.passed() == 1);
        CHECK(flux.rate_between(1, 2) == rel(1.0));
        CHECK(flux.rate(1.0) == rel(1.0));
        CHECK(flux.rate(5.0) == 0.0);  // history shorter than the window
    }

    TEST_CASE("axial resistance: cell volumes, Kozeny-Carman factor, and the circuit's flow scale") {
        ValveGeometry v;
        v.upstream_length = 1.0e-3;
        v.downstream_length = 0.5e-3;
        const double phi0 = 0.345, P = 105e3;
        // Full bore: the cells' fluid volumes add up to the passage's exact volume (Simpson between
        // the valve's breakpoints is exact for the cone's quadratic section; rounding ~1e-12).
        const AxialResistance bore(v, 0.0, -v.upstream_length, v.downstream_length, 88e-6, phi0, P);
        double total = 0;
        for (std::size_t k = 0; k < bore.cells(); ++k) total += bore.cell_volume(k);
        CHECK(total == rel(v.fluid_volume()).epsilon(1e-9));
        // A slab |x| < h inside the bore holds the chord area: cross-checked on a straight bore cell.
        const double h = 66e-6, rb = v.bore_radius();
        const AxialResistance slab(v, h, -v.upstream_length, v.downstream_length, 88e-6, phi0, P);
        CHECK(slab.cell_section(0) == rel(slab_section(rb, h)).epsilon(1e-12));
        CHECK(slab_section(rb, h) == rel(4 * h * rb).epsilon(1e-3));  // thin slab: a 2h x 2r_b strip

        // Kozeny-Carman per grain, phi / (1 - phi)^2, relative to the feed: 1 at and below the feed.
        CHECK(bore.drag_factor(phi0) == rel(1.0));
        CHECK(bore.drag_factor(0.1) == 1.0);
        CHECK(bore.drag_factor(0.55) == rel(0.55 / (0.45 * 0.45) * (0.655 * 0.655) / 0.345));
        CHECK(bore.drag_factor(0.9) == bore.drag_factor(0.62));  // capped, finite

        // The flow scale: one grain in the straight bore upstream, at the feed's density (factor 1).
        System s;
        s.terms.add(std::make_unique<DragTerm>(0.16, 1));
        const double R = 20e-6;
        s.particles.position = {{0, 0, -0.8e-3}};
        s.particles.radius = {R};
        s.particles.velocity = {{0, 0, 0}};
        ValveFlow flow(v, 0.273);
        AxialResistance one(v, 0.0, -v.upstream_length, v.downstream_length, 88e-6, 1e-6,
                            P);  // feed ~0: factor from phi
        const std::size_t k = static_cast<std::size_t>((-0.8e-3 + v.upstream_length) / (1.5e-3 / one.cells()));
        const double phi = 4.0 / 3.0 * M_PI * R * R * R / one.cell_volume(k);
        const double d1 = 6 * M_PI * 0.16 * R * one.drag_factor(phi) * 0.273 / one.cell_section(k);
        // At rest: s = P / (P + D1/A).
        AxialResistanceState st = one.update(s, flow, true);
        CHECK(st.scale == rel(P / (P + d1)).epsilon(1e-12));
        CHECK(flow.scale() == st.scale);
        CHECK(st.stretch_pressure == rel(st.scale * d1).epsilon(1e-12));
        // A raised supply P' through the same circuit (protocol/hold_pressure): s = P' / (P + D1/A).
        st = one.update(s, flow, true, 4 * P);
        CHECK(st.scale == rel(4 * P / (P + d1)).epsilon(1e-12));
        // Moving with the fluid: no slip, no extra resistance, the prescribed flow.
        s.particles.velocity = {{0, 0, 0.273}};
        st = one.update(s, flow, true);
        CHECK(st.scale == rel(1.0));
        CHECK(st.stretch_pressure == doctest::Approx(0.0).scale(1.0));
        // ... and at P' the circuit is linear: the open flow times P' / P.
        s.particles.velocity = {{0, 0, 4 * 0.273}};
        CHECK(one.update(s, flow, true, 4 * P).scale == rel(4.0));
        // The prescribed flow is only measured: scale and factors untouched.
        ValveFlow prescribed(v, 0.273);
        s.particles.velocity = {{0, 0, 0}};
        st = one.update(s, prescribed, false);
        CHECK(prescribed.scale() == 1.0);
        CHECK(prescribed.drag_factor({0, 0, -0.8e-3}) == 1.0);
        CHECK(st.arrested_pressure == rel(6 * M_PI * 0.16 * R * 0.273 / one.cell_section(k)));
    }

    TEST_CASE("axial resistance: a packed plug in the throat stops the pressure-driven flow") {
        // A lens of grains packed at 0.6 in the throat, at rest: the drag the prescribed flow would
        // put on it, as pressure on the throat's section, is far above the supply pressure, so
        // the flow falls below a tenth (~2,000 grains x 1.4e-4 N x the packing factor ~3 on 0.61 mm^2:
        // ~1.6 MPa against 105 kPa); the same grains moving with the fluid leave it at 1.
        ValveGeometry v;
        v.constriction_diameter = 0.88e-3;
        v.upstream_length = 1.0e-3;
        v.downstream_length = 0.5e-3;
        System s;
        s.terms.add(std::make_unique<DragTerm>(0.16, 1));
        const double R = 20e-6, rt = v.throat_radius();
        // 0.2 mm cells from -0.9 mm: cell 4 is exactly the straight throat (-0.1 .. 0.1 mm).
        const AxialResistance res(v, 0.0, -0.9e-3, 0.5e-3, 0.2e-3, 0.345, 105e3);
        // Grains on a lattice filling the throat cylinder at ~0.6.
        const double a = std::cbrt(4.0 / 3.0 * M_PI * R * R * R / 0.6);
        for (double z = -0.1e-3 + 0.5 * a; z < 0.1e-3; z += a)
            for (double x = -rt; x <= rt; x += a)
                for (double y = -rt; y <= rt; y += a)
                    if (x * x + y * y < (rt - R) * (rt - R)) {
                        s.particles.position.push_back({x, y, z});
                        s.particles.radius.push_back(R);
                        s.particles.velocity.push_back({0, 0, 0});
                    }
        ValveFlow flow(v, 0.273);
        const AxialResistanceState st = res.update(s, flow, true);
        CAPTURE(st.max_fraction);
        CHECK(st.max_fraction > 0.45);
        CHECK(st.arrested_pressure > 10 * 105e3);
        CHECK(st.scale < 0.1);
        CHECK(flow.drag_factor({0, 0, 0}) > 1.5);
        for (auto& vel : s.particles.velocity) vel = flow.unscaled({0, 0, 0});  // moving with the unscaled fluid
        CHECK(res.update(s, flow, true).scale == rel(1.0));
    }

    // A flux history of its own: (time, net grains passed) every 10 us from the field's switch-on
    // at t = 0, the count given by `passed(t)`.
    template <class Passed>
    ThroatFlux flux_history(double until, Passed passed) {
        json rows = json::array();
        for (int k = 0; k * 10e-6 <= until + 1e-12; ++k) rows.push_back({k * 10e-6, std::lround(passed(k * 10e-6))});
        ThroatFlux flux;
        flux.restore({{"plane", 0.0}, {"previous_z", json::array()}, {"passed", rows.back()[1]}, {"history", rows}});
        return flux;
    }

    TEST_CASE("steady flow: two windows of equal flux and a settled flow scale, nothing less") {
        const SteadyFlowCriterion c{1e-3, 0.15};
        // A constant 1e6 grains/s: steady once two 1 ms windows exist, not before.
        const auto constant = [](double t) { return 1e6 * t; };
        CHECK(steady_flow(flux_history(2e-3, constant), {}, 0.0, c).steady);
        CHECK(steady_flow(flux_history(2e-3, constant), {}, 0.0, c).last_rate == rel(1e6));
        CHECK_FALSE(steady_flow(flux_history(1.9e-3, constant), {}, 0.0, c).steady);
        // The field came on at 0.5 ms: the flux before it does not count.
        CHECK_FALSE(steady_flow(flux_history(2e-3, constant), {}, 0.5e-3, c).steady);
        // Off when the window is 0.
        CHECK_FALSE(steady_flow(flux_history(3e-3, constant), {}, 0.0, {0.0, 0.15}).steady);
        // Halving every millisecond (flux 2e6 e^{-t ln 2 / 1 ms}): windows 50 % apart, not steady.
        const double k = std::log(2.0) / 1e-3;
        const auto halving = [&](double t) { return 2e6 / k * (1 - std::exp(-k * t)); };
        CHECK_FALSE(steady_flow(flux_history(2e-3, halving), {}, 0.0, c).steady);
        // A 10 % fall per window is within a 15 % tolerance, a 20 % fall is not.
        const auto fall = [](double drop) {
            return [drop](double t) { return t <= 1e-3 ? 1e6 * t : 1e3 + (1 - drop) * 1e6 * (t - 1e-3); };
        };
        CHECK(steady_flow(flux_history(2e-3, fall(0.10)), {}, 0.0, c).steady);
        CHECK_FALSE(steady_flow(flux_history(2e-3, fall(0.20)), {}, 0.0, c).steady);
        // An arrest (no grains through) is not a steady flow.
        CHECK_FALSE(steady_flow(flux_history(2e-3, [](double) { return 0.0; }), {}, 0.0, c).steady);
        // Pressure-driven flow: the flux is steady but the flow scale fell 30 % over the last
        // window (the grains are still throttling the fluid): not yet steady; a settled scale is.
        std::vector<FlowSample> falling, settled;
        for (int i = 0; i <= 200; ++i) {
            const double t = i * 10e-6;
            falling.push_back({t, 1.0 - 0.3 * std::max(0.0, t - 1e-3) / 1e-3, 0, 0});
            settled.push_back({t, 0.6, 0, 0});
        }
        CHECK_FALSE(steady_flow(flux_history(2e-3, constant), falling, 0.0, c).steady);
        CHECK(steady_flow(flux_history(2e-3, constant), settled, 0.0, c).steady);
    }

    TEST_CASE("throat flux: when an arrested bed gives way, counted from the arrest over a window against a limit") {
        // Arrested (no grains) until 1 ms, then 1e6 grains/s. Over a 0.2 ms window a limit of
        // 7.5e4 /s is 15 grains: passed 10 us after the break (10 grains) it is not exceeded, at
        // 20 us (20 grains) it is.
        const auto breaks = [](double t) { return t <= 1e-3 ? 0.0 : 1e6 * (t - 1e-3); };
        const ThroatFlux flux = flux_history(2e-3, breaks);
        CHECK(flux.first_time_above(0.0, 2e-3, 0.2e-3, 7.5e4) == rel(1.02e-3));
        // Only grains passed after t0 count (from 1.055 ms: 20 of them by 1.08 ms), and no
        // observation after t1.
        CHECK(flux.first_time_above(1.055e-3, 2e-3, 0.2e-3, 7.5e4) == rel(1.08e-3));
        CHECK(std::isnan(flux.first_time_above(0.0, 1.015e-3, 0.2e-3, 7.5e4)));
        // A bed that stays put never gives way; one creeping below the limit neither.
        CHECK(std::isnan(flux_history(2e-3, [](double) { return 0.0; }).first_time_above(0.0, 2e-3, 0.2e-3, 7.5e4)));
        CHECK(std::isnan(
            flux_history(2e-3, [](double t) { return 5e4 * t; }).first_time_above(0.0, 2e-3, 0.2e-3, 7.5e4)));
    }

    TEST_CASE("throat flux: the share of the no-field flux in consecutive whole windows with the field on") {
        // 1e6 grains/s until 1 ms, then half that; observations every 10 us and window edges half-way
        // between them (a count at time t is the first observation at or after it). Against a base of
        // 1e6 /s, 0.2 ms windows from 0.605 ms read 1 (0.61-0.81 ms: 200 grains), 0.975 (0.81-1.01:
        // 190 + 5), then 0.5 twice; 1.45 ms holds no fifth whole window.
        const auto halves = [](double t) { return t <= 1e-3 ? 1e6 * t : 1e3 + 5e5 * (t - 1e-3); };
        const auto shares = flux_history(2e-3, halves).window_shares(0.605e-3, 1.45e-3, 0.2e-3, 1e6);
        REQUIRE(shares.size() == 4);
        CHECK(shares[0].first == rel(0.805e-3));
        CHECK(shares[0].second == rel(1.0));
        CHECK(shares[1].second == rel(0.975));
        CHECK(shares[2].second == rel(0.5));
        CHECK(shares[3].first == rel(1.405e-3));
        CHECK(shares[3].second == rel(0.5));
        // A span of exactly two windows gives two (the rounding of t0 + k w does not drop one).
        CHECK(flux_history(2e-3, halves).window_shares(0.1e-3, 0.7e-3, 0.3e-3, 1e6).size() == 2);
        // No reference flux, no window, or a span shorter than one window: no shares.
        CHECK(flux_history(2e-3, halves).window_shares(0.0, 2e-3, 0.2e-3, 0.0).empty());
        CHECK(flux_history(2e-3, halves).window_shares(0.0, 2e-3, 0.0, 1e6).empty());
        CHECK(flux_history(2e-3, halves).window_shares(0.0, 0.15e-3, 0.2e-3, 1e6).empty());
    }

    TEST_CASE("closed flow share: the flow scale over the arrest window against the no-field reference") {
        // Samples every 10 us, half-way between whole multiples, so that none sits on a window's edge.
        // During the 1 ms flow period the scale ramps 0 -> 2, so its mean over the reference half
        // [0.5, 1] ms (samples placed symmetrically in it) is 1.5 exactly; after it the scale is 0.3
        // in the arrest window [1.6, 1.8] ms and 0.9 elsewhere: the share is 0.3 / 1.5 = 0.2.
        std::vector<FlowSample> h;
        for (int i = 0; i < 300; ++i) {
            const double t = 5e-6 + i * 10e-6;
            h.push_back({t, i < 100 ? 2.0 * t / 1e-3 : (i >= 160 && i < 180) ? 0.3 : 0.9, 0, 0});
        }
        CHECK(mean_flow_scale(h, 0.5e-3, 1e-3) == rel(1.5));
        CHECK(closed_flow_share(h, 1e-3, 1.6e-3, 0.2e-3) == rel(0.2));
        // No sample in a window: no figure rather than a made-up one.
        CHECK(std::isnan(mean_flow_scale(h, 4e-3, 5e-3)));
        CHECK(std::isnan(closed_flow_share(h, 1e-3, 4e-3, 0.2e-3)));
        CHECK(std::isnan(closed_flow_share({}, 1e-3, 1.6e-3, 0.2e-3)));
    }

    TEST_CASE("hold pressure: a step at the arrest, or a linear ramp to it") {
        JamProtocol p;
        p.hold_pressure = 405e3;
        CHECK(p.supply_after_arrest(0.0, 105e3) == 405e3);  // a step by default
        p.hold_pressure_ramp = 0.5e-3;
        CHECK(p.supply_after_arrest(0.0, 105e3) == rel(105e3));
        CHECK(p.supply_after_arrest(0.25e-3, 105e3) == rel(255e3));
        CHECK(p.supply_after_arrest(0.5e-3, 105e3) == rel(405e3));
        CHECK(p.supply_after_arrest(2e-3, 105e3) == rel(405e3));
        // The default hold pressure is the scene's supply: nothing changes.
        JamProtocol same;
        same.hold_pressure = 105e3;
        CHECK(same.supply_after_arrest(1e-3, 105e3) == 105e3);
    }

    TEST_CASE("seed summary: a seed's progress line names its outcome, arrest and hold, or its flux") {
        const json none(nullptr);
        // Times to 3 significant digits: a run's arrest time is only known to an observation step.
        json broke = {{"outcome", "fail-no-hold"},
                      {"time_to_arrest_s", 0.493717e-3},
                      {"hold", {{"held", false}, {"gave_way_after_s", 0.12987e-3}}}};
        CHECK(seed_summary(broke) == "fail-no-hold, arrest at 0.494 ms of field, gave way 0.13 ms into the hold");
        json held = {{"outcome", "success"},
                     {"time_to_arrest_s", 0.3e-3},
                     {"hold", {{"held", true}, {"gave_way_after_s", none}}}};
        CHECK(seed_summary(held) == "success, arrest at 0.3 ms of field, held");
        json no_hold = {{"outcome", "success"}, {"time_to_arrest_s", 0.3e-3}, {"hold", none}};
        CHECK(seed_summary(no_hold) == "success, arrest at 0.3 ms of field");
        json flowed = {{"outcome", "fail-no-jam"}, {"time_to_arrest_s", none}, {"flux_share_last_window", 0.6393}};
        CHECK(seed_summary(flowed) == "fail-no-jam, grain flux at 64 % of the no-field flux over the last window");
        // A seed stopped before its outcome has only a status.
        CHECK(seed_summary(json{{"status", "interrupted"}}) == "interrupted");
        CHECK(seed_summary(json{{"outcome", none}, {"status", "blew up"}}) == "blew up");
    }

    TEST_CASE("jam outcome: Table 3.2's words, and a hold that breaks is no jam") {
        auto verdict = [](bool jammed, bool hold_asked, bool held, bool released) {
            JamVerdict v;
            v.jammed = jammed;
            v.hold_asked = hold_asked;
            v.held = held;
            v.released = released;
            return v;
        };
        // Without a hold the arrest alone decides, as the source's simulations did.
        CHECK(jam_outcome_word(verdict(false, false, false, false)) == "fail-no-jam");
        CHECK(jam_outcome_word(verdict(true, false, false, true)) == "success");
        CHECK(jam_outcome_word(verdict(true, false, false, false)) == "fail-irreversible");
        CHECK(jam_stops_flow(verdict(true, false, false, false)));
        CHECK_FALSE(jam_stops_flow(verdict(false, false, false, false)));
        // With a hold an arrest must also hold: one that breaks lets the fluid through with the
        // magnet on, which the experiment would score as no jam, whatever the release test says.
        CHECK(jam_outcome_word(verdict(true, true, true, true)) == "success");
        CHECK(jam_outcome_word(verdict(true, true, true, false)) == "fail-irreversible");
        CHECK(jam_outcome_word(verdict(true, true, false, true)) == "fail-no-hold");
        CHECK(jam_outcome_word(verdict(true, true, false, false)) == "fail-no-hold");
        CHECK(jam_stops_flow(verdict(true, true, true, true)));
        CHECK_FALSE(jam_stops_flow(verdict(true, true, false, true)));
        // No outcome before the protocol has ended, and none without a no-field reference.
        JamVerdict cut = verdict(true, true, false, false);
        cut.incomplete = true;
        CHECK(jam_outcome_word(cut).rfind("incomplete", 0) == 0);
        // A run that blew up is not one to resume: it says so rather than "resume with --resume".
        JamVerdict broken = verdict(false, false, false, false);
        broken.incomplete = broken.blew_up = true;
        CHECK(jam_outcome_word(broken).rfind("failed (the run blew up", 0) == 0);
        CHECK_FALSE(jam_stops_flow(broken));
        // No grain across in the no-field reference flow: too slow a flow to tell, or (where the carrier
        // would have brought many) a plain clog, which stops the flow.
        JamVerdict blind = verdict(false, false, false, false);
        blind.undetermined = true;
        CHECK(jam_outcome_word(blind) == "undetermined");
        CHECK_FALSE(jam_stops_flow(blind));
        JamVerdict clogged = verdict(false, false, false, false);
        clogged.clogged = true;
        CHECK(jam_outcome_word(clogged) == "clog");
        CHECK(jam_stops_flow(clogged));
        clogged.incomplete = true;
        CHECK(jam_outcome_word(clogged).rfind("incomplete", 0) == 0);
        CHECK_FALSE(jam_stops_flow(clogged));
        // With no field an arrest is a clog too, not a jam the magnet made; one that gives way is no hold.
        JamVerdict plain = verdict(true, false, false, false);
        plain.field_free = true;
        CHECK(jam_outcome_word(plain) == "clog");
        CHECK(jam_stops_flow(plain));
        plain.hold_asked = true;
        CHECK(jam_outcome_word(plain) == "fail-no-hold");
        plain.field_free = false;
        plain.jammed = false;
        plain.field_free = true;
        CHECK(jam_outcome_word(plain) == "fail-no-jam");
    }

}  // TEST_SUITE

TEST_SUITE("cli") {
    TEST_CASE("jam: impossible or meaningless scenes are refused before the run") {
        TempDir dir;
        auto refused = [&](const std::string& label, const json& scene, const std::string& path) {
            expect_mode_refused(dir, "jam", label, with_field(scene), path);
        };
        // Messages show numbers as a user writes them ("44 um"), not std::to_string's "44.000000".
        refused("narrow_throat", {{"valve", {{"constriction_diameter", "40 um"}}}},
                "/valve/constriction_diameter: the throat is not wider than the largest grain (44 um)");
        refused("size_as_preset", {{"valve", {{"constriction", "1 mm"}}}},
                "/valve/constriction: takes a preset (20x, 30x or 40x); give a size such as \"1 mm\" as "
                "constriction_diameter instead");
        refused("zero_threshold", {{"protocol", {{"arrest_fraction", 0}}}}, "/protocol/arrest_fraction");
        refused("dense", {{"grains", {{"volume_fraction", 0.7}}}}, "/grains/volume_fraction");
        // Below random close packing but more than the valve's walls let the packing reach: refused by
        // the generated engine scene's packer, named as the jam scene's key (not /grains/0/placement/...).
        expect_mode_refused(dir, "jam", "unpackable",
                            with_field({{"valve", {{"constriction", "20x"}}},
                                        {"grains", {{"volume_fraction", 0.6}}},
                                        {"model", {{"upstream_length", "0.95 mm"}, {"downstream_length", "0.3 mm"}}},
                                        {"output", {{"directory", dir.file("out_unpackable")}}}}),
                            "error in scene: /grains/volume_fraction:", "--fidelity quick");
        refused("empty_table", {{"grains", {{"diameters", json::array()}, {"mass_fractions", json::array()}}}},
                "/grains/diameters");
        // A field map that covers only part of the valve.
        const std::string map = dir.file("small.map");
        write_text(map, "mrjam-fieldmap 1\n2 2 2\n-1e-4 -1e-4 -1e-4\n2e-4 2e-4 2e-4\n" + std::string(8 * 1, ' ') +
                            "0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n");
        // The valve in millimetres: the standard tier's slab (6 x 44 um), the 2.6 mm bore, its tube.
        refused("small_map", {{"field", {{"type", "map"}, {"file", map}}}},
                "/field/file: the field map does not cover the modelled valve (x -0.132...0.132, y +-1.3, z "
                "-1.5...0.75 mm)");
        // A header that promises 4096^3 nodes (1.6 TB of values) and ends: refused as it is read, not allocated.
        const std::string huge = dir.file("huge.map");
        write_text(huge, "mrjam-fieldmap 1\n4096 4096 4096\n-1e-4 -1e-3 -1e-3\n1e-6 1e-6 1e-6\n0 0.2 0\n");
        refused("huge_map", {{"field", {{"type", "map"}, {"file", huge}}}}, "/field/file");
        // Tesla for millitesla: no magnet puts 230 T into a valve, and a map scaled past 10 T is refused too.
        refused("tesla_slip", {{"field", {{"flux_density", "230 T"}}}},
                "/field/flux_density: 230 T is more than any magnet applies (10 T at most; the valve's EPM gives "
                "0.2-0.8 T): did you mean mT?");
        const std::string wide = dir.file("wide.map");
        write_text(wide, "mrjam-fieldmap 1\n2 2 2\n-1e-3 -2e-3 -2e-3\n2e-3 4e-3 4e-3\n" +
                             std::string("0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.2 0\n0 0.3 0\n"));
        refused("map_scale", {{"field", {{"type", "map"}, {"file", wide}, {"scale", 40}}}},
                "/field/scale: raises the map's strongest node to 12 T");
        // Grains so fine that the modelled valve would hold more of them than memory does (~1e12 at 1 nm):
        // refused before they are drawn, not by the kernel's out-of-memory killer mid-run.
        const Result fine =
            expect_mode_refused(dir, "jam", "nanometre_grains",
                                with_field({{"grains", {{"diameters", {"1 nm"}}, {"mass_fractions", {1}}}}}),
                                "/grains/volume_fraction: about ");
        CHECK(fine.err.find("this machine's memory holds") != std::string::npos);
        // A duration past the engine's step count is named by the protocol key, not the engine scene's stage.
        refused("endless", {{"protocol", {{"max_time", "1e9 s"}}}}, "/protocol/max_time: needs ");
        // The jet mirrors the taper by default: a stepped orifice must say where the stream re-opens.
        refused("stepped_coupled", {{"valve", {{"taper_length", "0 mm"}}}, {"fluid", {{"flow", "coupled"}}}},
                "/fluid/jet_length: is the taper's length by default");
        refused("two_tables", {{"grains", {{"psd", "10um"}, {"diameters", {"40 um"}}, {"mass_fractions", {1}}}}},
                "/grains/psd");
        refused("typo", {{"protocol", {{"max_tme", "1 ms"}}}}, "/protocol/max_tme");
        refused("absurd_modulus", {{"material", {{"youngs_modulus", 1e-300}}}}, "/material/youngs_modulus");
        // An empty class still set the slab and the cells from its diameter.
        refused("empty_class", {{"grains", {{"diameters", {"44 um", "0.5 mm"}}, {"mass_fractions", {1, 0}}}}},
                "/grains/mass_fractions/1");
        // The prescribed flow takes no supply pressure: it was echoed as if used.
        refused("unused_pressure",
                {{"fluid", {{"flow", "prescribed"}, {"supply_pressure", "400 kPa"}}},
                 {"protocol", {{"order", "open_first"}}}},
                "/fluid/supply_pressure");
        refused("slab_faces", {{"model", {{"slab_faces", "smooth"}}}}, "/model/slab_faces");
        refused("no_evaluation", {{"model", {{"magnetic_update_interval", 0}}}}, "/model/magnetic_update_interval");
        refused("no_skin", {{"model", {{"neighbour_skin", 0}}}}, "/model/neighbour_skin");
        refused("heavier_below", {{"model", {{"heavier_below", "-1 um"}}}}, "/model/heavier_below");
        refused("no_lookup", {{"model", {{"flow_lookup_interval", 0}}}}, "/model/flow_lookup_interval");
        refused("close_pairs", {{"model", {{"close_pairs_min_gap", 0}}}}, "/model/close_pairs_min_gap");
        refused("steady_window", {{"protocol", {{"max_time", "3 ms"}, {"steady_window", "2 ms"}}}},
                "/protocol/steady_window");
        refused("short_cells", {{"fluid", {{"flow", "pressure"}, {"resistance_cell_length", "10 um"}}}},
                "/fluid/resistance_cell_length");
        refused("profile", {{"fluid", {{"profile", "uniform"}}}}, "/fluid/profile");
        // The converging jet must re-open before the periodic seam (the standard tier: 0.65 mm past
        // the exit, less two 88 um cells).
        refused("long_jet", {{"fluid", {{"profile", "converging"}, {"jet_length", "0.7 mm"}}}}, "/fluid/jet_length");
        refused("jet_without_jet", {{"fluid", {{"jet_length", "0.2 mm"}}}}, "/fluid/jet_length");
        // The coupled flow solves its own profile, needs rings a mean grain wide in the throat (the
        // 30x throat's 0.66 mm over 2 x 19.0 um: at most 17), a supply above what clear fluid needs,
        // and a circular orifice.
        refused("coupled_profile", {{"fluid", {{"flow", "coupled"}, {"profile", "source"}}}}, "/fluid/profile");
        refused("coupled_rings", {{"fluid", {{"flow", "coupled"}, {"rings", 19}}}}, "/fluid/rings");
        refused("rings_without_coupled", {{"fluid", {{"rings", 8}}}}, "/fluid/rings");
        refused("coupled_pressure", {{"fluid", {{"flow", "coupled"}, {"supply_pressure", "1 kPa"}}}},
                "/fluid/supply_pressure");
        refused("coupled_slot",
                {{"valve", {{"orifice", "slot"}, {"slot_width", "0.6 mm"}}}, {"fluid", {{"flow", "coupled"}}}},
                "/fluid/flow");
        refused("negative_hold", {{"protocol", {{"hold_time", "-0.1 ms"}}}}, "/protocol/hold_time");
        // The experiment's order (closed first) or the source's simulation's (open first), nothing else;
        // the magnetisation's keys belong to the closed order, which needs a supply pressure to apply.
        refused("order", {{"protocol", {{"order", "closed"}}}}, "/protocol/order");
        refused("magnetise_open", {{"protocol", {{"order", "open_first"}, {"magnetise_time", "1 ms"}}}},
                "/protocol/magnetise_time: applies to protocol/order \"closed_first\" only");
        refused("settle_window", {{"protocol", {{"magnetise_time", "0.3 ms"}, {"settle_window", "0.2 ms"}}}},
                "/protocol/settle_window: two windows must fit in protocol/magnetise_time (0.3 ms)");
        refused("settle_tolerance", {{"protocol", {{"settle_tolerance", 0}}}}, "/protocol/settle_tolerance");
        refused("viscosity_share", {{"protocol", {{"magnetise_viscosity_share", 0}}}},
                "/protocol/magnetise_viscosity_share");
        refused("viscosity_share_open", {{"protocol", {{"order", "open_first"}, {"magnetise_viscosity_share", 0.1}}}},
                "/protocol/magnetise_viscosity_share: applies to protocol/order \"closed_first\" only");
        refused("closed_prescribed", {{"fluid", {{"flow", "prescribed"}}}}, "/protocol/order: closed_first applies");
        // The field is never assumed: no block, or a uniform one without its flux density, is refused.
        expect_mode_refused(dir, "jam", "no_field", {{"valve", {{"constriction", "30x"}}}}, "/field: required");
        expect_mode_refused(dir, "jam", "no_flux_density", {{"field", {{"type", "uniform"}}}}, "/field/flux_density");
        // A hold pressure is the supply during a hold: it needs both.
        refused("hold_pressure_without_hold",
                {{"fluid", {{"flow", "pressure"}}}, {"protocol", {{"hold_pressure", "405 kPa"}}}},
                "/protocol/hold_pressure");
        refused(
            "hold_pressure_prescribed",
            {{"fluid", {{"flow", "prescribed"}}}, {"protocol", {{"hold_time", "1 ms"}, {"hold_pressure", "405 kPa"}}}},
            "/protocol/hold_pressure");
        refused("hold_below_supply",
                {{"fluid", {{"flow", "pressure"}}}, {"protocol", {{"hold_time", "1 ms"}, {"hold_pressure", "50 kPa"}}}},
                "/protocol/hold_pressure: is below fluid/supply_pressure (105 kPa)");
        refused("ramp_without_pressure",
                {{"fluid", {{"flow", "pressure"}}},
                 {"protocol", {{"hold_time", "1 ms"}, {"hold_pressure_ramp", "0.5 ms"}}}},
                "/protocol/hold_pressure_ramp");
        refused("ramp_past_hold",
                {{"fluid", {{"flow", "pressure"}}},
                 {"protocol", {{"hold_time", "1 ms"}, {"hold_pressure", "405 kPa"}, {"hold_pressure_ramp", "2 ms"}}}},
                "/protocol/hold_pressure_ramp");
        // A modelled tube that ends inside the taper: the model block's length is named, not the valve's.
        refused("short_model", {{"model", {{"upstream_length", "0.5 mm"}}}}, "/model/upstream_length");
        // The modelled tube's length given twice, in the model and the valve: one would be ignored.
        refused("length_twice",
                {{"model", {{"downstream_length", "1 mm"}}},
                 {"valve", {{"constriction", "30x"}, {"downstream_length", "2 mm"}}}},
                "/model/downstream_length");
        // A release period shorter than the window it is judged over would call every arrest irreversible.
        refused("short_release", {{"protocol", {{"arrest_window", "0.2 ms"}, {"release_time", "0.1 ms"}}}},
                "/protocol/release_time");
        // No flow, no no-field flux to measure an arrest against.
        refused("still_fluid", {{"fluid", {{"bore_speed", "0 m/s"}}}}, "/fluid/bore_speed");
        refused("no_directory", {{"output", {{"directory", ""}}}}, "/output/directory");
        // A slab that cannot hold the largest grain, or is as wide as the 20x throat (20 grains).
        refused("thin_slab", {{"model", {{"slab_thickness_diameters", 0.5}}}}, "/model/slab_thickness_diameters");
        refused("wide_slab", {{"valve", {{"constriction", "20x"}}}, {"model", {{"slab_thickness_diameters", 25}}}},
                "/model/slab_thickness_diameters");
        // Flux counted less than 4 times per arrest window (36 ns quick step x 2000 = 72 us > 50 us):
        // the window would read a zero rate, a false arrest. Refused once the step is known, before a step is run.
        expect_mode_refused(
            dir, "jam", "sparse_observations",
            with_field(
                {{"valve", {{"constriction", "30x"}}},
                 {"model", short_tube()},
                 {"protocol", {{"flow_time", "0.3 ms"}, {"arrest_window", "0.05 ms"}, {"observe_every_steps", 2000}}}}),
            "/protocol/observe_every_steps", "--fidelity quick");
    }

    // A carrier at 10 km/s throws the grains together within two steps: the run stops with exit 3,
    // the blow-up's cause on stderr and in the report, and an outcome that does not offer a resume.
    TEST_CASE("jam: a run that blows up says where and why, and is not offered a resume") {
        TempDir dir;
        const json scene = {{"valve", {{"constriction", "30x"}}},
                            {"model", short_tube()},
                            {"fluid", {{"bore_speed", "1e4 m/s"}}},
                            {"protocol", brief_protocol()},
                            {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "blown", with_field(scene), "--fidelity quick");
        CAPTURE(r.err);
        CHECK(r.exit_code == 3);
        CHECK(r.err.find("blow-up at step") != std::string::npos);
        const json report = json::parse(slurp(dir.file("blown_report.json")));
        CHECK(report["status"] == "failed");
        CHECK(report["error"].get<std::string>().find("overlaps") != std::string::npos);
        CHECK(report["results"]["field_period_ended_by"] == "blow-up");
        CHECK(report["results"]["outcome"].get<std::string>().rfind("failed (the run blew up", 0) == 0);
        CHECK(report["results"]["flux_history"]["partial"] == true);
    }

    // A fluid too slow to carry a grain through the throat during the no-field flow leaves nothing to
    // measure an arrest against: the seed is undetermined, left out of the probabilities, and with no
    // seed judged the command fails (exit 1) rather than report a jam probability of 0.
    TEST_CASE("jam: undetermined seeds are left out of the probabilities") {
        TempDir dir;
        const json scene = {{"valve", {{"constriction", "30x"}}},
                            {"model", short_tube()},
                            {"fluid", {{"bore_speed", "1e-6 m/s"}}},
                            {"protocol",
                             {{"flow_time", "0.02 ms"},
                              {"max_time", "0.02 ms"},
                              {"arrest_window", "0.01 ms"},
                              {"release_time", "0.01 ms"},
                              {"observe_every_steps", 20}}},  // 4 looks a window at the quick tier's step
                            {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "still", with_field(scene), "--fidelity quick");
        CAPTURE(r.err);
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("undetermined") != std::string::npos);
        const json res = json::parse(slurp(dir.file("still_report.json")))["results"];
        CHECK(res["outcome"] == "undetermined");
        CHECK(res["jam_probability"].is_null());
        CHECK(res["jam_probability_95ci"].is_null());
        CHECK(res["undetermined_seeds"] == 1);
        CHECK(res["field_period_ended_by"] != "max_time");
    }

    // The continuum tier: a Bingham plug, dP_hold linear in the yield stress, and a valve that closes
    // exactly when dP_hold exceeds the supply; its scene errors name the continuum block.
    TEST_CASE("jam --fidelity continuum: the plug's holding pressure scales with the yield stress") {
        TempDir dir;
        // [[B, tau_y], ...] as JSON arrays (an initializer list of string pairs would be an object).
        auto pairs = [](const std::vector<std::pair<std::string, std::string>>& rows) {
            json table = json::array();
            for (const auto& [b, tau] : rows) table.push_back(json::array({b, tau}));
            return table;
        };
        auto plug = [&](const std::string& name, const std::string& tau) {
            const json scene =
                with_field({{"valve", {{"constriction", "30x"}}},
                            {"continuum", {{"yield_stress", pairs({{"100 mT", tau}, {"300 mT", tau}})}}}});
            const Result r = run_mode(dir, "jam", name, scene, "--fidelity continuum");
            CAPTURE(r.err);
            REQUIRE(r.exit_code == 0);
            return json::parse(slurp(dir.file(name + "_report.json")))["results"];
        };
        const json one = plug("one", "1 kPa"), two = plug("two", "2 kPa");
        const double hold = one["continuum"]["hold_pressure_Pa"].get<double>();
        CHECK(two["continuum"]["hold_pressure_Pa"].get<double>() == rel(2 * hold));
        // Supply 105 kPa: a yield stress that makes the plug hold 10 % more closes the valve, 10 % less does not.
        const double closing = 105e3 / hold * 1e3;  // Pa of yield stress at which the plug holds the supply
        const json above = plug("above", format_number(1.1 * closing, 6) + " Pa");
        const json below = plug("below", format_number(0.9 * closing, 6) + " Pa");
        CHECK(above["outcome"] == "success");  // tau_y(0) = 0: the plug lets go with the field off
        CHECK(above["hold"]["gave_way_at_pressure_Pa"].get<double>() == rel(1.1 * 105e3).epsilon(1e-5));
        CHECK(below["outcome"] == "fail-no-jam");
        // The tier has no grains, and needs the fluid's yield stress, once.
        expect_mode_refused(dir, "jam", "no_table", with_field({{"valve", {{"constriction", "30x"}}}}), "/continuum",
                            "--fidelity continuum");
        expect_mode_refused(
            dir, "jam", "two_tables",
            with_field({{"continuum", {{"yield_stress", pairs({{"0.1 T", "1 kPa"}})}, {"shear_report", "x.json"}}}}),
            "/continuum/", "--fidelity continuum");
        expect_mode_refused(
            dir, "jam", "descending",
            with_field({{"continuum", {{"yield_stress", pairs({{"0.2 T", "1 kPa"}, {"0.1 T", "2 kPa"}})}}}}),
            "/continuum/yield_stress/1/0", "--fidelity continuum");
        expect_mode_refused(dir, "jam", "seeded",
                            with_field({{"continuum", {{"yield_stress", pairs({{"0.1 T", "1 kPa"}})}}}}), "--seeds",
                            "--fidelity continuum --seeds 3");
    }

    TEST_CASE("every mode: a report path that cannot be written is refused before any work") {
        TempDir dir;
        // Scenes with a typo that is never reached: the report is checked first.
        write_text(dir.file("jam.json"), json{{"protocol", {{"max_tme", "1 ms"}}}}.dump());
        write_text(dir.file("design.json"), json{{"jam", {{"protocol", {{"max_tme", "1 ms"}}}}}}.dump());
        for (const char* mode : {"run", "shear", "magnetics"})
            write_text(dir.file(std::string(mode) + ".json"), json{{"bogus", 1}}.dump());
        std::filesystem::create_directories(dir.file("a_directory"));
        write_text(dir.file("a_file"), "x");
        // The magnetics field map is a file written after the solve too.
        for (const std::string& map : {dir.file("a_directory"), dir.file("a_file") + "/map.txt", std::string("")}) {
            const Result r =
                mrjam_test::mrjam(dir, "magnetics " + quote(dir.file("magnetics.json")) + " --field-map " + quote(map));
            CHECK(r.exit_code == 2);
            CHECK(r.err.find("--field-map") != std::string::npos);
        }
        for (const std::string mode : {"jam", "design", "run", "shear", "magnetics"})
            for (const std::string& report :
                 {dir.file("a_directory"), std::string(""), dir.file("a_file") + "/r.json"}) {
                CAPTURE(mode);
                CAPTURE(report);
                const Result r =
                    mrjam_test::mrjam(dir, mode + " " + quote(dir.file(mode + ".json")) + " --report " + quote(report));
                CHECK(r.exit_code == 2);
                CHECK(r.err.find("--report") != std::string::npos);
            }
        // A report written over the command's own scene would lose it.
        write_text(dir.file("self.json"), json{{"protocol", {{"max_time", "1 ms"}}}}.dump());
        for (const std::string mode : {"jam", "design", "run", "shear", "magnetics"}) {
            CAPTURE(mode);
            const Result r = mrjam_test::mrjam(
                dir, mode + " " + quote(dir.file("self.json")) + " --report " + quote(dir.file("./self.json")));
            CHECK(r.exit_code == 2);
            CHECK(r.err.find("--report") != std::string::npos);
            CHECK(slurp(dir.file("self.json")).find("max_time") != std::string::npos);
        }
        // A number no double holds is bad input, named by its file.
        write_text(dir.file("huge.json"), R"({"protocol": {"max_time": 1e999}})");
        const Result huge =
            mrjam_test::mrjam(dir, "jam " + quote(dir.file("huge.json")) + " --report " + quote(dir.file("h.json")));
        CHECK(huge.exit_code == 2);
        CHECK(huge.err.find("huge.json") != std::string::npos);
    }

    TEST_CASE("jam scene: the converging jet is the taper mirrored where it fits, shortened to fit before the seam") {
        const json scene = {{"valve", {{"constriction", "30x"}}}, {"fluid", {{"profile", "converging"}}}};
        // Standard tier: 0.75 mm downstream, exit at 0.1 mm, cells 88 um: 0.474 mm of room < 0.8 mm taper.
        const JamScene standard = read_jam_scene(with_field(scene), "standard", ".");
        CHECK(standard.flow.jet_length == rel(0.75e-3 - 0.1e-3 - 2 * 88e-6));
        // A long enough tube gets the mirror image of the taper.
        json longer = scene;
        longer["model"] = {{"downstream_length", "1.5 mm"}};
        CHECK(read_jam_scene(with_field(longer), "standard", ".").flow.jet_length == rel(0.8e-3));
        CHECK(read_jam_scene(with_field(longer), "standard", ".")
                  .engine_scene["fluid"]["flow"]["jet_length"]
                  .get<double>() == rel(0.8e-3));
    }

    // A lone sphere of permeability mu_r magnetises to M = 3 beta H0, beta = (mu_r - 1)/(mu_r + 2), and
    // saturates at M_s: B0 = mu0 M_s / (3 beta) = 0.7142 T for iron (mu_r 1000, M_s 1.7e6 A/m).
    TEST_CASE("jam scene: the field at which a lone grain saturates, and the warning above it") {
        const json scene = {{"valve", {{"constriction", "30x"}}}};
        const JamScene iron = read_jam_scene(with_field(scene), "quick", ".");
        const double beta = 999.0 / 1002.0;
        CHECK(iron.lone_grain_saturation_flux_density == rel(1.25663706212e-6 * 1.7e6 / (3 * beta)).epsilon(1e-12));
        CHECK(iron.peak_flux_density == rel(0.230));
        CHECK(saturated_field_warning(iron).empty());
        json strong = scene;
        strong["field"] = {{"flux_density", "1 T"}};
        const std::string w = saturated_field_warning(read_jam_scene(with_field(strong), "quick", "."));
        CHECK(w.find("reaches 1 T at its strongest, above the 0.714 T") != std::string::npos);
        // A softer saturation lowers the knee in proportion: 0.85e6 A/m saturates at 0.357 T.
        json soft = scene;
        soft["material"] = {{"saturation_magnetisation", "0.85e6 A/m"}};
        CHECK(read_jam_scene(with_field(soft), "quick", ".").lone_grain_saturation_flux_density ==
              rel(0.5 * iron.lone_grain_saturation_flux_density).epsilon(1e-12));
        CHECK(read_jam_scene(with_field(soft), "quick", ".").engine_scene["materials"][0]["saturation_magnetisation"] ==
              rel(0.85e6));
    }

    TEST_CASE("jam scene: the neighbour skin reaches the engine scene, the engine's 0.1 by default") {
        const json scene = {{"valve", {{"constriction", "30x"}}}};
        CHECK(read_jam_scene(with_field(scene), "quick", ".").engine_scene["run"]["skin"].get<double>() ==
              rel(kDefaultSkinFraction));
        json wider = scene;
        wider["model"] = {{"neighbour_skin", 0.25}};
        CHECK(read_jam_scene(with_field(wider), "quick", ".").engine_scene["run"]["skin"].get<double>() == rel(0.25));
    }

    TEST_CASE(
        "jam scene: the quick and standard tiers hold the carrier-flow lookups 4 steps, the paper tier looks every "
        "step") {
        const json scene = {{"valve", {{"constriction", "30x"}}}};
        auto lookup_interval = [](const json& engine) { return engine["fluid"].value("lookup_interval", 1); };
        CHECK(lookup_interval(read_jam_scene(with_field(scene), "quick", ".").engine_scene) == 4);
        CHECK(lookup_interval(read_jam_scene(with_field(scene), "standard", ".").engine_scene) == 4);
        CHECK(lookup_interval(read_jam_scene(with_field(scene), "paper", ".").engine_scene) == 1);
        // The magnetic forces alike (docs/notes/jam_speed.md measures the standard tier's).
        auto magnetic_interval = [](const json& engine) { return engine["magnetic"].value("update_interval", 1); };
        CHECK(magnetic_interval(read_jam_scene(with_field(scene), "quick", ".").engine_scene) == 4);
        CHECK(magnetic_interval(read_jam_scene(with_field(scene), "standard", ".").engine_scene) == 4);
        CHECK(magnetic_interval(read_jam_scene(with_field(scene), "paper", ".").engine_scene) == 1);
        json every_step = scene;
        every_step["model"] = {{"flow_lookup_interval", 1}};
        CHECK(lookup_interval(read_jam_scene(with_field(every_step), "quick", ".").engine_scene) == 1);
    }

    TEST_CASE("jam scene: the close-pair correction is off unless the model asks for it, and reaches the engine") {
        const json scene = {{"valve", {{"constriction", "30x"}}}};
        CHECK_FALSE(read_jam_scene(with_field(scene), "quick", ".").engine_scene["magnetic"].contains("close_pairs"));
        json corrected = scene;
        corrected["model"] = {{"close_pairs_min_gap", 0.1}};
        const json engine = read_jam_scene(with_field(corrected), "quick", ".").engine_scene;
        CHECK(engine["magnetic"]["close_pairs"]["min_gap"].get<double>() == rel(0.1));
        CHECK(engine["magnetic"]["close_pairs"]["model"] == "linear");
        json saturating = scene;
        saturating["model"] = {{"close_pairs", "saturating"}};
        CHECK(read_jam_scene(with_field(saturating), "quick", ".").engine_scene["magnetic"]["close_pairs"]["model"] ==
              "saturating");
        saturating["model"]["close_pairs_min_gap"] = 0.1;
        CHECK_THROWS_WITH_AS(read_jam_scene(with_field(saturating), "quick", "."),
                             doctest::Contains("/model/close_pairs_min_gap"), SceneError);
    }

    TEST_CASE(
        "jam scene: every bundled valve example, and every design example's jam block, is accepted at every tier") {
        std::vector<std::string> names = {"valve_mix2_20x",        "valve_mix2_30x", "valve_mix2_40x",
                                          "valve_mix2_slot",       "valve_10um_30x", "valve_10um_30x_quick",
                                          "valve_mix2_30x_table21"};
        for (const char* mix : {"mix1", "mix2", "mix3", "mix4"})  // Table 3.2's matrix, in the curved field
            for (const char* constriction : {"20x", "30x", "40x"})
                names.push_back(std::string("table32/") + mix + "_" + constriction);
        for (const char* hold : {"hold_mix2_20x", "hold_mix2_30x", "hold_mix3_20x", "hold_mix3_30x"})
            names.push_back(std::string("table32/") + hold);
        for (const std::string& name : names)
            for (const std::string& tier : jam_tier_names()) {
                CAPTURE(name);
                CAPTURE(tier);
                const std::string path = std::string(MRJAM_SOURCE_DIR) + "/examples/" + name + ".json";
                const std::string dir = std::filesystem::path(path).parent_path().string();
                const json scene = json::parse(slurp(path));
                CHECK(scene.contains("field"));  // bundled scenes name their field
                // The continuum tier needs the fluid's yield stress, which only some scenes give.
                if (tier == "continuum" && !scene.contains("continuum"))
                    CHECK_THROWS_AS(read_jam_scene(scene, tier, dir), SceneError);
                else
                    CHECK_NOTHROW(read_jam_scene(scene, tier, dir));
            }
        // The design examples' jam blocks, as `mrjam design` checks them before its first field solve:
        // with each constriction's valve and a field (a uniform one stands in for the map to come).
        for (const char* name : {"design_quick", "design_curved", "design_rectangular", "design_insert"}) {
            const std::string dir = std::string(MRJAM_SOURCE_DIR) + "/examples";
            const json design = json::parse(slurp(dir + "/" + name + ".json"));
            for (const auto& constriction : design.at("constrictions"))
                for (const std::string tier : {"quick", "standard", "paper"}) {  // the design's tiers
                    CAPTURE(name);
                    CAPTURE(constriction);
                    CAPTURE(tier);
                    json scene = design.at("jam");
                    scene["valve"] = {{"constriction", constriction}};
                    scene["field"] = {{"type", "uniform"}, {"flux_density", "230 mT"}};
                    CHECK_NOTHROW(read_jam_scene(with_field(scene), tier, dir));
                }
        }
        // The fine grains' example runs the coupled flow with the taper's mirror as its jet.
        const json fine = json::parse(slurp(std::string(MRJAM_SOURCE_DIR) + "/examples/valve_10um_30x.json"));
        const JamScene js = read_jam_scene(with_field(fine), "quick", ".");
        CHECK(js.flow.coupled);
        CHECK(js.flow.jet_length == rel(js.valve.taper_length));
    }

    TEST_CASE("jam scene: the coupled flow's rings, wall gap and jet") {
        const json scene = {{"valve", {{"constriction", "30x"}}}, {"fluid", {{"flow", "coupled"}}}};
        const JamScene js = read_jam_scene(with_field(scene), "quick", ".");
        CHECK(js.flow.coupled);
        CHECK(js.flow.pressure_driven);
        // The 44 um table's volume-weighted mean radius: sum of d/2 x mass over the printed 122 %.
        const double mean = 0.5 * (44 * 44 + 38.9 * 35 + 33.8 * 24.2 + 28.7 * 13.2 + 23.6 * 5.6) / 122.0 * 1e-6;
        CHECK(js.flow.wall_gap == rel(mean));
        // Rings: one largest grain (44 um) wide in the 0.66 mm throat, 15, within the 18 allowed.
        CHECK(js.flow.rings == 15);
        // The jet: the taper mirrored, the quick tier's 0.5 mm of tube past the throat centre
        // lengthened to hold it and two 88 um cells (exit at 0.1 mm), and the report says so.
        CHECK(js.flow.jet_length == rel(0.8e-3));
        CHECK(js.valve.downstream_length == rel(0.1e-3 + 0.8e-3 + 2 * 88e-6));
        CHECK(js.resolved["model"]["downstream_length"].get<double>() == rel(js.valve.downstream_length));
        // A tube length the scene fixes is kept, and the jet is what fits in it.
        json fixed = scene;
        fixed["model"] = {{"downstream_length", "0.5 mm"}};
        const JamScene fixed_tube = read_jam_scene(with_field(fixed), "quick", ".");
        CHECK(fixed_tube.valve.downstream_length == rel(0.5e-3));
        CHECK(fixed_tube.flow.jet_length == rel(0.5e-3 - 0.1e-3 - 2 * 88e-6));
    }

    TEST_CASE(
        "jam scene: the slab's faces are frictionless or frictional as asked; the valve's wall keeps its friction") {
        auto built = [](const std::string& faces) {
            const json scene = {{"valve", {{"constriction", "30x"}}}, {"model", {{"slab_faces", faces}}}};
            BuildOptions build;
            build.fidelity = "quick";
            build.insert_grains = false;
            return build_scene(read_jam_scene(with_field(scene), "quick", ".").engine_scene, build);
        };
        auto wall = [](const System& s, const std::string& name) {
            for (const Wall& w : s.walls)
                if (w.name == name) return w;
            FAIL("no wall " << name);
            return Wall{};
        };
        const Scene smooth = built("frictionless");
        const System& s = smooth.system;
        for (const char* face : {"slab_low", "slab_high"}) {
            CAPTURE(face);
            CHECK(s.pairs(0, wall(s, face).material).friction == 0.0);
            CHECK(s.pairs(0, wall(s, face).material).rolling_friction == 0.0);
            // The face is the same iron in every other respect (stiffness, damping).
            CHECK(s.pairs(0, wall(s, face).material).effective_youngs == rel(s.pairs(0, 0).effective_youngs));
        }
        CHECK(s.pairs(0, 0).friction == rel(0.4));
        CHECK(s.pairs(0, wall(s, "valve").material).friction == rel(0.4));
        const Scene rough = built("frictional");
        CHECK(rough.system.pairs(0, wall(rough.system, "slab_low").material).friction == rel(0.4));
    }

    TEST_CASE("jam scene: model/heavier_below gives finer grains its Stokes and Rayleigh times, the quick tier all") {
        auto built = [](const json& model) {
            const json scene = {{"valve", {{"constriction", "30x"}}}, {"model", model}};
            BuildOptions build;
            build.fidelity = "quick";
            Scene s = build_scene(read_jam_scene(with_field(scene), "quick", ".").engine_scene, build);
            choose_timestep(s);
            return s;
        };
        const Scene plain = built({{"heavier_below", "0 um"}});
        const Scene heavy = built({{"heavier_below", "44 um"}});
        // The quick tier's default: every grain the largest one's Stokes time.
        const Scene tier_default = built(json::object());
        CHECK(tier_default.system.dt == heavy.system.dt);
        const json quick_model = {{"valve", {{"constriction", "30x"}}}};
        CHECK(read_jam_scene(with_field(quick_model), "quick", ".").resolved["model"]["heavier_below"].get<double>() ==
              rel(44e-6));
        CHECK(read_jam_scene(with_field(quick_model), "standard", ".").resolved["model"]["heavier_below"] == 0.0);
        const Particles& p = heavy.system.particles;
        REQUIRE(p.size() == plain.system.particles.size());
        const double density = heavy.system.materials[0].density;
        int scaled = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const double d = 2 * p.radius[i], natural = density * M_PI / 6 * d * d * d;
            const double expected = d < 44e-6 ? 44e-6 * 44e-6 / (d * d) : 1.0;
            CHECK(p.mass[i] / natural == rel(expected).epsilon(1e-9));
            scaled += d < 44e-6;
        }
        CHECK(scaled > 0);
        CHECK(scaled < static_cast<int>(p.size()));  // the 44 um class keeps its mass
        // Rayleigh-limited in both: every grain now has a 44 um grain's R sqrt(rho / G), where the
        // 23.6 um class set it before.
        REQUIRE(plain.limits.limiting == "Rayleigh time of the smallest grain");
        REQUIRE(heavy.limits.limiting == plain.limits.limiting);
        CHECK(heavy.system.dt / plain.system.dt == rel(44.0 / 23.6).epsilon(1e-9));
    }

    TEST_CASE(
        "jam scene: rolling resistance and cohesion switch on only when the material asks; the slab faces carry "
        "neither") {
        auto built = [](const json& material) {
            const json scene = {{"valve", {{"constriction", "30x"}}}, {"material", material}};
            BuildOptions build;
            build.fidelity = "quick";
            build.insert_grains = false;
            return build_scene(read_jam_scene(with_field(scene), "quick", ".").engine_scene, build);
        };
        const Scene bare = built(json::object());
        CHECK(bare.system.physics.rolling == RollingModel::none);
        CHECK(bare.system.physics.cohesion == CohesionModel::none);
        // Table 2.1's MRF suite (the bundled examples/valve_mix2_30x_table21.json).
        const Scene suite =
            built({{"rolling_friction", 0.1}, {"rolling_damping", 0.1}, {"cohesion_energy_density", "60 kJ/m3"}});
        const System& s = suite.system;
        CHECK(s.physics.rolling == RollingModel::epsd);
        CHECK(s.physics.cohesion == CohesionModel::sjkr);
        CHECK(s.pairs(0, 0).rolling_friction == rel(0.1));
        CHECK(s.pairs(0, 0).cohesion_energy_density == rel(6e4));
        for (const Wall& w : s.walls) {
            CAPTURE(w.name);
            // A symmetry plane neither sticks nor resists rolling; the valve's own wall does both.
            const bool face = w.name == "slab_low" || w.name == "slab_high";
            CHECK(s.pairs(0, w.material).cohesion_energy_density == (face ? 0.0 : rel(6e4)));
            CHECK(s.pairs(0, w.material).rolling_friction == (face ? 0.0 : rel(0.1)));
        }
        TempDir dir;
        expect_mode_refused(dir, "jam", "negative_rolling", with_field({{"material", {{"rolling_friction", -0.1}}}}),
                            "/material/rolling_friction");
        expect_mode_refused(dir, "jam", "damping_alone", with_field({{"material", {{"rolling_damping", 0.1}}}}),
                            "/material/rolling_damping");
        expect_mode_refused(dir, "jam", "negative_cohesion",
                            with_field({{"material", {{"cohesion_energy_density", "-1 kJ/m3"}}}}),
                            "/material/cohesion_energy_density");
    }

    TEST_CASE("jam scene: the stretch starts at the mix's volume fraction, the taper included") {
        // The quick 40x slab: grain volume over the slab's fluid volume (the resistance cells' sum,
        // exact for the cone) must be the feed fraction, less what the random packer's boxes cannot
        // reach: the taper staircase's wedges (~5 % of the taper, ~2 % of the stretch) and the
        // centre-free layer a grain radius deep at each slice face. Before the taper was filled the
        // stretch held 0.28 of 0.345 (81 %). So too a stepped orifice (no taper) and a sharp-edged one
        // (no throat), whose empty slices once reached the packer as regions of zero length.
        for (const json& valve :
             {json{{"constriction", "40x"}}, json{{"constriction", "40x"}, {"taper_length", "0 mm"}},
              json{{"constriction", "40x"}, {"throat_length", "0 mm"}}}) {
            CAPTURE(valve.dump());
            const json scene = {{"valve", valve}, {"grains", {{"psd", "44um"}, {"volume_fraction", 0.345}}}};
            const JamScene js = read_jam_scene(with_field(scene), "quick", ".");
            BuildOptions build;
            build.fidelity = "quick";
            const Scene built = build_scene(js.engine_scene, build);
            double grains = 0;
            for (double r : built.system.particles.radius) grains += 4.0 / 3.0 * M_PI * r * r * r;
            const AxialResistance cells(js.valve, js.slab_half_thickness, -js.valve.upstream_length,
                                        js.valve.downstream_length, js.flow.cell_length, js.feed_fraction, 1e5);
            double fluid = 0;
            for (std::size_t k = 0; k < cells.cells(); ++k) fluid += cells.cell_volume(k);
            const double phi = grains / fluid;
            CHECK(phi < 0.345);
            CHECK(phi > 0.93 * 0.345);
        }
    }

    TEST_CASE("jam: a short run reports the outcome keys, a flux history and a throat picture") {
        TempDir dir;
        const json scene = {{"valve", {{"constriction", "30x"}}},
                            {"model", short_tube()},
                            {"protocol", brief_protocol()},
                            {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "jam", with_field(scene), "--fidelity quick");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("jam_report.json")));
        const json& res = report["results"];
        for (const char* key : {"jammed", "time_to_arrest_s", "grains_passed_before_arrest", "released", "outcome",
                                "largest_cluster", "largest_cluster_spans_throat", "flux_history", "jam_probability"}) {
            CAPTURE(key);
            CHECK(res.contains(key));
        }
        CHECK(res["grains"].get<long>() > 100);
        CHECK(res["flux_history"]["rows"].size() > 2);
        CHECK(std::filesystem::exists(dir.file("jam_report_throat.png")));
        CHECK(report["fidelity"]["jam_tier"] == "quick");
        // The quick tier holds the magnetic forces 4 steps: the engine did what the report says.
        CHECK(report["fidelity"]["magnetic_update_interval"] == 4);
        CHECK(res["magnetic"]["update_interval_steps"] == 4);
        CHECK(res["magnetic"]["steps_with_held_forces"].get<long>() > 0);
        // It holds the carrier-flow lookups 4 steps too.
        CHECK(report["fidelity"]["flow_lookup_interval"] == 4);
        CHECK(res["carrier_flow"]["lookup_interval_steps"] == 4);
        CHECK(res["carrier_flow"]["steps_with_held_lookups"].get<long>() > 0);
        // The magnet is off during the no-field flow: the force evaluations there (one per step,
        // give or take the first before them and the last, at the switch-on time) skip the
        // magnetic pass; none does once it is on (no arrest here, so it stays on).
        const json& stages = res["stages"];
        REQUIRE(stages.size() >= 2);
        REQUIRE(stages[0]["name"] == "flow");
        const long flow_steps = stages[0]["steps"],
                   off_in_flow = stages[0]["state"]["magnetic"]["steps_with_magnet_off"];
        CHECK(off_in_flow >= flow_steps - 1);
        CHECK(off_in_flow <= flow_steps + 1);
        CHECK(res["jammed"] == false);
        CHECK(res["field_period_ended_by"] == "max_time");
        CHECK(res["magnetic"]["steps_with_magnet_off"].get<long>() == off_in_flow);
        CHECK(res["magnetic"]["mean_moment_A_m2"].get<double>() > 0.0);
    }

    // A finite batch (model/supply "batch"): grains reaching the outlet are taken out and none come
    // in, so the grains upstream of the throat plane fall by exactly the net number that crossed it
    // (both counted at the same observations), and the ones taken out are gone from the count.
    TEST_CASE("jam: a finite batch drains through the outlet, conserving the grains it counts") {
        TempDir dir;
        json scene = {{"valve", {{"constriction", "30x"}}},
                      {"model", short_tube({{"downstream_length", "0.5 mm"}, {"supply", "batch"}})},
                      {"field", {{"flux_density", "0 mT"}}},
                      {"protocol", {{"flow_time", "0.15 ms"}, {"max_time", "0.05 ms"}, {"arrest_window", "0.02 ms"}}},
                      {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "batch", with_field(scene), "--fidelity quick");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("batch_report.json")));
        const json& res = report["results"];
        const json& b = res["batch"];
        CAPTURE(b.dump());
        CHECK(res["supply"].get<std::string>().find("finite batch") != std::string::npos);
        CHECK(b["grains_left"].get<long>() == res["grains"].get<long>());  // the engine's own count at the end
        CHECK(b["grains_drained"].get<long>() > 0);
        CHECK(b["grains_left"].get<long>() == b["grains_at_start"].get<long>() - b["grains_drained"].get<long>());
        CHECK(res["grains_passed_total"].get<long>() > 0);
        CHECK(b["upstream_of_throat_centre_at_start"].get<long>() - b["upstream_of_throat_centre_at_end"].get<long>() ==
              res["grains_passed_total"].get<long>());
        CHECK(b["outlet_z_m"].get<double>() > 0.1e-3);  // past the throat's exit (0.1 mm)
        // The performance figures count the grains each step really moved: fewer than all steps
        // at the starting count, more than all at the final one.
        const double grain_steps =
            report["performance"]["grain_steps_per_s"].get<double>() * report["wall_time_s"].get<double>();
        const double steps = report["performance"]["steps_run"].get<double>();
        CHECK(grain_steps < 0.999 * steps * b["grains_at_start"].get<double>());
        CHECK(grain_steps > 1.001 * steps * b["grains_left"].get<double>());

        // An outlet with no room past the throat is refused, naming the key to lengthen.
        scene["model"]["downstream_length"] = "0.2 mm";
        const Result no_room = run_mode(dir, "jam", "short", with_field(scene), "--fidelity quick");
        CHECK(no_room.exit_code == 2);
        CHECK(no_room.err.find("/model/downstream_length") != std::string::npos);
    }

    // "Until arrest or steady flow": with protocol/steady_window the field period ends as soon as
    // two windows of flux agree. A tolerance of 0.99 calls any two windows with grains through
    // steady, so without a field the period must end after two windows, well before max_time. The
    // no-field flow through 30x comes in bursts (0.04 ms with no grain through is seen): the flow
    // time leaves the start-up flush behind, and the arrest test (1 % of the flux for 0.06 ms)
    // cannot mistake a pause for an arrest.
    TEST_CASE("jam: a steady flow ends the field period before max_time") {
        TempDir dir;
        const json scene = {{"valve", {{"constriction", "30x"}}},
                            {"model", short_tube()},
                            {"field", {{"flux_density", "0 mT"}}},
                            {"protocol",
                             {{"order", "open_first"},
                              {"flow_time", "0.3 ms"},
                              {"max_time", "0.5 ms"},
                              {"arrest_window", "0.06 ms"},
                              {"arrest_fraction", 0.01},
                              {"steady_window", "0.03 ms"},
                              {"steady_tolerance", 0.99}}},
                            {"output", {{"directory", dir.file("out")}}}};
        const Result r = run_mode(dir, "jam", "steady", with_field(scene), "--fidelity quick");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("steady_report.json")));
        const json& res = report["results"];
        CHECK(res["field_period_ended_by"] == "steady flow");
        CHECK(report["warnings"].dump().find("steady_window 0") != std::string::npos);
        CHECK(res["outcome"] == "fail-no-jam");
        const json& field_on = res["stages"][1];
        REQUIRE(field_on["name"] == "field_on");
        // The first test after the arrest window (0.06 ms, two steady windows), at most one
        // observation later, against 0.5 ms of max_time.
        CHECK(field_on["ended_early"] == true);
        CHECK(field_on["end_time_s"].get<double>() < 0.3e-3 + 0.08e-3);
        // The performance figures count the steps really run, not those the early end skipped.
        long stepped = 0;
        for (const auto& stage : res["stages"]) stepped += stage["steps"].get<long>();
        CHECK(report["performance"]["steps_run"].get<long>() == stepped);
    }

}  // TEST_SUITE

TEST_SUITE("cli") {
    // The design chain end to end on one constriction with a coarse field mesh and a short run:
    // the field map written for the constriction must drive the jam run, and the report must name
    // the jam probability and the open-state flow estimate.
    // Ctrl-C in a terminal reaches the whole process group, GetDP included, while mrjam waits on it:
    // the design still ends as interrupted, exit 130, with its report written, rather than as a
    // solver failure (exit 1). (The signal to mrjam alone: tests/test_magnetics_cli.cpp.)
    TEST_CASE("design: Ctrl-C during the field solve is an interruption") {
        // GetDP is part of the tool (scripts/install-deps.sh installs it): its absence fails, not skips.
        REQUIRE_MESSAGE(!mrjam::magnetics::find_getdp().empty(), "getdp is not installed: run scripts/install-deps.sh");
        TempDir dir;
        const json design = {{"constrictions", {"30x"}}, {"output", {{"directory", dir.file("design")}}}};
        write_text(dir.file("design.json"), design.dump());
        // GetDP is mrjam's child: signal both, as a terminal would.
        const std::string signal_group =
            " & pid=$!; g=; for i in $(seq 1 600); do g=$(pgrep -P $pid -x getdp);"
            " [ -n \"$g\" ] && break; sleep 0.05; done; kill -INT $pid $g; wait $pid";
        const Result r = mrjam_test::mrjam(dir,
                                           "design " + quote(dir.file("design.json")) + " --report " +
                                               quote(dir.file("report.json")) + " --fidelity quick --quiet",
                                           signal_group);
        CAPTURE(r.err);
        CHECK(r.exit_code == 130);
        const json report = json::parse(slurp(dir.file("report.json")));
        CHECK(report["status"] == "interrupted");
        CHECK(report["stopped"]["stage"] == "field solve");
    }

    TEST_CASE("design: magnetics -> field map -> jam predictor -> report") {
        // GetDP is part of the tool (scripts/install-deps.sh installs it): its absence fails, not skips.
        REQUIRE_MESSAGE(!mrjam::magnetics::find_getdp().empty(), "getdp is not installed: run scripts/install-deps.sh");
        TempDir dir;
        const json design = brief_design(dir.file("design"));
        write_text(dir.file("design.json"), design.dump());
        const Result r =
            mrjam_test::mrjam(dir, "design " + quote(dir.file("design.json")) + " --report " +
                                       quote(dir.file("design_report.json")) + " --fidelity quick --quiet");
        CAPTURE(r.err);
        REQUIRE(r.exit_code == 0);
        const json report = json::parse(slurp(dir.file("design_report.json")));
        const json& row = report["results"]["constrictions"][0];
        CHECK(row["constriction"] == "30x");
        CHECK(row["mean_B_active_T"].get<double>() > 0.05);
        CHECK(row["jam_probability"].is_number());
        REQUIRE(row["jam_probability_95ci"].size() == 2);  // brackets the seeds' share
        CHECK(row["jam_probability_95ci"][0].get<double>() <= row["jam_probability"].get<double>());
        CHECK(row["jam_probability_95ci"][1].get<double>() >= row["jam_probability"].get<double>());
        CHECK(row["open_flow_rate_m3_s"].get<double>() > 0);
        CHECK(std::filesystem::exists(dir.file("design/30x/field.map")));
        // The solved field's picture, linked from the row and drawn in the summary figure (the
        // only constriction is the likeliest to jam, whether or not it did).
        REQUIRE(row.contains("field_picture"));
        CHECK(slurp(row["field_picture"].get<std::string>()).find("data:image/png;base64,") != std::string::npos);
        CHECK(std::filesystem::exists(mrjam::png_twin(row["field_picture"].get<std::string>())));
        REQUIRE(report.contains("summary_figure"));
        CHECK(report["summary_figure"]["field_of"] == "30x");
        const std::string summary = slurp(report["summary_figure"]["svg"].get<std::string>());
        CHECK(summary.find("Jam probability") != std::string::npos);
        CHECK(summary.find("data:image/png;base64,") != std::string::npos);
        CHECK(std::filesystem::file_size(report["summary_figure"]["png"].get<std::string>()) > 1000);
        CHECK(report["results"].contains("widest_reliable_constriction"));
        CHECK(report["status"] == "complete");
        CHECK(report["wall_time_s"].get<double>() > 0);
        // The map is the fluid's field interpolated from fluid vertex values, so on the axis it is
        // positive and never above the largest nodal value in the active fluid around the throat.
        const double throat_b = row["B_on_axis"]["throat_centre_T"].get<double>();
        CHECK(throat_b > 0);
        CHECK(throat_b <= row["max_B_active_T"].get<double>() * (1 + 1e-9));
        // The constriction's jam run keeps its own report beside the map, as `mrjam jam` writes it.
        const json jam = json::parse(slurp(dir.file("design/30x/jam_report.json")));
        CHECK(jam["results"]["outcome"] == row["runs"][0]["outcome"]);
        CHECK(jam["inputs_jam"]["field"]["type"] == "map");

        // A jam run that blows up (grains far too soft for the flow) stops the design with exit 3;
        // the design report is still written, says where it stopped, and points at the partial report.
        json soft = design;
        soft["jam"]["material"] = {{"youngs_modulus", "1 MPa"}};
        soft["jam"]["protocol"]["flow_time"] = "0.5 ms";
        soft["jam"]["protocol"]["observe_every_steps"] =
            1;  // the soft grains' long step still observes a window 4 times
        write_text(dir.file("soft.json"), soft.dump());
        const Result blown =
            mrjam_test::mrjam(dir, "design " + quote(dir.file("soft.json")) + " --report " +
                                       quote(dir.file("soft_report.json")) + " --fidelity quick --quiet");
        CAPTURE(blown.err);
        CHECK(blown.exit_code == 3);
        const json stopped = json::parse(slurp(dir.file("soft_report.json")));
        CHECK(stopped["status"] == "failed");
        CHECK(stopped["stopped"]["constriction"] == "30x");
        CHECK(stopped["results"]["constrictions"].empty());
        CHECK(std::filesystem::exists(stopped["stopped"]["jam_report"].get<std::string>()));

        write_text(dir.file("bad.json"), json{{"constrictions", {"30x"}}, {"magnet", json::object()}}.dump());
        const Result bad = mrjam_test::mrjam(dir, "design " + quote(dir.file("bad.json")) + " --quiet");
        CHECK(bad.exit_code == 2);
        CHECK(bad.err.find("/magnet") != std::string::npos);

        // Keys the design sets for each constriction itself are refused, not silently overwritten.
        for (const auto& [block, key, path] : std::vector<std::tuple<std::string, json, std::string>>{
                 {"jam", {{"field", {{"type", "uniform"}, {"flux_density", "500 mT"}}}}, "/jam/field"},
                 {"jam", {{"valve", {{"orifice", "slot"}}}}, "/jam/valve"},
                 {"jam", {{"output", {{"directory", "elsewhere"}}}}, "/jam/output"},
                 {"magnetics", {{"state", "off"}}, "/magnetics/state"},
                 {"magnetics", {{"valve", {{"constriction", "40x"}}}}, "/magnetics/valve/constriction"}}) {
            json overridden = design;
            overridden[block].update(key);
            write_text(dir.file("overridden.json"), overridden.dump());
            const Result refused = mrjam_test::mrjam(dir, "design " + quote(dir.file("overridden.json")) + " --quiet");
            CAPTURE(path);
            CAPTURE(refused.err);
            CHECK(refused.exit_code == 2);
            CHECK(refused.err.find(path) != std::string::npos);
        }
        // A block's errors are named from the design file's root, a constriction's by its list entry,
        // and a block that is not an object is bad input too.
        for (const auto& [change, path] : std::vector<std::pair<json, std::string>>{
                 {{{"jam", {{"protocol", {{"arrest_fraction", 0}}}}}}, "/jam/protocol/arrest_fraction"},
                 {{{"magnetics", {{"bogus", 1}}}}, "/magnetics/bogus"},
                 {{{"constrictions", {"30x", "3 mm"}}}, "/constrictions/1"},
                 // Each constriction runs under its own name: a repeat overwrote the first's files.
                 {{{"constrictions", {"30x", "30x"}}}, "/constrictions/1"},
                 // Found before the field solve (they stopped the design after it, or wrapped a seed).
                 {{{"jam", {{"model", {{"upstream_length", "10 mm"}}}}}}, "/jam/model/upstream_length"},
                 {{{"jam", {{"seed", std::numeric_limits<long long>::max()}}}, {"seeds", 2}}, "/jam/seed"},
                 // Past a long long it wrapped to -1 and the message quoted a seed nobody wrote.
                 {{{"jam", {{"seed", std::numeric_limits<std::uint64_t>::max()}}}},
                  "/jam/seed: value 18446744073709551615 is"},
                 {{{"magnetics", {{"model", "circuit"}}}}, "/magnetics/model"},
                 {{{"jam", 5}}, "/jam"},
                 {{{"magnetics", {{"valve", 5}}}}, "/magnetics/valve"},
                 // The key of earlier versions, refused with the one that replaced it.
                 {{{"output_directory", "out/x"}}, "/output_directory"},
                 {{{"output", {{"directory", ""}}}}, "/output/directory"},
                 // The jam runs' checkpoints are where --resume looks for them.
                 {{{"output", {{"checkpoint", {{"path", "x.mrjam"}}}}}}, "/output/checkpoint/path"},
                 {{{"output", {{"snapshots", {{"format", "obj"}}}}}}, "/output/snapshots/format"}}) {
            json changed = design;
            changed.update(change);
            write_text(dir.file("changed.json"), changed.dump());
            const Result refused = mrjam_test::mrjam(dir, "design " + quote(dir.file("changed.json")) + " --quiet");
            CAPTURE(path);
            CAPTURE(refused.err);
            CHECK(refused.exit_code == 2);
            // A path, then its message; or (ending " is") the start of the message itself.
            CHECK(refused.err.find("error in scene: " + path + (path.ends_with(" is") ? " " : ":")) !=
                  std::string::npos);
        }
    }

    // An interrupted design resumes where it stopped and ends as the uninterrupted design: two seeds
    // on one constriction, Ctrl-C about half-way through the second seed (the field solve, about a
    // second, and the first seed before it), so the second seed resumes from its checkpoint after the
    // first seed's record is read back from the design's progress; a signal that lands in the first
    // seed or in the meshing is resumed just as well (a signal during GetDP's solve is ignored by
    // mrjam, which waits on it: then the design finishes, and the signal is tried again earlier).
    TEST_CASE("design --resume: an interrupted design ends as the uninterrupted one") {
        // GetDP is part of the tool (scripts/install-deps.sh installs it): its absence fails, not skips.
        REQUIRE_MESSAGE(!mrjam::magnetics::find_getdp().empty(), "getdp is not installed: run scripts/install-deps.sh");
        TempDir dir;
        auto design_in = [&](const std::string& out) {
            json design = brief_design(dir.file(out));
            design["seeds"] = 2;
            return design;
        };
        write_text(dir.file("full.json"), design_in("full").dump());
        const Result full =
            mrjam_test::mrjam(dir, "design " + quote(dir.file("full.json")) + " --report " +
                                       quote(dir.file("full_report.json")) + " --fidelity quick --quiet");
        CAPTURE(full.err);
        REQUIRE(full.exit_code == 0);
        const json a = json::parse(slurp(dir.file("full_report.json")));
        // Nothing to resume in a directory without a design in progress, and a design resumed with
        // another tier or after its file changed would not be the design that was started.
        write_text(dir.file("cut.json"), design_in("cut").dump());
        const Result nothing = mrjam_test::mrjam(dir, "design " + quote(dir.file("cut.json")) + " --resume --quiet");
        CHECK(nothing.exit_code == 2);
        CHECK(nothing.err.find("--resume") != std::string::npos);

        const double jam_seed_s =
            json::parse(slurp(dir.file("full/30x/jam_report_seed2.json")))["wall_time_s"].get<double>();
        const double delay = std::max(0.1, a["wall_time_s"].get<double>() - 0.5 * jam_seed_s);
        // A signal during GetDP's solve is ignored (the design finishes): tried again earlier.
        const Result cut = mrjam_test::mrjam_interrupted(
            dir,
            "design " + quote(dir.file("cut.json")) + " --report " + quote(dir.file("cut_report.json")) +
                " --fidelity quick --quiet",
            delay, [&](const Result&) { return std::filesystem::exists(dir.file("cut_report.json")); });
        CAPTURE(cut.err);
        REQUIRE(cut.exit_code == 130);
        const json c = json::parse(slurp(dir.file("cut_report.json")));
        CHECK(c["status"] == "interrupted");
        CHECK(c["resume_with"].get<std::string>().find("--resume") != std::string::npos);
        MESSAGE("interrupted at the " << c["stopped"]["stage"].get<std::string>() << ", seed "
                                      << c["stopped"].value("seed", -1));

        json changed = design_in("cut");
        changed["seeds"] = 3;
        write_text(dir.file("changed.json"), changed.dump());
        const Result refused =
            mrjam_test::mrjam(dir, "design " + quote(dir.file("changed.json")) + " --resume --quiet");
        CHECK(refused.exit_code == 2);
        CHECK(refused.err.find("changed") != std::string::npos);
        const Result other_tier =
            mrjam_test::mrjam(dir, "design " + quote(dir.file("cut.json")) + " --resume --fidelity standard --quiet");
        CHECK(other_tier.exit_code == 2);
        CHECK(other_tier.err.find("--fidelity") != std::string::npos);

        const Result resumed = mrjam_test::mrjam(dir, "design " + quote(dir.file("cut.json")) + " --report " +
                                                          quote(dir.file("resumed_report.json")) + " --resume --quiet");
        CAPTURE(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        const json b = json::parse(slurp(dir.file("resumed_report.json")));
        CHECK(b["status"] == "complete");
        CHECK(b["resumed"] == true);
        CHECK(b["fidelity"] == a["fidelity"]);
        // Everything but where the files went: the field, every seed's outcome, flux shares and
        // times, the open flow; bit for bit, as one thread sums in the same order.
        auto results = [](json report, const std::string& out) {
            json rows = report["results"]["constrictions"];
            for (auto& row : rows) {
                for (const char* file : {"field_map", "field_picture", "throat_picture"}) {
                    CHECK(row[file].get<std::string>().find(out) != std::string::npos);
                    row.erase(file);
                }
                for (auto& run : row["runs"]) run.erase("jam_report");
            }
            return rows;
        };
        CHECK(results(b, "cut") == results(a, "full"));
        CHECK(b["results"]["widest_reliable_constriction"] == a["results"]["widest_reliable_constriction"]);
        // It continued the interrupted seed rather than running it again.
        if (c["stopped"]["stage"] == "jam run") {
            const std::string seed_report =
                std::filesystem::path(c["stopped"]["jam_report"].get<std::string>()).filename().string();
            const auto steps_run = [&](const std::string& out) {
                return json::parse(slurp(dir.file(out + "/30x/" + seed_report)))["performance"]["steps_run"]
                    .get<long>();
            };
            CHECK(steps_run("cut") < steps_run("full"));
        }
        // A finished seed leaves no checkpoint to be resumed by mistake.
        CHECK_FALSE(std::filesystem::exists(dir.file("cut/30x/jam/checkpoint.mrjam")));
        // A damaged progress record is bad input to --resume, not a JSON library's exception.
        write_text(dir.file("cut/design_progress.json"), "{\"format\": \"mrjam design progress 2\", \"inputs\": 3}");
        const Result damaged = mrjam_test::mrjam(dir, "design " + quote(dir.file("cut.json")) + " --resume --quiet");
        CHECK(damaged.exit_code == 2);
        CHECK(damaged.err.find("damaged") != std::string::npos);
    }

}  // TEST_SUITE

TEST_CASE("jam: the closed period's viscosity share applies to the magnetisation at rest alone") {
    mrjam::JamProtocol p;
    p.order = mrjam::JamOrder::closed_first;
    p.magnetise_viscosity_share = 0.01;
    // Stages: the no-field reference, the magnetisation at rest, the pressure, the release.
    CHECK(mrjam::carrier_viscosity_share(p, 0) == 1.0);
    CHECK(mrjam::carrier_viscosity_share(p, 1) == 0.01);
    CHECK(mrjam::carrier_viscosity_share(p, 2) == 1.0);
    CHECK(mrjam::carrier_viscosity_share(p, 3) == 1.0);
    // Open first has no closed period: the carrier keeps its own viscosity throughout.
    p.order = mrjam::JamOrder::open_first;
    for (std::size_t stage = 0; stage < 3; ++stage) CHECK(mrjam::carrier_viscosity_share(p, stage) == 1.0);
}
