// Self-gravity (lib/engine/gravity/, terms/self_gravity_term): two bodies exactly, a uniform
// lattice sphere's field outside (G M / r^2) and inside (proportional to r), the tree against
// direct summation (and a monopole-only tree failing the same bounds, so the test sees the
// quadrupole), the cold collapse of a uniform cloud against the free-fall solution, and the
// angular momentum of a spinning cloud with held forces.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <vector>

#include "gravity/self_gravity.hpp"
#include "integrator.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "scene/scene_node.hpp"
#include "terms/self_gravity_term.hpp"

using mrjam_test::rel;
using namespace mrjam;
using json = nlohmann::json;

namespace {

// Lattice points of spacing a inside a sphere of radius R about the origin.
std::vector<Vec3> lattice_sphere(double R, double a) {
    std::vector<Vec3> x;
    const int n = static_cast<int>(R / a) + 1;
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j)
            for (int k = -n; k <= n; ++k) {
                const Vec3 p{(i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a};
                if (norm(p) < R) x.push_back(p);
            }
    return x;
}

// A contact-free scene of equal grains at `positions` (radius r, density rho) in open space.
json cloud_scene(const std::vector<Vec3>& positions, double r, const json& self_gravity, double dt) {
    json list = json::array();
    double extent = 0;
    for (const Vec3& p : positions) {
        list.push_back({p.x, p.y, p.z});
        extent = std::max(extent, norm(p));
    }
    const double L = 4 * extent + 10 * r;
    return {{"domain", {{"lo", {-L, -L, -L}}, {"hi", {L, L, L}}}},
            {"materials", {{{"name", "rock"}, {"density", 3000}, {"youngs_modulus", 1e7}}}},
            {"contact", {{"model", "none"}}},
            {"self_gravity", self_gravity},
            {"grains",
             {{{"material", "rock"},
               {"size", {{"distribution", "single"}, {"diameter", 2 * r}}},
               {"placement", {{"method", "list"}, {"positions", list}}}}}},
            {"run", {{"timestep", dt}, {"steps", 1}}}};
}

Scene build(const json& scene) {
    Scene s = build_scene(scene, BuildOptions{});
    choose_timestep(s);
    prepare(s.system);
    return s;
}

double relative_error(const Vec3& a, const Vec3& b) { return norm(a - b) / norm(b); }

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * (v.size() - 1))];
}

double rms_radius(const Particles& p) {
    Vec3 c{};
    for (const Vec3& x : p.position) c += x;
    c = c / static_cast<double>(p.size());
    double s = 0;
    for (const Vec3& x : p.position) s += dot(x - c, x - c);
    return std::sqrt(s / p.size());
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE(
        "self-gravity: two grains attract as G m1 m2 / r^2, by the tree and directly, and as touching inside contact") {
        Particles p;
        p.position = {{0, 0, 0}, {3, 4, 0}};
        p.mass = {2e3, 5e3};
        p.radius = {0.5, 0.5};
        std::vector<Vec3> direct, tree;
        direct_gravity(p, kNewtonG, direct, 1);
        GravityTree t;
        t.build(p);
        t.accelerations(p, kNewtonG, tree, 1);
        const Vec3 expected = Vec3{3, 4, 0} * (kNewtonG * 5e3 / 125.0);
        CHECK(relative_error(direct[0], expected) < 1e-12);
        CHECK(relative_error(tree[0], expected) < 1e-12);
        CHECK(relative_error(direct[1] * 5e3, direct[0] * -2e3) < 1e-12);  // action and reaction
        // Overlapping centres 0.5 apart with radii 0.5: the pull of grains touching at 1.
        p.position[1] = {0.3, 0.4, 0};
        direct_gravity(p, kNewtonG, direct, 1);
        CHECK(norm(direct[0]) == rel(kNewtonG * 5e3 / 1.0).epsilon(1e-12));
        CHECK(gravitational_energy(p, kNewtonG) == rel(-kNewtonG * 2e3 * 5e3 / 1.0).epsilon(1e-12));
    }

    TEST_CASE("self-gravity: a uniform lattice sphere pulls as G M / r^2 outside and in proportion to r inside") {
        const double R = 10, a = 1.3;  // about 2,000 grains
        std::vector<Vec3> x = lattice_sphere(R, a);
        const std::size_t n = x.size();
        x.push_back({2 * R, 0, 0});  // a probe grain of negligible mass
        Particles p;
        p.position = x;
        p.radius.assign(x.size(), 0.1);
        p.mass.assign(x.size(), 1e6);
        p.mass.back() = 1e-12;
        CAPTURE(n);
        CHECK(n > 1500);
        const double M = 1e6 * n;
        std::vector<Vec3> acc;
        direct_gravity(p, kNewtonG, acc, 2);
        CHECK(norm(acc.back()) == rel(kNewtonG * M / (4 * R * R)).epsilon(3e-3));
        // Inside: |a| / r = (4 pi / 3) G rho, rho the lattice's mean density m / a^3.
        const double slope = 4 * M_PI / 3 * kNewtonG * 1e6 / (a * a * a);
        std::vector<double> ratio;
        for (std::size_t i = 0; i < n; ++i) {
            const double r = norm(x[i]);
            if (r > 0.3 * R && r < 0.7 * R) ratio.push_back(norm(acc[i]) / r / slope);
        }
        CHECK(percentile(ratio, 0.5) == rel(1.0).epsilon(0.03));
        CHECK(percentile(ratio, 0.05) > 0.9);
        CHECK(percentile(ratio, 0.95) < 1.1);
    }

    TEST_CASE("self-gravity: the tree at theta 0.5 against direct summation; a monopole-only tree misses") {
        std::vector<Vec3> x = lattice_sphere(12, 1.0);
        // Jitter the lattice so no grain sits on a cube's face.
        for (std::size_t i = 0; i < x.size(); ++i)
            x[i] += Vec3{std::sin(1.7 * i), std::cos(2.3 * i), std::sin(0.7 * i + 1)} * 0.3;
        Particles p;
        p.position = x;
        p.radius.assign(x.size(), 0.1);
        p.mass.assign(x.size(), 1e3);
        for (std::size_t i = 0; i < x.size(); ++i) p.mass[i] *= 1 + 0.5 * std::sin(3.1 * i);
        std::vector<Vec3> direct;
        direct_gravity(p, kNewtonG, direct, 2);
        auto errors = [&](bool quadrupole) {
            GravityTree t({0.5, 8, quadrupole});
            t.build(p);
            std::vector<Vec3> tree;
            t.accelerations(p, kNewtonG, tree, 2);
            std::vector<double> e;
            for (std::size_t i = 0; i < x.size(); ++i) e.push_back(relative_error(tree[i], direct[i]));
            return e;
        };
        const std::vector<double> with = errors(true), without = errors(false);
        CAPTURE(x.size());
        CAPTURE(percentile(with, 0.5));
        CAPTURE(percentile(with, 0.99));
        CAPTURE(percentile(without, 0.5));
        CHECK(percentile(with, 0.5) <= 1e-3);
        CHECK(percentile(with, 0.99) <= 5e-3);
        CHECK_FALSE((percentile(without, 0.5) <= 1e-3 && percentile(without, 0.99) <= 5e-3));
    }

    TEST_CASE("self-gravity: a cold uniform cloud collapses as the free-fall solution (r_rms within 2 %)") {
        const double R = 10, a = 1.4, r = 0.05;
        const std::vector<Vec3> x = lattice_sphere(R, a);
        const double rho = 3000 * 4.0 / 3.0 * M_PI * r * r * r / (a * a * a);  // the cloud's mean density
        const double t_ff = std::sqrt(3 * M_PI / (32 * kNewtonG * rho));
        const double dt = t_ff / 1000;
        Scene sc = build(cloud_scene(x, r, {{"method", "tree"}}, dt));
        System& s = sc.system;
        const double r0 = rms_radius(s.particles);
        // A homologous collapse: every shell r = r0 cos^2(b), t / t_ff = (b + sin b cos b) / (pi / 2).
        auto shrink = [](double f) {
            double lo = 0, hi = M_PI / 2;
            for (int k = 0; k < 100; ++k) {
                const double b = 0.5 * (lo + hi);
                ((b + std::sin(b) * std::cos(b)) / (M_PI / 2) < f ? lo : hi) = b;
            }
            const double b = 0.5 * (lo + hi);
            return std::cos(b) * std::cos(b);
        };
        advance_steps(s, 500);
        CHECK(rms_radius(s.particles) / r0 == rel(shrink(0.5)).epsilon(0.02));
        advance_steps(s, 300);
        CHECK(rms_radius(s.particles) / r0 == rel(shrink(0.8)).epsilon(0.02));
    }

    TEST_CASE("self-gravity: a spinning cloud keeps its angular momentum to 1e-3 with forces held 4 steps") {
        const std::vector<Vec3> x = lattice_sphere(8, 1.3);
        const double r = 0.05, rho = 3000 * 4.0 / 3.0 * M_PI * r * r * r / (1.3 * 1.3 * 1.3);
        const double t_ff = std::sqrt(3 * M_PI / (32 * kNewtonG * rho));
        Scene sc = build(cloud_scene(x, r, {{"method", "tree"}, {"update_interval", 4}}, t_ff / 1000));
        System& s = sc.system;
        const double omega = 0.5 * M_PI / (2 * t_ff);  // a quarter turn over two free-fall times
        for (std::size_t i = 0; i < s.particles.size(); ++i)
            s.particles.velocity[i] = cross(Vec3{0, 0, omega}, s.particles.position[i]);
        auto angular_momentum = [&] {
            Vec3 L{};
            for (std::size_t i = 0; i < s.particles.size(); ++i)
                L += cross(s.particles.position[i], s.particles.velocity[i]) * s.particles.mass[i];
            return L;
        };
        const Vec3 L0 = angular_momentum();
        const auto* term = s.terms.find<SelfGravityTerm>();
        REQUIRE(term);
        const long before = term->evaluations();
        advance_steps(s, 400);
        CHECK(norm(angular_momentum() - L0) / norm(L0) < 1e-3);
        CHECK(term->evaluations() - before == 100);  // 400 steps, one evaluation in four
    }
}

TEST_SUITE("unit") {
    TEST_CASE("self-gravity scene: a periodic axis, theta outside (0, 1] and unknown keys are refused by name") {
        auto refusal = [](json scene) {
            try {
                build_scene(scene, BuildOptions{});
            } catch (const SceneError& e) {
                return e.path();
            }
            return std::string("accepted");
        };
        const json base = cloud_scene({{0, 0, 0}, {1, 0, 0}}, 0.1, json::object(), 1.0);
        CHECK(refusal(base) == "accepted");
        json s = base;
        s["domain"]["periodic"] = "x";
        CHECK(refusal(s) == "/domain/periodic");
        s = base;
        s["self_gravity"]["opening_angle"] = 1.5;
        CHECK(refusal(s) == "/self_gravity/opening_angle");
        s["self_gravity"]["opening_angle"] = 0;
        CHECK(refusal(s) == "/self_gravity/opening_angle");
        s = base;
        s["self_gravity"]["theta"] = 0.5;
        CHECK(refusal(s) == "/self_gravity/theta");
        s = base;
        s["self_gravity"]["constant"] = "6.674e-11 m3/kg s2";  // one "/": the rest is the denominator
        CHECK(refusal(s) == "accepted");
        s["self_gravity"]["constant"] = "6.674e-11 m/s2";
        CHECK(refusal(s) == "/self_gravity/constant");
    }
}
