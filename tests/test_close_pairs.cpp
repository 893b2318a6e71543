// The close-pair correction (lib/engine/magnetic/close_pair_correction): with it, the engine's force on
// an isolated pair is the exact two-sphere force, along and across the line of centres.
//
//  1. Two iron grains (mu_r 1000) 0.1 radii apart, the line of centres 35 degrees from the field,
//     converged dipoles plus the correction: the engine's force on each equals the gradient of
//     the exact co-energy W' = 2 pi mu0 a^3 H^2 (alpha_ax cos^2 + alpha_tr sin^2), taken by
//     central differences of the exact solver (an independent route to the across-the-line part).
//     Tolerance 2e-3 of the force: the table's linear interpolation in log(gap) (96 points from
//     0.01 to 1 radius) is good to ~1e-3 of the correction.
//  2. Beyond the range the engine's force is the point dipoles' alone; action equals reaction.
//  3. A field looked up per grain (a map's path) gives the uniform shortcut's forces, on one
//     thread and on two.
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <memory>

#include "magnetic/magnetic_model.hpp"
#include "magnetic/sphere_pair_exact.hpp"
#include "rel_approx.hpp"

using namespace mrjam;

namespace {

// A uniform field that does not say so, so the engine looks it up at every grain as in a map.
class LookedUpField final : public ExternalField {
public:
    explicit LookedUpField(Vec3 b) : b_(b) {}
    Vec3 flux_density(const Vec3&, double) const override { return b_; }
    Gradient gradient(const Vec3&, double) const override { return {}; }
    bool uniform() const override { return false; }
    std::string name() const override { return "looked up"; }

private:
    Vec3 b_;
};

// The linear table for one permeability, built once per test run: every pair here uses the same
// settings, and each build solves the exact two-sphere problem at every tabulated gap (seconds).
const ClosePairTable& table(double mu, const ClosePairSettings& settings) {
    static std::map<double, ClosePairTable> built;
    auto it = built.find(mu);
    if (it == built.end()) it = built.emplace(mu, ClosePairTable(mu, settings)).first;
    return it->second;
}

struct Pair {
    Particles p;
    MagneticModel model;
    Domain domain;
    Pair(double radius, double mu, double b, const Vec3& offset, bool corrected, bool looked_up = false,
         int threads = 1) {
        model.enabled = true;
        if (looked_up)
            model.field = std::make_shared<LookedUpField>(Vec3{0, 0, b});
        else
            model.field = std::make_shared<UniformField>(Vec3{0, 0, b}, 0.0, 0.0, 1e300);
        model.settings.policy = MutualPolicy::converged;
        model.settings.tolerance = 1e-13;
        model.settings.max_iterations = 1000;
        model.settings.cutoff_scale = 3.0;
        model.settings.close_pairs = {corrected, ClosePairModel::linear, 0.01, 1.0};
        if (corrected) model.close_pair_table = table(mu, model.settings.close_pairs);
        domain.lo = {-1, -1, -1};
        domain.hi = {1, 1, 1};
        const double beta = (mu - 1) / (mu + 2);
        for (const Vec3& x : {Vec3{}, offset}) {
            const std::size_t i = p.add(x, radius, 7800.0, 0);
            p.induced_coefficient[i] = 4 * M_PI * radius * radius * radius * beta;
            p.saturation_moment[i] = 1e100;
        }
        model.pairs = NeighborList(NeighborList::Settings{0.0, 3.0, false, 0.0});
        model.pairs.build(p, domain, 1);
        for (auto& f : p.force) f = Vec3{};
        initialise_moments(model, p, 0.0);
        add_magnetic_forces(model, p, 0.0, threads);
    }
};

// W' of the pair with grain 1 at `x1` (grain 0 at the origin), exact, in units of 2 pi mu0 a^3 H^2.
double exact_coenergy(double mu, const Vec3& x1, double a) {
    const double r = norm(x1), s = r / a, cos_t = x1.z / r;
    const double ax = converged_sphere_pair_response(mu, s, PairOrientation::axial, 1e-12).polarisability;
    const double tr = converged_sphere_pair_response(mu, s, PairOrientation::transverse, 1e-12).polarisability;
    return ax * cos_t * cos_t + tr * (1 - cos_t * cos_t);
}

}  // namespace

TEST_SUITE("physics") {
    TEST_CASE("close pairs: the corrected engine force on an isolated pair is the exact two-sphere force") {
        const double a = 10e-6, mu = 1000, b = 0.01, h = b / kMu0, theta = 35 * M_PI / 180;
        const double s = 2.1;
        const Vec3 x1{s * a * std::sin(theta), 0, s * a * std::cos(theta)};
        const Pair pair(a, mu, b, x1, true);
        // The exact force on grain 1: +grad W' (fixed applied field), by central differences.
        const double step = 1e-5 * a, unit = 2 * M_PI * kMu0 * a * a * a * h * h;
        Vec3 exact{};
        for (int k : {0, 2}) {
            Vec3 e{};
            e[k] = step;
            exact[k] = unit * (exact_coenergy(mu, x1 + e, a) - exact_coenergy(mu, x1 - e, a)) / (2 * step);
        }
        CAPTURE(pair.p.force[1]);
        CAPTURE(exact);
        CHECK(norm(pair.p.force[1] - exact) <= 2e-3 * norm(exact));
        CHECK(norm(pair.p.force[0] + pair.p.force[1]) <= 1e-12 * norm(exact));
        // The correction matters here: the point dipoles alone are off by far more than the tolerance.
        const Pair dipoles(a, mu, b, x1, false);
        CHECK(norm(dipoles.p.force[1] - exact) > 0.2 * norm(exact));
    }

    TEST_CASE("close pairs: no correction beyond the range") {
        const double a = 10e-6;
        const Vec3 x1{0.3 * a, 0, 3.2 * a};  // gap ~1.21 radii > range 1
        const Pair corrected(a, 1000, 0.01, x1, true), plain(a, 1000, 0.01, x1, false);
        CHECK(norm(corrected.p.force[1] - plain.p.force[1]) == 0.0);
    }

    TEST_CASE("close pairs: a field looked up per grain gives the uniform shortcut's forces") {
        const double a = 10e-6;
        const Vec3 x1{1.0 * a, 0.4 * a, 1.8 * a};  // gap ~0.1 radii, off the field's axis
        const Pair shortcut(a, 1000, 0.01, x1, true);
        for (int threads : {1, 2}) {
            CAPTURE(threads);
            const Pair looked_up(a, 1000, 0.01, x1, true, true, threads);
            for (int i : {0, 1})
                CHECK(norm(looked_up.p.force[i] - shortcut.p.force[i]) <= 1e-12 * norm(shortcut.p.force[i]));
        }
    }

}  // TEST_SUITE
