// Size distributions, insertion regions and initial packings (geometry/).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

#include "geometry/packing.hpp"
#include "geometry/region.hpp"
#include "geometry/size_distribution.hpp"
#include "rel_approx.hpp"

using mrjam_test::rel;

using namespace mrjam;

namespace {

constexpr double kPi = 3.14159265358979323846;
using Basis = SizeDistribution::FrequencyBasis;

double sphere_volume(double d) { return kPi / 6.0 * d * d * d; }

// Worst overlap / smaller radius over ALL pairs, by brute force with minimum image: an
// independent check of the packer's grid search.
double brute_force_max_overlap(const std::vector<Sphere>& s, const Domain& domain) {
    double worst = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i)
        for (std::size_t j = 0; j < i; ++j) {
            const double gap = norm(domain.separation(s[i].centre, s[j].centre)) - s[i].radius - s[j].radius;
            if (gap < 0.0) worst = std::max(worst, -gap / std::min(s[i].radius, s[j].radius));
        }
    return worst;
}

double solid_volume(const std::vector<Sphere>& s) {
    double v = 0.0;
    for (const auto& x : s) v += sphere_volume(2.0 * x.radius);
    return v;
}

Domain periodic_cube(double L) {
    Domain d;
    d.lo = {0, 0, 0};
    d.hi = {L, L, L};
    d.periodic = {true, true, true};
    return d;
}

// Periodic cube that holds about n grains of `sizes` at volume fraction phi.
Domain cube_for(const SizeDistribution& sizes, int n, double phi) {
    return periodic_cube(std::cbrt(n * sizes.mean_particle_volume() / phi));
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("size table: volume frequencies convert to number frequencies n_i ~ f_i / d_i^3") {
        // Equal volume in 100 um and 200 um grains: 8 small grains per large one -> 8/9, 1/9.
        const auto two = SizeDistribution::table({100e-6, 200e-6}, {0.5, 0.5}, Basis::volume);
        const auto c2 = two.discrete_classes();
        REQUIRE(c2.size() == 2);
        CHECK(c2[0].number_fraction == rel(8.0 / 9.0).epsilon(1e-12));
        CHECK(c2[1].number_fraction == rel(1.0 / 9.0).epsilon(1e-12));

        // Unnormalised volume shares 1:1:2 at 1, 2, 4 um: counts 1 : 1/8 : 2/64, sum 37/32.
        const auto three = SizeDistribution::table({1e-6, 2e-6, 4e-6}, {1, 1, 2}, Basis::volume);
        const auto c3 = three.discrete_classes();
        CHECK(c3[0].number_fraction == rel(32.0 / 37.0).epsilon(1e-12));
        CHECK(c3[1].number_fraction == rel(4.0 / 37.0).epsilon(1e-12));
        CHECK(c3[2].number_fraction == rel(1.0 / 37.0).epsilon(1e-12));
        // Mean diameter (32*1 + 4*2 + 1*4)/37 um = 44/37 um.
        CHECK(three.mean_diameter_number() == rel(44.0 / 37.0 * 1e-6).epsilon(1e-12));

        // Number basis is only normalised: 2:6 -> 1/4, 3/4; mean volume by hand.
        const auto num = SizeDistribution::table({1e-3, 2e-3}, {2, 6}, Basis::number);
        const auto cn = num.discrete_classes();
        CHECK(cn[0].number_fraction == rel(0.25));
        CHECK(cn[1].number_fraction == rel(0.75));
        CHECK(num.mean_particle_volume() ==
              rel(0.25 * sphere_volume(1e-3) + 0.75 * sphere_volume(2e-3)).epsilon(1e-12));
        CHECK(num.min_diameter() == 1e-3);
        CHECK(num.max_diameter() == 2e-3);

        // Empty classes at the tails of a laser-diffraction table are dropped.
        const auto tails = SizeDistribution::table({1e-6, 2e-6, 4e-6, 8e-6}, {0, 3, 1, 0}, Basis::volume);
        CHECK(tails.min_diameter() == 2e-6);
        CHECK(tails.max_diameter() == 4e-6);
    }

    TEST_CASE("size table: bad tables are refused") {
        CHECK_THROWS_AS(SizeDistribution::table({}, {}, Basis::number), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::table({1e-3, 2e-3}, {1}, Basis::volume), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::table({1e-3, 0.0}, {1, 1}, Basis::volume), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::table({1e-3, -2e-3}, {1, 1}, Basis::number), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::table({1e-3, 2e-3}, {1, -1}, Basis::number), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::table({1e-3, 2e-3}, {0, 0}, Basis::volume), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::single(0.0), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::lognormal(1e-3, 0.5, 2e-3, 1e-3), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::lognormal(1e-3, 0.0, 1e-4, 1e-2), std::invalid_argument);
        // Window far in the tail: rejection would almost never accept.
        CHECK_THROWS_AS(SizeDistribution::lognormal(1e-3, 0.1, 1e-2, 2e-2), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::mixture({}), std::invalid_argument);
        CHECK_THROWS_AS(SizeDistribution::mixture({{SizeDistribution::single(1e-3), -1.0}}), std::invalid_argument);
    }

    TEST_CASE("size table: sample mean matches the exact number-weighted mean") {
        const auto t = SizeDistribution::table({50e-6, 100e-6, 200e-6, 400e-6}, {5, 20, 40, 35}, Basis::volume);
        double mean = 0.0, second = 0.0;
        for (const auto& c : t.discrete_classes()) {
            mean += c.number_fraction * c.diameter;
            second += c.number_fraction * c.diameter * c.diameter;
        }
        CHECK(t.mean_diameter_number() == rel(mean).epsilon(1e-12));

        // By the central limit theorem the sample mean of n draws is normal with standard error
        // sqrt(var / n); 5 standard errors is exceeded with probability ~6e-7, so a failure means a
        // biased sampler, not bad luck (and the seed makes the outcome fixed anyway).
        const int n = 200000;
        Rng rng(42);
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += t.sample(rng);
        const double standard_error = std::sqrt((second - mean * mean) / n);
        CHECK(std::abs(sum / n - mean) < 5.0 * standard_error);
    }

    TEST_CASE("lognormal: sample median, moments and reproducibility") {
        const double median = 300e-6, sigma = 0.4;
        // Truncation symmetric in ln d keeps the median where it was.
        const auto ln =
            SizeDistribution::lognormal(median, sigma, median * std::exp(-2.5 * sigma), median * std::exp(2.5 * sigma));
        const int n = 20001;
        Rng rng(7);
        std::vector<double> logs(n);
        for (auto& x : logs) x = std::log(ln.sample(rng));
        std::nth_element(logs.begin(), logs.begin() + n / 2, logs.end());
        // The sample median has standard error 1 / (2 f(m) sqrt(n)), f the density of ln d at the
        // median: phi(0) / (sigma * P) with P the mass kept by truncation. Allow 5 of them.
        const double kept = std::erf(2.5 / std::sqrt(2.0));
        const double f_median = 1.0 / std::sqrt(2.0 * kPi) / (sigma * kept);
        const double standard_error = 1.0 / (2.0 * f_median * std::sqrt(double(n)));
        CHECK(std::abs(logs[n / 2] - std::log(median)) < 5.0 * standard_error);

        // Mean grain volume (closed form) against Simpson quadrature of the truncated pdf in ln d.
        const auto skew = SizeDistribution::lognormal(median, 0.8, 50e-6, 2e-3);
        const double a = std::log(50e-6), b = std::log(2e-3);
        const int m = 4000;  // even
        double mass = 0.0, vol = 0.0, dia = 0.0;
        for (int i = 0; i <= m; ++i) {
            const double x = a + (b - a) * i / m;
            const double z = (x - std::log(median)) / 0.8;
            const double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            const double pdf = w * std::exp(-0.5 * z * z);
            mass += pdf;
            vol += pdf * sphere_volume(std::exp(x));
            dia += pdf * std::exp(x);
        }
        CHECK(skew.mean_particle_volume() == rel(vol / mass).epsilon(1e-8));
        CHECK(skew.mean_diameter_number() == rel(dia / mass).epsilon(1e-8));
        CHECK(skew.min_diameter() == 50e-6);
        CHECK(skew.max_diameter() == 2e-3);

        // Same seed, same grains; another seed, other grains.
        Rng r1(99), r2(99), r3(100);
        const auto g1 = skew.sample_for_volume(1e-6, r1);
        const auto g2 = skew.sample_for_volume(1e-6, r2);
        const auto g3 = skew.sample_for_volume(1e-6, r3);
        CHECK(g1 == g2);
        CHECK(g1 != g3);
        for (double d : g1) CHECK((d >= 50e-6 && d <= 2e-3));
    }

    TEST_CASE("sample_for_volume: reaches the target to half a grain, largest first") {
        const auto t = SizeDistribution::table({100e-6, 300e-6, 1e-3}, {1, 1, 1}, Basis::volume);
        Rng rng(3);
        const double target = 2e-6;
        const auto grains = t.sample_for_volume(target, rng);
        double total = 0.0;
        for (double d : grains) total += sphere_volume(d);
        // The last draw is kept only if that brings the total closer, so the miss is at most half of
        // one grain's volume.
        CHECK(std::abs(total - target) <= 0.5 * sphere_volume(1e-3));
        CHECK(std::is_sorted(grains.begin(), grains.end(), std::greater<>()));
        CHECK(t.sample_for_volume(0.0, rng).empty());
        CHECK_THROWS_AS(t.sample_for_volume(-1.0, rng), std::invalid_argument);
    }

    TEST_CASE("mixture: parts weighted by solid volume") {
        // 33:67 by volume of 100 um fines and 200 um coarse grains: fines per coarse grain
        // = (0.33 / 1^3) / (0.67 / 2^3) = 3.9403...
        const auto mix = SizeDistribution::mixture(
            {{SizeDistribution::single(100e-6), 33.0}, {SizeDistribution::single(200e-6), 67.0}});
        const double ratio = 0.33 * 8.0 / 0.67;
        const auto c = mix.discrete_classes();
        REQUIRE(c.size() == 2);
        CHECK(c[0].diameter == 100e-6);
        CHECK(c[0].number_fraction == rel(ratio / (1.0 + ratio)).epsilon(1e-12));

        // Drawn grains carry the volume shares. ~95000 grains, 80% fines by number: the fine volume
        // share has standard deviation s(1-s)/sqrt(N p(1-p)) ~ 0.0018, so 3% of 0.33 is 5.5 of them.
        Rng rng(11);
        double fine = 0.0, total = 0.0;
        for (double d : mix.sample_for_volume(1.2e-7, rng)) {
            total += sphere_volume(d);
            if (d < 150e-6) fine += sphere_volume(d);
        }
        CHECK(fine / total == rel(0.33).epsilon(0.03));

        // A lognormal part is kept exact: a mixture of one part is that part.
        const auto ln = SizeDistribution::lognormal(1e-3, 0.5, 2e-4, 5e-3);
        const auto alone = SizeDistribution::mixture({{ln, 1.0}});
        CHECK(alone.mean_particle_volume() == rel(ln.mean_particle_volume()).epsilon(1e-12));
        const auto both = SizeDistribution::mixture({{ln, 1.0}, {SizeDistribution::single(1e-4), 1.0}});
        CHECK(both.min_diameter() == 1e-4);
        CHECK(both.max_diameter() == 5e-3);
        CHECK_FALSE(both.is_discrete());
        CHECK_THROWS_AS(both.discrete_classes(), std::logic_error);
    }

    TEST_CASE("region: volume, containment, sampling, periodic spanning") {
        const Domain closed = [] {
            Domain d;
            d.lo = {0, 0, 0};
            d.hi = {1, 1, 1};
            return d;
        }();
        const auto box = Region::box({0, 0, 0}, {1, 2, 3});
        CHECK(box.volume() == rel(6.0));
        CHECK(box.contains_sphere({0.5, 0.5, 0.5}, 0.5, closed));
        CHECK_FALSE(box.contains_sphere({0.4, 0.5, 0.5}, 0.5, closed));

        const auto tube = Region::cylinder({0, 0, 1}, 2, 0.5, 2.0);  // valve tube along z
        CHECK(tube.volume() == rel(kPi * 0.25 * 2.0));
        CHECK(tube.contains_sphere({0.3, 0, 1.5}, 0.2, closed));
        CHECK_FALSE(tube.contains_sphere({0.3, 0.1, 1.5}, 0.2, closed));
        CHECK_FALSE(tube.contains_sphere({0, 0, 1.1}, 0.2, closed));
        Rng rng(5);
        for (int i = 0; i < 1000; ++i) {
            CHECK(tube.contains_sphere(tube.sample_centre(0.1, rng), 0.1, closed));
            CHECK(box.contains_sphere(box.sample_centre(0.3, rng), 0.3, closed));
        }
        CHECK_THROWS_AS(tube.sample_centre(0.6, rng), std::invalid_argument);

        // On a periodic axis a full-span box does not clip; a partial one does.
        const Domain per = periodic_cube(1.0);
        const auto full = Region::box({0, 0, 0}, {1, 1, 1});
        CHECK(full.contains_sphere({0.01, 0.99, 0.5}, 0.1, per));
        CHECK_FALSE(full.contains_sphere({0.01, 0.5, 0.5}, 0.1, closed));
        const auto half = Region::box({0, 0, 0}, {0.5, 1, 1});
        CHECK_FALSE(half.contains_sphere({0.01, 0.5, 0.5}, 0.1, per));
        CHECK(half.volume(per) == rel(0.5));
        CHECK_THROWS_AS(Region::box({0, 0, 0}, {1, 0, 1}), std::invalid_argument);
        CHECK_THROWS_AS(Region::cylinder({0, 0, 0}, 3, 1, 1), std::invalid_argument);
    }

    TEST_CASE("random_packing: 0.6 monodisperse in a periodic box") {
        const auto mono = SizeDistribution::single(1e-3);
        const Domain domain = cube_for(mono, 2000, 0.6);
        const auto region = Region::box(domain.lo, domain.hi);
        Rng rng(2024);
        const PackingResult r = random_packing(region, domain, mono, 0.6, rng);
        CHECK(r.spheres.size() == 2000);
        CHECK(r.achieved_volume_fraction == rel(0.6).epsilon(0.02));
        CHECK(solid_volume(r.spheres) / region.volume() == rel(r.achieved_volume_fraction));
        const double worst = brute_force_max_overlap(r.spheres, domain);
        CHECK(worst <= 1e-3);
        CHECK(worst == rel(r.max_overlap_ratio).epsilon(1e-9));
    }

    TEST_CASE("random_packing: 30:1 polydisperse in a periodic box") {
        // Mostly 0.1 mm fines with 3 mm lumps by number: the lumps hold most of the volume.
        const auto bimodal = SizeDistribution::table({1e-4, 3e-3}, {1900, 100}, Basis::number);
        const Domain domain = cube_for(bimodal, 2000, 0.3);
        const auto region = Region::box(domain.lo, domain.hi);
        Rng rng(8);
        const PackingResult r = random_packing(region, domain, bimodal, 0.3, rng);
        CHECK(r.achieved_volume_fraction == rel(0.3).epsilon(0.02));
        CHECK(brute_force_max_overlap(r.spheres, domain) <= 1e-3);
        CHECK(r.spheres.front().radius / r.spheres.back().radius == rel(30.0));

        // A continuous 30:1 spread, dense enough that relaxation has work to do.
        const auto ln = SizeDistribution::lognormal(3e-4, 1.0, 1e-4, 3e-3);
        const Domain d2 = cube_for(ln, 2000, 0.55);
        Rng rng2(9);
        const PackingResult r2 = random_packing(Region::box(d2.lo, d2.hi), d2, ln, 0.55, rng2);
        CHECK(r2.achieved_volume_fraction == rel(0.55).epsilon(0.02));
        CHECK(brute_force_max_overlap(r2.spheres, d2) <= 1e-3);
    }

    TEST_CASE("random_packing: walled valve tube keeps grains inside") {
        const auto sizes = SizeDistribution::table({5e-4, 1e-3, 2e-3}, {10, 30, 60}, Basis::volume);
        Domain domain;
        domain.lo = {-0.01, -0.01, 0};
        domain.hi = {0.01, 0.01, 0.02};
        const auto tube = Region::cylinder({0, 0, 0.005}, 2, 0.005, 0.012);
        Rng rng(31);
        const PackingResult r = random_packing(tube, domain, sizes, 0.5, rng);
        CHECK(r.achieved_volume_fraction == rel(0.5).epsilon(0.03));
        for (const auto& s : r.spheres) CHECK(tube.contains_sphere(s.centre, s.radius, domain));
        CHECK(brute_force_max_overlap(r.spheres, domain) <= 1e-3);
    }

    TEST_CASE("random_packing: reproducible and refuses impossible fractions") {
        const auto mono = SizeDistribution::single(1e-3);
        const Domain domain = cube_for(mono, 300, 0.5);
        const auto region = Region::box(domain.lo, domain.hi);
        Rng a(1), b(1);
        const auto ra = random_packing(region, domain, mono, 0.5, a);
        const auto rb = random_packing(region, domain, mono, 0.5, b);
        REQUIRE(ra.spheres.size() == rb.spheres.size());
        bool same = true;
        for (std::size_t i = 0; i < ra.spheres.size(); ++i)
            same = same && norm2(ra.spheres[i].centre - rb.spheres[i].centre) == 0.0;
        CHECK(same);

        Rng rng(1);
        CHECK_THROWS_AS(random_packing(region, domain, mono, 0.7, rng), std::invalid_argument);
        CHECK_THROWS_AS(random_packing(region, domain, mono, 0.0, rng), std::invalid_argument);
        PackingOptions few;
        few.max_sweeps = 3;
        CHECK_THROWS_AS(random_packing(region, domain, mono, 0.64, rng, few), std::runtime_error);
        // Grain larger than the region.
        CHECK_THROWS_AS(random_packing(Region::box({0, 0, 0}, {5e-4, 1, 1}), Domain{}, mono, 0.3, rng),
                        std::invalid_argument);
    }

    TEST_CASE("lattice_packing: counts and spacing") {
        Domain closed;
        closed.lo = {0, 0, 0};
        closed.hi = {10, 10, 10};
        const auto cube = Region::box(closed.lo, closed.hi);
        // Simple cubic, touching spheres of d = 1 in a 10 cube: 10 per edge.
        CHECK(lattice_packing(cube, closed, 1.0, 1.0, "cubic").size() == 1000);
        // Spacing 1.5: centres at 0.5, 2.0, ..., 9.5 -> 7 per edge.
        CHECK(lattice_packing(cube, closed, 1.0, 1.5, "cubic").size() == 343);

        // Periodic fcc: cubic cell sqrt(2), 7 cells per edge, 4 sites each; no image closer than 1.
        const Domain per = periodic_cube(10.0);
        const auto fcc = lattice_packing(cube, per, 1.0, 1.0, "fcc");
        CHECK(fcc.size() == 7 * 7 * 7 * 4);
        double closest = 1e9;
        for (std::size_t i = 0; i < fcc.size(); ++i)
            for (std::size_t j = 0; j < i; ++j)
                closest = std::min(closest, norm(per.separation(fcc[i].centre, fcc[j].centre)));
        CHECK(closest == rel(1.0));

        for (const auto& s : lattice_packing(cube, closed, 1.0, 1.0, "hcp"))
            CHECK(cube.contains_sphere(s.centre, s.radius, closed));
        CHECK_THROWS_AS(lattice_packing(cube, closed, 1.0, 0.9, "cubic"), std::invalid_argument);
        CHECK_THROWS_AS(lattice_packing(cube, closed, 1.0, 1.0, "diamond"), std::invalid_argument);
    }

}  // TEST_SUITE
