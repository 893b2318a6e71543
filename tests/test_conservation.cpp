// Conservation laws and whole-run behaviour, through the same path the CLI takes (a JSON scene,
// build_scene, choose_timestep, prepare, advance):
//  - an undamped, frictionless elastic gas keeps its total energy (kinetic + rotational + Hertz
//    elastic) and its linear momentum;
//  - one grain settling in a viscous fluid reaches the Stokes terminal velocity with buoyancy,
//    and a grain at rest in a Couette flow reaches the local fluid velocity;
//  - extreme scenes (1 um and 1 m grains, Young's moduli 1e5 and 2e11 Pa, a 30:1 size ratio,
//    volume fraction 0.6) either run with finite positions or are refused with a clear message;
//  - a requested step above the stable limit is refused at /run/timestep with the limit;
//  - the same scene, seed and thread count give bit-identical positions.
// Set MRJAM_TEST_VERBOSE=1 to print the measured figures.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "contact/restitution.hpp"
#include "integrator.hpp"
#include "observers.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/drag_term.hpp"
#include "timestep.hpp"

using mrjam_test::rel;

namespace {

using namespace mrjam;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

void report(const std::string& text) {
    if (std::getenv("MRJAM_TEST_VERBOSE")) MESSAGE(text);
}

std::string str(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

Scene build(const json& scene_json, int threads = 1) {
    BuildOptions options;
    options.threads = threads;
    Scene scene = build_scene(scene_json, options);
    choose_timestep(scene);
    return scene;
}

Vec3 momentum(const Particles& p) {
    Vec3 m{};
    for (std::size_t i = 0; i < p.size(); ++i) m += p.velocity[i] * p.mass[i];
    return m;
}

double momentum_scale(const Particles& p) {
    double s = 0;
    for (std::size_t i = 0; i < p.size(); ++i) s += p.mass[i] * norm(p.velocity[i]);
    return s;
}

bool all_finite(const Particles& p) {
    for (std::size_t i = 0; i < p.size(); ++i)
        if (!finite(p.position[i]) || !finite(p.velocity[i])) return false;
    return true;
}

// ---------------------------------------------------------------------------------------------
// Energy and momentum of an elastic gas.
//
// About 200 grains of 0.9 to 1.1 mm (soft glass, Y = 100 MPa) at volume fraction 0.35 in a
// periodic box, velocity components uniform in +-0.1 m/s, no damping (restitution 1), no
// friction, no drag, no gravity.
//
// Choice of step. The fastest possible impact is 2 sqrt(3) 0.1 = 0.35 m/s; the Hertz contact
// time of the two smallest grains at that speed, t_c = 45 us, is the shortest collision the gas
// can have. The step is t_c / 80 = 0.56 us, so every collision spans at least 80 steps. Velocity
// Verlet is symplectic and time reversible: within a collision its energy error is bounded by
// ~(dt / t_c)^2 of the collision's energy and is mostly handed back when the pair separates; the
// remainder left by each collision (the Hertz force has no smooth third derivative at first
// touch) accumulates as a random walk that falls steeply with the step, roughly as dt^3.
// Measured on this scene over 1e5 steps (final / largest relative drift):
//   t_c / 10: 2.4e-3 / 2.4e-3     t_c / 20: 1.7e-4 / 1.9e-4     t_c / 50: 1.9e-5 / 3.0e-5
//   t_c / 80: 4.5e-6 / 7.5e-6     t_c / 100: 1.7e-6 / 3.7e-6
// and at t_c / 80 with four other seeds 0.6e-6 to 3.4e-6 / 4.4e-6 to 9.8e-6: a tenfold margin
// under 1e-4. (Steps above 0.055 t_c, 0.2 of the Rayleigh time here, are refused by the engine;
// its automatic step, 0.1 of that time, is t_c / 37.)
// 1e5 steps are 0.056 s, in which a grain at 0.1 m/s crosses 5.6 diameters: several collisions each.
json elastic_gas_scene() {
    return {
        {"seed", 2024},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {"6.7 mm", "6.7 mm", "6.7 mm"}}, {"periodic", "xyz"}}},
        {"materials",
         {{{"name", "glass"},
           {"density", "2500 kg/m3"},
           {"youngs_modulus", "100 MPa"},
           {"poisson_ratio", 0.3},
           {"restitution", 1},
           {"friction", 0}}}},
        {"grains",
         {{{"material", "glass"},
           {"size",
            {{"distribution", "table"}, {"diameters", {"0.9 mm", "1 mm", "1.1 mm"}}, {"frequencies", {1, 1, 1}}}},
           {"placement", {{"method", "random"}, {"volume_fraction", 0.35}}},
           {"random_velocity", "0.1 m/s"}}}},
        {"run", {{"steps", 100000}, {"characteristic_speed", "0.35 m/s"}}},
    };
}

// The Hertz contact time of the two smallest grains of the scene at `speed`.
double smallest_pair_contact_time(const System& s, double speed) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < s.particles.size(); ++i)
        if (s.particles.radius[i] < s.particles.radius[k]) k = i;
    return hertz_contact_duration(0.5 * s.particles.mass[k], 0.5 * s.particles.radius[k],
                                  s.pairs(0, 0).effective_youngs, speed);
}

// ---------------------------------------------------------------------------------------------
// One grain in a fluid.
json single_grain_in_fluid(const json& fluid, const json& position, bool gravity) {
    json scene = {
        {"seed", 1},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {"1 mm", "1 mm", "1 mm"}}, {"periodic", "xyz"}}},
        {"materials", {{{"name", "steel"}, {"density", "7800 kg/m3"}, {"youngs_modulus", "200 GPa"}}}},
        // A lone grain never touches anything: without the contact model the step is set by the
        // drag relaxation time alone (otherwise by the Rayleigh time, thousands of times shorter).
        {"contact", {{"model", "none"}}},
        {"fluid", fluid},
        {"grains",
         {{{"material", "steel"},
           {"size", {{"distribution", "single"}, {"diameter", "100 um"}}},
           {"placement", {{"method", "list"}, {"positions", {position}}}}}}},
        {"run", {{"duration", 1}}},  // replaced by the test's own loop
    };
    if (gravity) scene["gravity"] = {0, 0, "-9.81 m/s2"};
    return scene;
}

// ---------------------------------------------------------------------------------------------
// Extremes.
// A periodic box 8 diameters wide at volume fraction 0.6 (about 590 grains) of grains of radius
// r and Young's modulus E, moving at up to 0.1 m/s.
json dense_scene(double radius, double youngs, double phi = 0.6) {
    const double d = 2 * radius, side = 8 * d;
    return {
        {"seed", 5},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {side, side, side}}, {"periodic", "xyz"}}},
        {"materials",
         {{{"name", "m"}, {"density", 2500}, {"youngs_modulus", youngs}, {"restitution", 0.5}, {"friction", 0.5}}}},
        {"grains",
         {{{"material", "m"},
           {"size", {{"distribution", "table"}, {"diameters", {0.9 * d, d, 1.1 * d}}, {"frequencies", {1, 1, 1}}}},
           {"placement", {{"method", "random"}, {"volume_fraction", phi}}},
           {"random_velocity", 0.1}}}},
        {"run", {{"steps", 300}}},
    };
}

// Sizes from d_min to 30 d_min in a periodic box 70 d_min wide.
json ratio_30_scene(double d_min, double youngs, double phi) {
    const double side = 70 * d_min;
    json diameters = json::array();
    for (double f : {1.0, 2.0, 4.0, 8.0, 15.0, 30.0}) diameters.push_back(f * d_min);
    return {
        {"seed", 6},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {side, side, side}}, {"periodic", "xyz"}}},
        {"materials",
         {{{"name", "m"}, {"density", 7800}, {"youngs_modulus", youngs}, {"restitution", 0.5}, {"friction", 0.5}}}},
        {"grains",
         {{{"material", "m"},
           {"size",
            {{"distribution", "table"},
             {"diameters", diameters},
             {"frequencies", {0.7, 0.2, 0.07, 0.02, 0.007, 0.003}}}},
           {"placement", {{"method", "random"}, {"volume_fraction", phi}}},
           {"random_velocity", 0.1}}}},
        {"run", {{"steps", 300}}},
    };
}

enum class Outcome { ran, refused_scene, blew_up };

struct ExtremeResult {
    Outcome outcome;
    std::string message;
    std::size_t grains = 0;
    double dt = 0;
    std::string limiting;
    double seconds = 0;
};

ExtremeResult run_extreme(const json& scene_json, long steps) {
    ExtremeResult r;
    const auto t0 = std::chrono::steady_clock::now();
    try {
        Scene scene = build(scene_json);
        System& s = scene.system;
        r.grains = s.particles.size();
        r.dt = s.dt;
        r.limiting = scene.limits.limiting;
        CHECK(std::isfinite(s.dt));
        CHECK(s.dt > 0);
        prepare(s);
        for (long i = 0; i < steps; ++i) advance(s);
        CHECK(all_finite(s.particles));
        const EnergyBreakdown e = energy(s);
        CHECK(std::isfinite(e.total()));
        r.outcome = Outcome::ran;
    } catch (const SceneError& e) {
        r.outcome = Outcome::refused_scene;
        r.message = e.what();
        // A clear refusal names a JSON path and says something about it.
        CHECK(e.path().size() > 1);
        CHECK(e.path()[0] == '/');
        CHECK(r.message.size() > e.path().size() + 10);
        CHECK(r.message.find("nan") == std::string::npos);
    } catch (const BlowUp& e) {
        r.outcome = Outcome::blew_up;
        r.message = e.what();
        CHECK(r.message.find("step") != std::string::npos);
        CHECK(r.message.find("grain") != std::string::npos);
        CHECK(r.message.find("Likely cause") != std::string::npos);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
}

const char* outcome_name(Outcome o) {
    switch (o) {
        case Outcome::ran:
            return "ran";
        case Outcome::refused_scene:
            return "refused (SceneError)";
        case Outcome::blew_up:
            return "stopped (BlowUp)";
    }
    return "?";
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("conservation: an elastic gas keeps its energy and momentum over 1e5 steps") {
        Scene scene = build(elastic_gas_scene());
        System& s = scene.system;
        const double tc = smallest_pair_contact_time(s, 0.35);
        REQUIRE(tc / 80 < scene.limits.stable_limit);
        s.dt = tc / 80;
        REQUIRE(s.particles.size() > 150);
        REQUIRE(s.particles.size() < 300);
        prepare(s);

        const double e0 = energy(s).total();
        const Vec3 p0 = momentum(s.particles);
        const double p_scale = momentum_scale(s.particles);
        REQUIRE(e0 > 0);
        double max_drift = 0;
        std::size_t max_contacts = 0;
        const long steps = 100000;
        for (long i = 1; i <= steps; ++i) {
            advance(s);
            max_contacts = std::max(max_contacts, s.contact_stats.contacts);
            if (i % 500 == 0) max_drift = std::max(max_drift, std::fabs(energy(s).total() - e0) / e0);
        }
        const EnergyBreakdown e = energy(s);
        const double drift = std::fabs(e.total() - e0) / e0;
        const double dp = norm(momentum(s.particles) - p0) / p_scale;
        report("elastic gas: " + std::to_string(s.particles.size()) + " grains, dt = t_c/80 = " + str(s.dt) +
               " s, final relative energy drift " + str(drift) + ", largest on the way " + str(max_drift) +
               ", momentum change / sum m|v| " + str(dp) + ", up to " + std::to_string(max_contacts) +
               " simultaneous contacts, " + std::to_string(s.contacts.builds()) + " list builds");
        CHECK(max_contacts > 3);  // the gas collides
        CHECK(drift < 1e-4);
        CHECK(max_drift < 1e-4);
        CHECK(dp < 1e-12);
        CHECK(e.rotational == 0);  // frictionless: no torque ever
    }

    TEST_CASE("drag: a grain settling in a viscous fluid reaches the Stokes terminal velocity with buoyancy") {
        const double mu = 0.05, rho_f = 1000;
        Scene scene = build(single_grain_in_fluid({{"viscosity", mu}, {"density", "1000 kg/m3"}},
                                                  {"0.5 mm", "0.5 mm", "0.5 mm"}, true));
        System& s = scene.system;
        REQUIRE(s.particles.size() == 1);
        CHECK(scene.limits.limiting.find("Stokes") != std::string::npos);
        const double r = s.particles.radius[0], m = s.particles.mass[0];
        const double volume = 4.0 / 3.0 * kPi * r * r * r;
        const double tau = m / (6 * kPi * mu * r);
        const double v_terminal = (m - rho_f * volume) * 9.81 / (6 * kPi * mu * r);
        prepare(s);
        const long steps = static_cast<long>(std::ceil(25 * tau / s.dt));  // e^-25 of the start left
        for (long i = 0; i < steps; ++i) advance(s);
        const double vz = -s.particles.velocity[0].z;
        const double err = std::fabs(vz - v_terminal) / v_terminal;
        report("Stokes settling: terminal velocity " + str(v_terminal) + " m/s, measured " + str(vz) + " m/s after " +
               std::to_string(steps) + " steps (dt = " + str(s.dt / tau) + " tau), relative error " + str(err));
        CHECK(err < 5e-3);
        CHECK(err < 1e-6);  // the fixed point of the scheme is exact
        CHECK(std::fabs(s.particles.velocity[0].x) < 1e-12 * v_terminal);
        CHECK(std::fabs(s.particles.velocity[0].y) < 1e-12 * v_terminal);
        // Without buoyancy the grain settles faster, by m / (m - rho_f V).
        Scene heavy = build(single_grain_in_fluid({{"viscosity", mu}}, {"0.5 mm", "0.5 mm", "0.5 mm"}, true));
        prepare(heavy.system);
        for (long i = 0; i < steps; ++i) advance(heavy.system);
        const double v_heavy = m * 9.81 / (6 * kPi * mu * r);
        CHECK(-heavy.system.particles.velocity[0].z == rel(v_heavy).epsilon(1e-6));
        // At a share s of the viscosity (the jam mode's fast-forwarded closed period) the grain
        // settles 1 / s times faster, after 1 / s times as long a relaxation.
        Scene thin = build(single_grain_in_fluid({{"viscosity", mu}}, {"0.5 mm", "0.5 mm", "0.5 mm"}, true));
        constexpr double share = 0.1;
        thin.system.terms.find<DragTerm>()->set_viscosity_share(share);
        prepare(thin.system);
        for (long i = 0; i < static_cast<long>(steps / share); ++i) advance(thin.system);
        CHECK(-thin.system.particles.velocity[0].z == rel(v_heavy / share).epsilon(1e-6));
    }

    TEST_CASE("drag: a grain at rest in a Couette flow reaches the local fluid velocity") {
        const json flow = {{"type", "couette"},
                           {"gradient_axis", "z"},
                           {"lower", 0},
                           {"upper", "1 mm"},
                           {"lower_velocity", {"-2 mm/s", 0, 0}},
                           {"upper_velocity", {"8 mm/s", "1 mm/s", 0}}};
        Scene scene = build(
            single_grain_in_fluid({{"viscosity", "10 mPa s"}, {"flow", flow}}, {"0.5 mm", "0.5 mm", "0.3 mm"}, false));
        System& s = scene.system;
        const double r = s.particles.radius[0], m = s.particles.mass[0];
        const double tau = m / (6 * kPi * 0.01 * r);
        prepare(s);
        const long steps = static_cast<long>(std::ceil(30 * tau / s.dt));
        for (long i = 0; i < steps; ++i) advance(s);
        // The grain stays at z = 0.3 mm (the flow has no z component): u = lower + 0.3 (upper - lower).
        const Vec3 expected{-2e-3 + 0.3 * 10e-3, 0.3 * 1e-3, 0};
        const Vec3 v = s.particles.velocity[0];
        report("Couette: expected (" + str(expected.x) + ", " + str(expected.y) + ") m/s, measured (" + str(v.x) +
               ", " + str(v.y) + ", " + str(v.z) + ") m/s");
        CHECK(s.particles.position[0].z == rel(0.3e-3).epsilon(1e-12));
        CHECK(v.x == rel(expected.x).epsilon(1e-6));
        CHECK(v.y == rel(expected.y).epsilon(1e-6));
        CHECK(std::fabs(v.z) < 1e-15);
    }

    // A flow that stretches along z, u = (0, 0, a z): a grain carried by it meets a faster fluid at
    // every step, so a held lookup (fluid/lookup_interval) is always stale.
    struct StretchingFlow final : FlowField {
        double rate;
        explicit StretchingFlow(double a) : rate(a) {}
        Vec3 velocity(const Vec3& x, double) const override { return {0, 0, rate * x.z}; }
        std::string name() const override { return "stretching"; }
    };

    // Held carrier-flow lookups: the grain's drag uses the fluid velocity at its position of up to
    // K - 1 steps before, so it follows the every-step grain a few steps late: z_K(t) ~ z_1(t - tau)
    // with tau <= (K - 1) dt, and |z_K - z_1| <= (K - 1) dt max|v| (the lag is a shift in time along
    // the same trajectory, which the flow's growth does not amplify). It must lag (else nothing was
    // held) and stay inside that bound; and every K-th force evaluation looks the flow up afresh.
    TEST_CASE("drag: held carrier-flow lookups lag the every-step grain by at most K - 1 steps") {
        const double mu = 0.05;
        auto run = [&](int interval, double& vmax, long& evaluations) {
            Scene scene = build(single_grain_in_fluid({{"viscosity", mu}, {"lookup_interval", interval}},
                                                      {"0.5 mm", "0.5 mm", "0.3 mm"}, false));
            System& s = scene.system;
            const double r = s.particles.radius[0], m = s.particles.mass[0];
            const double tau = m / (6 * kPi * mu * r);
            s.flow = std::make_shared<StretchingFlow>(0.1 / tau);
            prepare(s);
            const long steps = static_cast<long>(std::ceil(8 * tau / s.dt));  // z grows to ~0.6 mm
            vmax = 0;
            for (long i = 0; i < steps; ++i) {
                advance(s);
                vmax = std::max(vmax, std::fabs(s.particles.velocity[0].z));
            }
            evaluations = steps + 1;  // prepare's and one per step
            return std::make_pair(s, s.dt);
        };
        double vmax1 = 0, vmax4 = 0;
        long e1 = 0, e4 = 0;
        const auto [every, dt] = run(1, vmax1, e1);
        const auto [held, dt4] = run(4, vmax4, e4);
        REQUIRE(dt == dt4);
        const double z1 = every.particles.position[0].z, z4 = held.particles.position[0].z;
        const double bound = 3 * dt * std::max(vmax1, vmax4);
        report("held flow lookups (K = 4): z " + str(z4) + " m against " + str(z1) + " m every step, difference " +
               str(z1 - z4) + " m, bound (K - 1) dt max|v| = " + str(bound) + " m, " + std::to_string(e4) +
               " evaluations");
        CHECK(z1 > 0.5e-3);  // the flow carried the grain
        CHECK(z1 - z4 > 0);  // held: the grain saw the slower fluid behind it
        CHECK(z1 - z4 <= bound);
        const DragTerm* every_drag = every.terms.find<DragTerm>();
        const DragTerm* held_drag = held.terms.find<DragTerm>();
        REQUIRE(every_drag);
        REQUIRE(held_drag);
        CHECK(every_drag->lookups().reused == 0);
        CHECK(every_drag->held_lookups().empty());
        CHECK(held_drag->lookups().reused == e4 - (e4 + 3) / 4);  // fresh at evaluations 1, 5, 9, ...
    }

    TEST_CASE("stability: extreme scenes run with finite positions or are refused with a clear message") {
        // Grains of radius 1 um and 1 m, Young's moduli 1e5 and 2e11 Pa, at volume fraction 0.6, with
        // velocity components up to 0.1 m/s; then the soft ones again at 1 mm/s; then 30:1 size
        // ratios at volume fraction 0.6 from 1 um and up to 1 m grains. The overlap of a collision,
        // relative to the radius, depends only on rho v^2 / Y (not on the size): for the soft
        // material at 0.1 m/s it reaches ~10% of a radius, so those runs may stop with a BlowUp
        // naming the pair; everything else must run.
        struct Case {
            std::string label;
            json scene;
            bool must_run;
        };
        auto gentle = [](json j) {
            j["grains"][0]["random_velocity"] = "1 mm/s";
            return j;
        };
        const std::vector<Case> cases = {
            {"r ~ 1 um, Y = 1e5 Pa, phi 0.6, 0.1 m/s", dense_scene(1e-6, 1e5), false},
            {"r ~ 1 um, Y = 2e11 Pa, phi 0.6, 0.1 m/s", dense_scene(1e-6, 2e11), true},
            {"r ~ 1 m, Y = 1e5 Pa, phi 0.6, 0.1 m/s", dense_scene(1.0, 1e5), false},
            {"r ~ 1 m, Y = 2e11 Pa, phi 0.6, 0.1 m/s", dense_scene(1.0, 2e11), true},
            {"r ~ 1 um, Y = 1e5 Pa, phi 0.6, 1 mm/s", gentle(dense_scene(1e-6, 1e5)), true},
            {"r ~ 1 m, Y = 1e5 Pa, phi 0.6, 1 mm/s", gentle(dense_scene(1.0, 1e5)), true},
            {"30:1, d 1-30 um, Y = 1e9 Pa, phi 0.6, 0.1 m/s", ratio_30_scene(1e-6, 1e9, 0.6), true},
            {"30:1, d 1-30 um, Y = 2e11 Pa, phi 0.6, 0.1 m/s", ratio_30_scene(1e-6, 2e11, 0.6), true},
            {"30:1, d 1-30 um, Y = 1e5 Pa, phi 0.6, 1 mm/s", gentle(ratio_30_scene(1e-6, 1e5, 0.6)), true},
            {"30:1, d 6.7 cm-2 m, Y = 2e11 Pa, phi 0.6, 0.1 m/s", ratio_30_scene(2.0 / 30, 2e11, 0.6), true},
            {"30:1, d 6.7 cm-2 m, Y = 1e5 Pa, phi 0.6, 0.1 m/s", ratio_30_scene(2.0 / 30, 1e5, 0.6), false},
        };
        for (const Case& c : cases) {
            CAPTURE(c.label);
            const ExtremeResult r = run_extreme(c.scene, 300);
            if (c.must_run) CHECK(r.outcome == Outcome::ran);
            report(c.label + ": " + outcome_name(r.outcome) + ", " + std::to_string(r.grains) + " grains, dt " +
                   str(r.dt) + " s (" + r.limiting + "), " + str(r.seconds) + " s" +
                   (r.message.empty() ? "" : ": " + r.message));
        }
    }

    TEST_CASE("stability: a requested step above the stable limit is refused at /run/timestep with the limit") {
        json scene_json = dense_scene(50e-6, 1e9, 0.3);
        const Scene automatic = build(scene_json);
        const double limit = automatic.limits.stable_limit;
        REQUIRE(limit > 0);
        CHECK(automatic.system.dt == rel(0.1 * automatic.limits.critical));
        CHECK(automatic.system.dt < limit);

        scene_json["run"]["timestep"] = 1.5 * limit;
        try {
            build(scene_json);
            FAIL("a step of 1.5 x the stable limit was accepted");
        } catch (const SceneError& e) {
            CHECK(e.path() == "/run/timestep");
            const std::string msg = e.what();
            CHECK(msg.find(str(limit)) != std::string::npos);
            CHECK(msg.find("stable limit") != std::string::npos);
            report(std::string("refused: ") + msg);
        }
        // Just below the limit is accepted, and used as given.
        scene_json["run"]["timestep"] = 0.99 * limit;
        const Scene accepted = build(scene_json);
        CHECK(accepted.system.dt == 0.99 * limit);
    }

    // The step a drag sets is stable but can be thousands of times shorter than the contacts need:
    // said when more than 10 times, with the ratio to the contacts' shorter clock.
    TEST_CASE("stability: a step the drag sets far below the contacts' is named, with the ratio") {
        const double inf = std::numeric_limits<double>::infinity();
        TimestepLimits l;
        l.rayleigh = 1e-7;
        l.hertz = 2e-7;
        l.drag = l.stokes = 1e-9;
        l.pair_damping = inf;
        const std::string w = drag_limited_step_warning(l);
        CHECK(w.find("(1e-09 s, the smallest grain's m / (6 pi mu R)) sets the time step, 100 times shorter") !=
              std::string::npos);
        // Pair damping, not a fluid: its own clock and its own remedy.
        l.stokes = inf;
        l.drag = l.pair_damping = 1e-9;
        CHECK(drag_limited_step_warning(l).find("the pair damping's relaxation time (1e-09 s") == 0);
        CHECK(drag_limited_step_warning(l).find("contact/pair_damping") != std::string::npos);
        l.drag = l.pair_damping = 1.1e-8;  // 9.1 times: not worth a word
        CHECK(drag_limited_step_warning(l).empty());
        l.drag = l.pair_damping = inf;  // no fluid, no damping
        CHECK(drag_limited_step_warning(l).empty());
        // No contact law (a lone grain in a fluid): nothing to compare the drag with.
        l.rayleigh = l.hertz = inf;
        l.drag = l.stokes = 1e-9;
        CHECK(drag_limited_step_warning(l).empty());
    }

    TEST_CASE("reproducibility: same scene, seed and thread count give bit-identical positions") {
        // Dense, frictional and damped, so contact history and the neighbour list's rebuilds count.
        json scene_json = ratio_30_scene(20e-6, 1e9, 0.35);
        scene_json["materials"][0]["restitution"] = 0.3;
        scene_json["grains"][0]["random_velocity"] = "1 m/s";
        for (const int threads : {1, 2}) {
            CAPTURE(threads);
            std::vector<Vec3> positions[2];
            long builds[2] = {0, 0};
            for (int run = 0; run < 2; ++run) {
                Scene scene = build(scene_json, threads);
                prepare(scene.system);
                for (int i = 0; i < 400; ++i) advance(scene.system);
                positions[run] = scene.system.particles.position;
                builds[run] = scene.system.contacts.builds();
                CHECK(scene.system.contact_stats.contacts > 0);
                CHECK(scene.system.contacts.builds() > 2);
            }
            REQUIRE(positions[0].size() == positions[1].size());
            CHECK(builds[0] == builds[1]);
            CHECK(std::memcmp(positions[0].data(), positions[1].data(), positions[0].size() * sizeof(Vec3)) == 0);
        }
        // Another seed gives another packing.
        Scene a = build(scene_json), b = build([&] {
                                         json j = scene_json;
                                         j["seed"] = 7;
                                         return j;
                                     }());
        CHECK(std::memcmp(a.system.particles.position.data(), b.system.particles.position.data(),
                          std::min(a.system.particles.size(), b.system.particles.size()) * sizeof(Vec3)) != 0);
    }

}  // TEST_SUITE
