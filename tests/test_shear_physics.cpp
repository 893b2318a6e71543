// Physics checks of the shear-cell observers and protocol against analytic answers: a lone grain
// relaxing to the Couette flow (no stress reaches the rafts), the magnetic pair force counted in
// the raft stress and in the virial, and the steady-state balance of raft and bulk stresses.
#include <doctest/doctest.h>

#include <cmath>

#include "integrator.hpp"
#include "magnetic/magnetic_model.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "shear/shear_cell.hpp"
#include "shear/shear_spec.hpp"
#include "shear/shear_stress.hpp"
#include "test_support.hpp"

using mrjam_test::rel;

using namespace mrjam;
using json = nlohmann::json;

namespace {

constexpr double kL = 40e-6;  // cell edge

// Grains of one size at given positions between two walls, fluid at rest, optional field.
Scene cell_with(const std::vector<std::array<double, 3>>& positions, double diameter, double flux_density) {
    json pos = json::array();
    for (const auto& x : positions) pos.push_back({x[0], x[1], x[2]});
    json scene = {{"domain", {{"lo", {0, 0, 0}}, {"hi", {kL, kL, kL}}, {"periodic", "xy"}}},
                  {"materials",
                   {{{"name", "iron"},
                     {"density", 7800},
                     {"youngs_modulus", 1e9},
                     {"poisson_ratio", 0.278},
                     {"restitution", 0.1},
                     {"friction", 0.1}}}},
                  {"fluid", {{"viscosity", 0.01}}},
                  {"walls",
                   {{{"name", "bottom"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
                    {{"name", "top"}, {"type", "plane"}, {"point", {0, 0, kL}}, {"normal", {0, 0, -1}}}}},
                  {"grains",
                   {{{"size", {{"distribution", "single"}, {"diameter", diameter}}},
                     {"placement", {{"method", "list"}, {"positions", pos}}}}}},
                  {"run", {{"steps", 0}}}};
    if (flux_density > 0)
        scene["magnetic"] = {{"field", {{"type", "uniform"}, {"flux_density", {0, 0, flux_density}}}},
                             {"mutual", "fixed"},
                             {"cutoff", {{"length", 12e-6}}}};
    Scene s = build_scene(scene, BuildOptions{});
    choose_timestep(s);
    return s;
}

void make_raft(System& s, std::size_t grain, const std::string& name, Vec3 v) {
    s.rafts.push_back(Raft{name, v, {}, 1});
    s.particles.raft[grain] = static_cast<std::int16_t>(s.rafts.size() - 1);
}

// Grains are put in spatial order after insertion, so find them by their height.
std::size_t index_at_height(const System& s, double z) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
        if (std::abs(s.particles.position[i].z - z) < 1e-12) return i;
    FAIL("no grain at z = " << z);
    return 0;
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE(
        "shear cell: a lone grain relaxes to the Couette flow as v(t) = u (1 - exp(-t/tau)) and no stress reaches the "
        "rafts") {
        // Two raft grains, one free grain between them; Stokes drag only (no contacts happen).
        Scene sc = cell_with({{20e-6, 20e-6, 3e-6}, {20e-6, 20e-6, 37e-6}, {10e-6, 10e-6, 28e-6}}, 4e-6, 0);
        System& s = sc.system;
        const double v = 0.05, lower = 8e-6, upper = 32e-6;
        s.rafts.clear();
        make_raft(s, index_at_height(s, 3e-6), "lower", Vec3{-v, 0, 0});
        make_raft(s, index_at_height(s, 37e-6), "upper", Vec3{v, 0, 0});
        s.flow = std::make_shared<CouetteFlow>(2, lower, upper, Vec3{-v, 0, 0}, Vec3{v, 0, 0});
        for (auto& w : s.walls) w.velocity = Vec3{w.name == "top" ? v : -v, 0, 0};
        prepare(s);
        const std::size_t g = index_at_height(s, 28e-6);
        const double radius = s.particles.radius[g];
        const double tau = s.particles.mass[g] / (6 * M_PI * 0.01 * radius);
        const double u = -v + 2 * v * (28e-6 - lower) / (upper - lower);
        const long steps = static_cast<long>(std::ceil(tau / s.dt));
        advance_steps(s, steps);
        // The grain starts at rest and moves along x only, so z and hence u stay fixed.
        const double expected = u * (1 - std::exp(-s.time / tau));
        // The drag term is explicit and first order in dt / tau: that is the tolerance.
        CAPTURE(s.dt / tau);
        CHECK(s.particles.velocity[g].x == rel(expected).epsilon(s.dt / tau));
        ShearStress st = shear_stress(s, 1, 0, 1, 0, lower, upper);
        CHECK(st.upper == 0.0);
        CHECK(st.lower == 0.0);
        // Bulk stress: only the drag moment, -(z - z_mid) D_x / V with D_x = 6 pi mu R (u - v_x).
        const double volume = kL * kL * (upper - lower);
        const double drag = 6 * M_PI * 0.01 * radius * (u - s.particles.velocity[g].x);
        CHECK(st.bulk == rel(-(28e-6 - 0.5 * (lower + upper)) * drag / volume).epsilon(1e-9));
        advance_steps(s, 30 * steps);  // 31 tau: the drag balance is reached, v = u
        CHECK(s.particles.velocity[g].x == rel(u).epsilon(1e-9));
        st = shear_stress(s, 1, 0, 1, 0, lower, upper);
        CHECK(std::abs(st.bulk) <
              1e-9 * std::abs(-(28e-6 - 0.5 * (lower + upper)) * 6 * M_PI * 0.01 * radius * u / volume));
    }

    TEST_CASE("shear cell: the raft stress and the virial include the dipole force of eq. 4.8") {
        // Two grains 8 um apart along a line tilted 30 degrees from the field (z), not touching; fixed
        // dipoles m = 4 pi R^3 (mu_r - 1)/(mu_r + 2) B/mu0. The upper one is a raft grain.
        const double B = 0.1, d = 4e-6, r = 8e-6, angle = M_PI / 6;
        const double x1 = 20e-6, z1 = 16e-6;
        const double x2 = x1 + r * std::sin(angle), z2 = z1 + r * std::cos(angle);
        Scene sc = cell_with({{x1, 20e-6, z1}, {x2, 20e-6, z2}}, d, B);
        System& s = sc.system;
        make_raft(s, index_at_height(s, z2), "upper", Vec3{});
        prepare(s);
        const double R = d / 2, mu_r = 1000;
        const double m = 4 * M_PI * R * R * R * (mu_r - 1) / (mu_r + 2) * B / kMu0;
        // Force on grain 2 from grain 1 for parallel moments along z, rhat from 1 to 2 at angle theta:
        // F = 3 mu0 m^2 / (4 pi r^4) [ (1 - 5 cos^2) rhat + 2 cos zhat ].
        const double c = std::cos(angle), pref = 3 * kMu0 * m * m / (4 * M_PI * std::pow(r, 4));
        const double fx2 = pref * (1 - 5 * c * c) * std::sin(angle);
        const double area = kL * kL;
        const ShearStress st = shear_stress(s, 0, -1, -1, -1, 10e-6, 30e-6);
        CHECK(st.upper == rel(-fx2 / area).epsilon(1e-9));
        // Virial of the one pair: -(z1 - z2) f_12,x / V with f_12 = -F on 2.
        CHECK(st.bulk == rel(-((z1 - z2) * (-fx2)) / (area * 20e-6)).epsilon(1e-9));
    }

    TEST_CASE("shear cell: in steady shear the virial stress matches the raft stresses and the rafts balance") {
        // A small magnetised cell sheared at two rates. Momentum balance of the free grains makes the
        // virial over the gap equal the mean raft stress up to where inside each raft layer its force
        // acts (within about one grain diameter d of the inner face): tolerance 2 d / gap, plus three
        // standard errors. The two rafts carry the same stress up to the net drag, which the Couette
        // flow keeps small: within 15% plus three errors.
        const json input = {
            {"size", {{"distribution", "single"}, {"diameter", "4 um"}}},
            {"cell", {{"size", {"40 um", "40 um", "44 um"}}, {"raft_thickness", "5 um"}}},
            {"material", mrjam_test::chapter2_iron()},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "300 mT"}}},
            {"magnetise", {{"min_duration", "3 us"}, {"max_duration", "5 us"}, {"field_ramp", "2 us"}}},
            {"ladder", {{"shear_rates", {"3000 1/s", "1500 1/s"}}, {"strain_first", 0.2}, {"strain_per_rate", 0.1}}},
            {"measure", {{"samples_per_rate", 40}, {"window", 0.5}, {"blocks", 5}}},
            {"output", {{"directory", (std::filesystem::temp_directory_path() / "mrjam_shear_balance").string()}}}};
        const ShearSpec spec = read_shear_spec(input, "quick");
        ShearOptions opt;
        opt.progress = false;
        const ShearOutcome out = run_shear_study(spec, opt);
        REQUIRE(out.status == "complete");
        const double tol = 2 * 4e-6 / spec.gap();
        for (const auto& q : out.results["flow_curve"]) {
            const double up = q["stress_Pa"], lo = q["lower_raft_stress_Pa"], bulk = q["bulk_stress_Pa"];
            const double e_up = q["error_Pa"], e_lo = q["lower_raft_error_Pa"], e_bulk = q["bulk_error_Pa"];
            const double mean = 0.5 * (up + lo), e_mean = 0.5 * std::hypot(e_up, e_lo);
            CAPTURE(q.dump());
            CHECK(up > 0);
            CHECK(std::abs(bulk - mean) <= tol * std::abs(mean) + 3 * std::hypot(e_bulk, e_mean));
            CHECK(std::abs(up - lo) <= 0.15 * std::abs(mean) + 3 * std::hypot(e_up, e_lo));
        }
        std::filesystem::remove_all(spec.output.directory);
    }

}  // TEST_SUITE

TEST_SUITE("physics") {
    TEST_CASE("contact damping: a sliding touching pair loses relative velocity as exp(-2 c t / m), momentum kept") {
        // Frictionless equal grains touching along z, sliding along x: the only tangential force is
        // the pair damping f = -c (v_i - v_j), so the relative velocity decays at 2 c / m.
        const double d = 4e-6, c = 1e-5;
        json scene = {
            {"domain", {{"lo", {0, 0, 0}}, {"hi", {kL, kL, kL}}, {"periodic", "xyz"}}},
            {"materials", {{{"name", "iron"}, {"density", 7800}, {"youngs_modulus", 1e9}, {"friction", 0.0}}}},
            {"contact", {{"pair_damping", c}}},
            {"grains",
             {{{"size", {{"distribution", "single"}, {"diameter", d}}},
               {"placement",
                {{"method", "list"},
                 {"positions", {{20e-6, 20e-6, 20e-6}, {20e-6, 20e-6, 20e-6 + d * (1 - 1e-5)}}}}}}}},
            {"run", {{"steps", 0}}}};
        // The damping term is explicit, first order in x = 2 c dt / m (the automatic step keeps
        // x <= 0.1): after one relaxation time the decay's relative error is about x / 2. So check
        // it against that bound at the automatic step, and check that it is first order: a step
        // four times smaller cuts the error about four times.
        auto decay_error = [&](double step_divisor, double& x) {
            Scene sc = build_scene(scene, BuildOptions{});
            choose_timestep(sc);
            System& s = sc.system;
            s.dt /= step_divisor;
            s.particles.velocity[0] = Vec3{0.01, 0, 0};
            s.particles.velocity[1] = Vec3{-0.01, 0, 0};
            prepare(s);
            const double m = s.particles.mass[0];
            x = 2 * c * s.dt / m;
            const double t_end = 0.5 * m / c;  // one relaxation time of the relative velocity (rate 2c/m)
            advance_steps(s, static_cast<long>(std::ceil(t_end / s.dt)));
            REQUIRE(s.contact_stats.contacts == 1);  // still touching: the damping acted throughout
            CHECK(std::abs(s.particles.velocity[0].x + s.particles.velocity[1].x) < 1e-15);  // momentum
            const double relative_speed = std::abs(s.particles.velocity[0].x - s.particles.velocity[1].x);
            return relative_speed / (0.02 * std::exp(-2 * c * s.time / m)) - 1;
        };
        double x_auto = 0, x_fine = 0;
        const double coarse = decay_error(1, x_auto), fine = decay_error(4, x_fine);
        CAPTURE(x_auto);
        CAPTURE(coarse);
        CAPTURE(fine);
        CHECK(x_auto <= 0.1 + 1e-12);
        CHECK(std::abs(coarse) <= x_auto);
        CHECK(std::abs(coarse) / std::abs(fine) == doctest::Approx(4.0).epsilon(0.25));
    }

}  // TEST_SUITE
