// Unit checks of the shear-mode statistics: the yield-stress fits recover the parameters of
// synthetic flow curves exactly, and block averaging gives sigma / sqrt(n) for independent data.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "magnetic/magnetic_model.hpp"
#include "rel_approx.hpp"
#include "shear/block_average.hpp"
#include "shear/dimensionless.hpp"
#include "shear/flow_curve_fit.hpp"
#include "shear/shear_spec.hpp"
#include "shear/steady_state.hpp"

using mrjam_test::rel;

using namespace mrjam;

namespace {
std::vector<FlowPoint> synthetic(const std::vector<double>& rates, double (*law)(double)) {
    std::vector<FlowPoint> pts;
    for (double g : rates) pts.push_back({g, law(g), 0.0});
    return pts;
}
const std::vector<double> kRates = {1164, 582, 291, 100, 73, 36, 18, 9};
}  // namespace

namespace {

// A rate's averaged window as block_average gives it: `samples` samples in blocks with these means.
BlockAverage window_of(std::size_t samples, const std::vector<double>& block_means) {
    BlockAverage w;
    w.samples = samples;
    w.blocks = block_means.size();
    w.means = block_means;
    for (double m : block_means) w.mean += m / static_cast<double>(block_means.size());
    return w;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("shear fits: Bingham recovers tau_y and eta from exact data, using only rates above the threshold") {
        // Below 200 1/s the data follow another law: the fit must ignore them.
        auto law = [](double g) { return g >= 200 ? 44.9e3 + 3.5 * g : 1e3; };
        const auto pts = synthetic(kRates, law);
        const ModelFit f = fit_bingham(pts, 200);
        REQUIRE(f.ok);
        CHECK(f.points == 3);
        CHECK(f.yield_stress == rel(44.9e3).epsilon(1e-12));
        CHECK(f.viscosity == rel(3.5).epsilon(1e-10));
        CHECK(f.yield_stress_error ==
              doctest::Approx(0).scale(1e3).epsilon(1e-9));  // exact data: no scatter, no error bars
    }

    TEST_CASE("shear fits: Bingham uncertainty propagates the points' error bars when two points fit exactly") {
        // Two points, each +-s: intercept = (g2 y1 - g1 y2)/(g2 - g1), so its error is
        // s sqrt(g1^2 + g2^2) / |g2 - g1|.
        const double s = 500;
        const std::vector<FlowPoint> pts = {{1000, 50e3, s}, {300, 46e3, s}};
        const ModelFit f = fit_bingham(pts, 200);
        REQUIRE(f.ok);
        CHECK(f.yield_stress_error == rel(s * std::sqrt(1000.0 * 1000 + 300.0 * 300) / 700).epsilon(1e-12));
        CHECK_FALSE(fit_bingham({{100, 1e3, 0}, {1000, 2e3, 0}}, 200).ok);  // one rate above the threshold
        // A line through the origin's far side, or falling, is fitted and said to be no Bingham fluid.
        const ModelFit below = fit_bingham({{1000, 5e3, 0}, {300, 1e3, 0}}, 200);
        CHECK(below.yield_stress < 0);
        CHECK(below.note.find("negative intercept") == 0);
        const ModelFit falling = fit_bingham({{1000, 1e3, 0}, {300, 5e3, 0}}, 200);
        CHECK(falling.viscosity < 0);
        CHECK(falling.note.find("stress falls with rate") == 0);
        CHECK(fit_bingham(pts, 200).note.empty());
    }

    TEST_CASE("shear fits: Casson recovers tau_y and eta from exact data") {
        auto law = [](double g) {
            const double r = std::sqrt(30e3) + std::sqrt(0.8 * g);
            return r * r;
        };
        const ModelFit f = fit_casson(synthetic(kRates, law));
        REQUIRE(f.ok);
        CHECK(f.yield_stress == rel(30e3).epsilon(1e-10));
        CHECK(f.viscosity == rel(0.8).epsilon(1e-9));
        CHECK(f.rms_residual < 1e-6);
    }

    TEST_CASE("shear fits: Herschel-Bulkley recovers tau_y, K and n from exact data") {
        for (double n : {0.35, 0.8, 1.4}) {
            CAPTURE(n);
            static double nn;
            nn = n;
            auto law = [](double g) { return 20e3 + 150.0 * std::pow(g, nn); };
            const ModelFit f = fit_herschel_bulkley(synthetic(kRates, law));
            REQUIRE(f.ok);
            CHECK(f.flow_index == rel(n).epsilon(1e-6));
            CHECK(f.yield_stress == rel(20e3).epsilon(1e-5));
            CHECK(f.consistency == rel(150.0).epsilon(1e-4));
        }
    }

    TEST_CASE("block averaging: the error of independent samples matches sigma / sqrt(n)") {
        // For iid data every block mean is independent, so the block estimate of the standard error
        // is unbiased for sigma^2/n; with B blocks its relative spread is about 1/sqrt(2(B-1)). Averaged
        // over 200 trials of 50 blocks, the mean estimate must lie within 3% of sigma / sqrt(n)
        // (the standard deviation of that mean is 0.1/sqrt(200) = 0.7%, and the mean of a sqrt of an
        // unbiased variance is low by about 1/(8(B-1)) = 0.26%).
        std::mt19937_64 rng(7);
        std::normal_distribution<double> normal(3.0, 2.0);
        const std::size_t n = 5000, blocks = 50;
        double ratio_sum = 0;
        const int trials = 200;
        for (int t = 0; t < trials; ++t) {
            std::vector<double> x(n);
            for (auto& v : x) v = normal(rng);
            const BlockAverage b = block_average(x, blocks);
            CHECK(b.blocks == blocks);
            CHECK(b.samples == n);
            ratio_sum += b.error / (2.0 / std::sqrt(static_cast<double>(n)));
        }
        CHECK(ratio_sum / trials == rel(1.0).epsilon(0.03));
    }

    TEST_CASE(
        "block averaging: correlated data get a larger error than the naive one; leftovers drop the oldest samples") {
        // AR(1) with phi = 0.9: the true standard error is sqrt((1+phi)/(1-phi)) = 4.36 times the naive one.
        std::mt19937_64 rng(11);
        std::normal_distribution<double> normal(0.0, 1.0);
        std::vector<double> x(200000);
        double y = 0;
        for (auto& v : x) {
            y = 0.9 * y + normal(rng);
            v = y;
        }
        const BlockAverage b = block_average(x, 20);
        double mean = 0, var = 0;
        for (double v : x) mean += v;
        mean /= x.size();
        for (double v : x) var += (v - mean) * (v - mean);
        const double naive = std::sqrt(var / (x.size() - 1) / x.size());
        CHECK(b.error / naive > 2.5);  // 4.36 expected, with the ~16% spread of a 20-block estimate
        const BlockAverage odd = block_average({100.0, 1.0, 2.0, 3.0, 4.0}, 2);
        CHECK(odd.samples == 4);
        CHECK(odd.mean == rel(2.5));
    }

    TEST_CASE("steady state: MSER finds the end of a transient, and none in a stationary series") {
        std::mt19937 rng(7);
        std::normal_distribution<double> noise(0.0, 1.0);
        // A stress rising linearly for 10 samples to a plateau 20 standard deviations up, then 30 noisy samples.
        std::vector<double> rising;
        for (int i = 0; i < 10; ++i) rising.push_back(2.0 * i + noise(rng));
        for (int i = 0; i < 30; ++i) rising.push_back(20.0 + noise(rng));
        const std::size_t d = mser_truncation(rising);
        CHECK(d >= 9);
        CHECK(d <= 11);
        // Stationary noise: whatever MSER drops is a few samples of chance, far less than the half it may.
        std::vector<double> steady;
        for (int i = 0; i < 40; ++i) steady.push_back(5.0 + noise(rng));
        CHECK(mser_truncation(steady) < 10);
        // A transient longer than half the series: MSER stops at the half (the rate never settled
        // within what it could judge), which the report flags as not steady before the window.
        std::vector<double> slow;
        for (int i = 0; i < 40; ++i) slow.push_back(i < 30 ? i : 30.0);
        CHECK(mser_truncation(slow) == 20);
        CHECK(mser_truncation({1.0, 2.0}) == 0);  // too short to judge
    }

    TEST_CASE("dimensionless numbers: Clausius-Mossotti contrast, magnetic stress scale and Mason number") {
        // beta: 0 for a grain like the carrier, 1 for a perfect magnet, (mu - 1) / (mu + 2) between.
        CHECK(clausius_mossotti(1.0) == 0.0);
        CHECK(clausius_mossotti(1000.0) == rel(999.0 / 1002.0));
        CHECK(clausius_mossotti(1e12) == rel(1.0).epsilon(1e-9));
        // 2 mu0 beta^2 H0^2 = 2 beta^2 B^2 / mu0: with beta = 1 and B = mu0 (H0 = 1 A/m), 2 mu0 Pa.
        CHECK(magnetic_stress_scale(1.25663706212e-6, 1.0) == rel(2 * 1.25663706212e-6));
        // The chapter-2 fluid at 600 mT: 2 (999/1002)^2 0.36 / mu0 = 569.5 kPa; the scale goes as B^2.
        const double beta = clausius_mossotti(1000.0);
        const double scale = magnetic_stress_scale(0.6, beta);
        CHECK(scale == rel(2 * beta * beta * 0.36 / 1.25663706212e-6));
        CHECK(scale == rel(5.695e5).epsilon(1e-3));
        CHECK(magnetic_stress_scale(0.3, beta) == rel(scale / 4));
        // Mn times the scale is the carrier's viscous stress: 10 mPa s at 1164 1/s is 11.64 Pa.
        const double mn = mason_number(0.010, 1164.0, 0.6, beta);
        CHECK(mn * scale == rel(11.64));
        CHECK(mason_number(0.010, 2 * 1164.0, 0.6, beta) == rel(2 * mn));
        // No field: no magnetic scale, an infinite Mason number.
        CHECK(magnetic_stress_scale(0.0, beta) == 0.0);
        CHECK(std::isinf(mason_number(0.010, 1164.0, 0.0, beta)));
    }

    TEST_CASE("steady state: a rate settling inside its window is flagged, with the strain that leaves it out") {
        // 40 samples over a strain of 2: the stress climbs for 30 samples (1.5 strain) and MSER stops at
        // the half, sample 20, i.e. 1.0 strain into the rate.
        std::vector<double> slow;
        for (int i = 0; i < 40; ++i) slow.push_back(i < 30 ? i : 30.0);
        const std::vector<double> flat_blocks(5, 30.0);
        const Settling late = settling_of(slow, 2.0, window_of(20, flat_blocks));  // the window: the last 20 samples
        CHECK(late.strain == doctest::Approx(1.0));
        CHECK(late.before_window);  // sample 20 is the window's first: steady just in time
        CHECK(late.steady());
        CHECK_FALSE(settling_of(slow, 2.0, window_of(21, flat_blocks)).before_window);
        // A plateau from the start settles at strain 0, before any window.
        const Settling flat = settling_of(std::vector<double>(40, 5.0), 2.0, window_of(40, flat_blocks));
        CHECK(flat.strain == 0.0);
        CHECK(flat.steady());
        CHECK(settling_of({}, 2.0, BlockAverage{}).steady());
        // A window rising 10, 12, ..., 18 (mean 14): the drift of 10 is significant and more than a
        // tenth of the mean, so the rate is drifting; the same rise on a mean of 140 is not material.
        std::vector<double> rise = {10.0, 12.0, 14.0, 16.0, 18.0};
        CHECK(settling_of(flat_blocks, 2.0, window_of(5, rise)).drifting);
        CHECK_FALSE(settling_of(flat_blocks, 2.0, window_of(5, rise)).steady());
        for (double& m : rise) m += 126.0;
        CHECK(settling_of(flat_blocks, 2.0, window_of(5, rise)).drift.significant);
        CHECK_FALSE(settling_of(flat_blocks, 2.0, window_of(5, rise)).drifting);
        // The advice names the key of the rate that needs it and the strain: 1.0 / (1 - 0.5) = 2.
        Settling inside;
        inside.strain = 1.0;
        inside.before_window = false;
        CHECK(unsettled_advice(ladder_length_key(0, false), inside, 1.5, 0.5) ==
              "raise /ladder/strain_first to give at least 2 strain");
        inside.strain = 0.3;
        CHECK(unsettled_advice(ladder_length_key(2, false), inside, 0.5, 0.25) ==
              "raise /ladder/strain_per_rate to give at least 0.4 strain");
        CHECK(unsettled_advice(ladder_length_key(1, true), inside, 0.5, 0.5).find("/ladder/steps_per_rate") !=
              std::string::npos);
        CHECK(unsettled_advice(ladder_length_key(0, true), inside, 0.5, 0.5).find("/ladder/steps_first") !=
              std::string::npos);
        CHECK(unsettled_advice(ladder_length_key(0, false), inside, 0.5, 1.0).find("/measure/window") !=
              std::string::npos);
        // Still drifting: no strain to read off, only that the rate's was not enough.
        Settling drifting;
        drifting.drift = {5.0, 1.0, true};
        drifting.drifting = true;
        CHECK(unsettled_advice(ladder_length_key(0, false), drifting, 0.3, 0.5) ==
              "raise /ladder/strain_first beyond 0.3 strain, until the window's stress stops drifting");
    }

    TEST_CASE("steady state: the window's drift is the line through its block means, judged by Student's t") {
        // Exact line: block means 10, 12, ..., 18 rise 2 a block, 10 over the window's 5 blocks, with no
        // residual, so no error and a significant drift.
        const Drift line = window_drift({10.0, 12.0, 14.0, 16.0, 18.0});
        CHECK(line.change == doctest::Approx(10.0));
        CHECK(line.error == doctest::Approx(0.0).epsilon(1e-12));
        CHECK(line.significant);
        // Alternating noise about a plateau: slope exactly 0 by symmetry, never significant.
        const Drift zigzag = window_drift({5.0, 6.0, 5.0, 6.0, 5.0});
        CHECK(zigzag.change == doctest::Approx(0.0).epsilon(1e-12));
        CHECK_FALSE(zigzag.significant);
        // By hand, means 0, 2, 1, 3, 2 at x = 0..4: mean 1.6, Sxx 10, Sxy 5, slope 0.5; residuals -0.6,
        // 0.9, -0.6, 0.9, -0.6, SSres 2.7, slope error sqrt(2.7 / 3 / 10) = 0.3. Over 5 blocks: 2.5 +- 1.5.
        const Drift noisy = window_drift({0.0, 2.0, 1.0, 3.0, 2.0});
        CHECK(noisy.change == doctest::Approx(2.5));
        CHECK(noisy.error == doctest::Approx(1.5));
        // t = 0.5 / 0.3 = 1.67 against 3.18 for 3 degrees of freedom: not significant.
        CHECK_FALSE(noisy.significant);
        // The same rise with a quarter of the scatter: t = 6.7, significant.
        const Drift clean = window_drift({-0.15, 0.5 + 0.225, 1.0 - 0.15, 1.5 + 0.225, 2.0 - 0.15});
        CHECK(clean.change == doctest::Approx(2.5));
        CHECK(clean.significant);
        // Two blocks cannot be judged.
        const Drift two = window_drift({1.0, 100.0});
        CHECK(two.change == 0.0);
        CHECK_FALSE(two.significant);
    }
}  // TEST_SUITE
