// The Verlet neighbour list against a brute-force O(N^2) minimum-image search: on random
// polydisperse packings with a 30:1 size ratio, in boxes periodic on all axes, on x and y only,
// and on none, the list holds exactly the pairs closer than pair_cutoff(R_i, R_j), each once,
// with the periodic image that makes them close; it still holds every touching pair after the
// grains moved by less than skin / 2 without a rebuild; and it is the same for 1 and 2 threads.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/domain.hpp"
#include "core/random.hpp"
#include "geometry/packing.hpp"
#include "geometry/region.hpp"
#include "geometry/size_distribution.hpp"
#include "neighbor/neighbor_list.hpp"
#include "particles.hpp"

namespace {

using namespace mrjam;

using PairKey = std::pair<std::uint32_t, std::uint32_t>;  // (lower index, higher index)

PairKey key(std::uint32_t a, std::uint32_t b) { return a < b ? PairKey{a, b} : PairKey{b, a}; }

// Every listed pair: its owner and its separation x_owner - x_partner + shift, as the force loop
// computes it. Fails on a pair listed twice (in either order) or a grain paired with itself.
struct Listed {
    std::uint32_t owner;
    Vec3 d;
};

std::map<PairKey, Listed> listed_pairs(const NeighborList& list, const Particles& p) {
    std::map<PairKey, Listed> out;
    REQUIRE(list.offsets.size() == p.size() + 1);
    REQUIRE(list.partners.size() == list.offsets.back());
    REQUIRE(list.image.size() == list.partners.size());
    for (std::uint32_t i = 0; i + 1 < list.offsets.size(); ++i) {
        REQUIRE(list.offsets[i] <= list.offsets[i + 1]);
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            REQUIRE(j < p.size());
            REQUIRE(j != i);
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const bool fresh = out.emplace(key(i, j), Listed{i, d}).second;
            if (!fresh) FAIL_CHECK("pair " << i << "-" << j << " is listed twice");
        }
    }
    return out;
}

// Tags each listed pair's contact history with a value of its own and marks it touching.
std::map<PairKey, double> tag_history(NeighborList& list) {
    std::map<PairKey, double> tag;
    for (std::uint32_t i = 0; i + 1 < list.offsets.size(); ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const double v = 1.0 + i + 1e-6 * list.partners[k];
            list.history[k].tangential = {v, -v, 0};
            list.touching[k] = 1;
            tag[key(i, list.partners[k])] = v;
        }
    return tag;
}

// How many listed pairs still carry their tag and touching flag; every listed pair must have been
// tagged (the rebuild lists the same pairs).
std::size_t carried_tags(const NeighborList& list, const std::map<PairKey, double>& tag) {
    std::size_t carried = 0;
    for (std::uint32_t i = 0; i + 1 < list.offsets.size(); ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const auto it = tag.find(key(i, list.partners[k]));
            REQUIRE(it != tag.end());
            if (list.touching[k] == 1 && list.history[k].tangential.x == it->second &&
                list.history[k].tangential.y == -it->second)
                ++carried;
        }
    return carried;
}

struct Mismatch {
    std::size_t missing = 0;  // closer than the cutoff (by a margin) but not listed
    std::size_t extra = 0;    // listed but farther than the cutoff (by a margin)
    std::size_t wrong_image = 0;
    std::size_t required = 0;  // pairs the brute force requires
};

// Brute-force minimum-image comparison, against the list's own cutoff or (touching_only) against
// contact, R_i + R_j. The relative margin 1e-12 keeps rounding at the boundary out of the verdict.
Mismatch compare_with_brute_force(const NeighborList& list, const Particles& p, const Domain& domain,
                                  bool touching_only = false) {
    const std::map<PairKey, Listed> listed = listed_pairs(list, p);
    Mismatch m;
    const double tol = 1e-12;
    const Vec3 len = domain.length();
    const double len_scale = std::max({len.x, len.y, len.z});
    for (std::uint32_t i = 0; i < p.size(); ++i) {
        for (std::uint32_t j = i + 1; j < p.size(); ++j) {
            const Vec3 sep = domain.separation(p.position[i], p.position[j]);  // x_j - x_i
            const double dist = norm(sep);
            const double cut = touching_only ? p.radius[i] + p.radius[j] : list.pair_cutoff(p.radius[i], p.radius[j]);
            auto it = listed.find({i, j});
            if (dist < cut * (1 - tol)) {
                ++m.required;
                if (it == listed.end()) {
                    ++m.missing;
                    continue;
                }
            }
            if (it == listed.end()) continue;
            // The listed image must be the minimum image: x_owner - x_partner + shift.
            const Vec3 d = it->second.d;
            const Vec3 expect = it->second.owner == i ? -sep : sep;
            if (norm(d - expect) > 1e-9 * len_scale) ++m.wrong_image;
            if (!touching_only && norm(d) >= list.pair_cutoff(p.radius[i], p.radius[j]) * (1 + tol)) ++m.extra;
        }
    }
    return m;
}

// The size distribution of the tests: classes from 1 to 30 um in diameter, number-weighted so
// most grains are fine and a handful (about 6 in these boxes) are 30 times larger.
SizeDistribution ratio_30_table() {
    return SizeDistribution::table({1e-6, 2e-6, 4e-6, 8e-6, 15e-6, 30e-6}, {0.7, 0.2, 0.07, 0.02, 0.007, 0.003},
                                   SizeDistribution::FrequencyBasis::number);
}

SizeDistribution ratio_30_lognormal() { return SizeDistribution::lognormal(3e-6, 0.9, 1e-6, 30e-6); }

struct Packed {
    Particles particles;
    Domain domain;
    double skin = 0;
};

Packed pack(const SizeDistribution& sizes, std::array<bool, 3> periodic, double side, double phi, std::uint64_t seed) {
    Packed out;
    out.domain.lo = {0, 0, 0};
    out.domain.hi = {side, side, side};
    out.domain.periodic = periodic;
    Rng rng(seed);
    const Region region = Region::box(out.domain.lo, out.domain.hi);
    const PackingResult r = random_packing(region, out.domain, sizes, phi, rng);
    double rsum = 0;
    for (const Sphere& s : r.spheres) {
        out.particles.add(s.centre, s.radius, 7800, 0);
        rsum += s.radius;
    }
    // The scene default: a skin of 0.1 mean diameters.
    out.skin = 0.1 * 2 * rsum / static_cast<double>(r.spheres.size());
    return out;
}

double size_ratio(const Particles& p) {
    const auto [lo, hi] = std::minmax_element(p.radius.begin(), p.radius.end());
    return *hi / *lo;
}

// min_ratio: the table distribution draws both its 1 and 30 um classes; the truncated lognormal
// spreads over [1, 30] um without reaching the ends exactly.
// Checked with the scene's default skin (0.1 mean diameters) and with a skin of 1.5 mean
// diameters, which lists many pairs that are not in contact and reaches further into the grid.
void check_list_matches_brute_force(Packed& s, const std::string& label, double min_ratio = 30 * (1 - 1e-9)) {
    CAPTURE(label);
    MESSAGE(label << ": size ratio " << size_ratio(s.particles));
    REQUIRE(size_ratio(s.particles) >= min_ratio);
    for (const double skin : {s.skin, 15 * s.skin}) {
        CAPTURE(skin);
        NeighborList list(NeighborList::Settings{skin, 1.0, true});
        list.build(s.particles, s.domain, 1);
        const Mismatch m = compare_with_brute_force(list, s.particles, s.domain);
        MESSAGE(label << ", skin " << skin << " m: " << s.particles.size() << " grains, " << list.pair_count()
                      << " listed pairs, " << m.required << " required by brute force");
        CHECK(m.required > 20);
        CHECK(m.missing == 0);
        CHECK(m.extra == 0);
        CHECK(m.wrong_image == 0);
        CHECK(list.pair_count() == m.required);
    }
}

// Moves every grain by less than skin / 2 (no rebuild is due), then checks that every pair now
// touching is still listed, with the right image. Random moves in random directions; then, as a
// harsher case from the same start, every grain moved 0.4999 skin straight at its nearest
// neighbour, which closes most gaps shorter than a skin.
void check_list_survives_small_moves(Packed& s, std::uint64_t seed, const std::string& label) {
    CAPTURE(label);
    const std::vector<Vec3> start = s.particles.position;
    for (const bool towards_nearest : {false, true}) {
        CAPTURE(towards_nearest);
        s.particles.position = start;
        NeighborList list(NeighborList::Settings{s.skin, 1.0, true});
        list.build(s.particles, s.domain, 1);
        const std::vector<Vec3> at_build = s.particles.position;
        const std::size_t n = s.particles.size();
        std::vector<Vec3> step(n);
        Rng rng(seed);
        for (std::size_t i = 0; i < n; ++i) {
            Vec3 dir{rng.normal(), rng.normal(), rng.normal()};
            double length = 0.4999 * s.skin * std::sqrt(rng.uniform());
            if (towards_nearest) {
                double best_gap = INFINITY;
                for (std::size_t j = 0; j < n; ++j) {
                    if (j == i) continue;
                    const Vec3 sep = s.domain.separation(at_build[i], at_build[j]);
                    const double gap = norm(sep) - s.particles.radius[i] - s.particles.radius[j];
                    if (gap < best_gap) {
                        best_gap = gap;
                        dir = sep;
                    }
                }
                length = 0.4999 * s.skin;
            }
            step[i] = dir * (length / norm(dir));
        }
        for (std::size_t i = 0; i < n; ++i) s.particles.position[i] += step[i];
        REQUIRE_FALSE(list.needs_rebuild(s.particles, s.domain, 1));
        const Mismatch touching = compare_with_brute_force(list, s.particles, s.domain, true);
        MESSAGE(label << std::string(towards_nearest ? ", moved towards nearest" : ", moved randomly") << ": "
                      << touching.required << " touching pairs after the moves");
        CHECK(touching.required > 10);
        CHECK(touching.missing == 0);
        CHECK(touching.wrong_image == 0);
        // A move past skin / 2 is noticed.
        s.particles.position[0] = at_build[0] + Vec3{0.5001 * s.skin, 0, 0};
        CHECK(list.needs_rebuild(s.particles, s.domain, 1));
    }
}

void check_threads_identical(Packed& s, const std::string& label) {
    CAPTURE(label);
    Particles p1 = s.particles, p2 = s.particles;
    NeighborList l1(NeighborList::Settings{s.skin, 1.0, true}), l2(NeighborList::Settings{s.skin, 1.0, true});
    l1.build(p1, s.domain, 1);
    l2.build(p2, s.domain, 2);
    CHECK(l1.offsets == l2.offsets);
    CHECK(l1.partners == l2.partners);
    CHECK(l1.image == l2.image);
    bool same_positions = true;
    for (std::size_t i = 0; i < p1.size(); ++i)
        same_positions = same_positions && p1.position[i].x == p2.position[i].x &&
                         p1.position[i].y == p2.position[i].y && p1.position[i].z == p2.position[i].z;
    CHECK(same_positions);
    // Rebuilding with 2 threads after a rebuild with 1 thread changes nothing either.
    l1.build(p1, s.domain, 2);
    CHECK(l1.partners == l2.partners);
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("neighbour list: exactly the brute-force pairs, 30:1 sizes, periodic on all axes") {
        Packed s = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.35, 11);
        check_list_matches_brute_force(s, "table, periodic xyz");
        Packed t = pack(ratio_30_lognormal(), {true, true, true}, 80e-6, 0.4, 12);
        check_list_matches_brute_force(t, "lognormal, periodic xyz", 10);
    }

    TEST_CASE("neighbour list: exactly the brute-force pairs, 30:1 sizes, periodic on x and y only") {
        Packed s = pack(ratio_30_table(), {true, true, false}, 70e-6, 0.35, 21);
        check_list_matches_brute_force(s, "table, periodic xy");
        Packed t = pack(ratio_30_lognormal(), {true, true, false}, 80e-6, 0.4, 22);
        check_list_matches_brute_force(t, "lognormal, periodic xy", 10);
    }

    TEST_CASE("neighbour list: exactly the brute-force pairs, 30:1 sizes, no periodic axis") {
        Packed s = pack(ratio_30_table(), {false, false, false}, 70e-6, 0.35, 31);
        check_list_matches_brute_force(s, "table, closed box");
        Packed t = pack(ratio_30_lognormal(), {false, false, false}, 80e-6, 0.4, 32);
        check_list_matches_brute_force(t, "lognormal, closed box", 10);
    }

    TEST_CASE("neighbour list: grains outside a closed box and wrapped across periodic faces") {
        // Grains that drifted out of a closed box are binned in the edge cells; grains far outside
        // a periodic box are wrapped in at build. Both must keep their pairs.
        Packed s = pack(ratio_30_table(), {true, false, true}, 70e-6, 0.3, 41);
        Rng rng(42);
        for (Vec3& x : s.particles.position) {
            if (rng.uniform() < 0.1) x.x += 70e-6 * std::floor(rng.uniform(-3, 3));  // whole periods
            if (x.y < 5e-6) x.y -= 3e-6;  // out of the closed side, as a grain against a wall may be
        }
        check_list_matches_brute_force(s, "periodic xz, grains outside");
        for (const Vec3& x : s.particles.position) {
            CHECK(x.x >= 0);
            CHECK(x.x < 70e-6);
        }
    }

    TEST_CASE("neighbour list: every touching pair stays listed after moves shorter than skin / 2") {
        Packed a = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.5, 51);
        check_list_survives_small_moves(a, 52, "periodic xyz");
        Packed b = pack(ratio_30_lognormal(), {true, true, false}, 80e-6, 0.5, 53);
        check_list_survives_small_moves(b, 54, "periodic xy");
        Packed c = pack(ratio_30_table(), {false, false, false}, 70e-6, 0.5, 55);
        check_list_survives_small_moves(c, 56, "closed box");
    }

    TEST_CASE("neighbour list: the same list for 1 and 2 threads") {
        Packed a = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.35, 61);
        check_threads_identical(a, "periodic xyz");
        Packed b = pack(ratio_30_lognormal(), {true, true, false}, 80e-6, 0.4, 62);
        check_threads_identical(b, "periodic xy");
        Packed c = pack(ratio_30_table(), {false, false, false}, 70e-6, 0.35, 63);
        check_threads_identical(c, "closed box");
    }

    TEST_CASE("neighbour list: contact history follows its pair across a rebuild") {
        Packed s = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.3, 71);
        NeighborList list(NeighborList::Settings{s.skin, 1.0, true});
        list.build(s.particles, s.domain, 2);
        const std::map<PairKey, double> tag = tag_history(list);
        list.build(s.particles, s.domain, 1);  // same positions: the same pairs
        const std::size_t carried = carried_tags(list, tag);
        CHECK(carried == list.pair_count());
    }

    // The contact list filtered from the magnetic range (build_within) against a grid build of the
    // same list: the same pairs with the same owners and images, for 1 and 2 threads, history carried.
    void check_filtered_matches_grid(Packed & s, const std::string& label) {
        CAPTURE(label);
        // Reach 1.1 (R_i + R_j) + 1 um: as wide as the 70 um periodic box allows for 30 um grains.
        NeighborList wide(NeighborList::Settings{s.skin, 1.1, false, 1e-6});
        wide.build(s.particles, s.domain, 1);
        CHECK(wide.pair_count() > 0);
        CHECK(wide.history.empty());  // a list without history stores none
        CHECK(wide.touching.empty());
        NeighborList grid(NeighborList::Settings{s.skin, 1.0, true});
        grid.build(s.particles, s.domain, 1);
        const std::map<PairKey, Listed> expected = listed_pairs(grid, s.particles);
        REQUIRE(expected.size() > 20);
        for (const int threads : {1, 2}) {
            CAPTURE(threads);
            NeighborList filtered(NeighborList::Settings{s.skin, 1.0, true});
            filtered.build_within(wide, s.particles, s.domain, threads);
            const std::map<PairKey, Listed> got = listed_pairs(filtered, s.particles);
            CHECK(got.size() == expected.size());
            std::size_t same = 0;
            for (const auto& [k, v] : got) {
                const auto it = expected.find(k);
                if (it != expected.end() && it->second.owner == v.owner && norm(it->second.d - v.d) == 0) ++same;
            }
            CHECK(same == expected.size());
            CHECK(filtered.history.size() == filtered.pair_count());
            // History carried across a filtered rebuild at the same positions.
            const std::map<PairKey, double> tag = tag_history(filtered);
            filtered.build_within(wide, s.particles, s.domain, threads);
            const std::size_t carried = carried_tags(filtered, tag);
            CHECK(carried == filtered.pair_count());
        }
    }

    TEST_CASE("neighbour list: the contacts filtered from a wider list are exactly the grid build's") {
        Packed a = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.35, 81);
        check_filtered_matches_grid(a, "periodic xyz");
        Packed b = pack(ratio_30_lognormal(), {true, true, false}, 80e-6, 0.4, 82);
        check_filtered_matches_grid(b, "periodic xy");
        Packed c = pack(ratio_30_table(), {false, false, false}, 70e-6, 0.35, 83);
        check_filtered_matches_grid(c, "closed box");
    }

    // A range beyond contact capped at a multiple of R_i + R_j (a magnetic cutoff of "diameters" with
    // "beyond_contact"): fine pairs reach the cap, coarse ones the length beyond contact; the list
    // holds exactly the brute-force pairs at that range, fewer than without the cap, and the
    // contacts filtered from it are the grid build's.
    TEST_CASE("neighbour list: a range beyond contact capped in pair diameters") {
        Packed s = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.35, 85);
        const NeighborList::Settings capped_settings{s.skin, 1.0, false, 3e-6, 2.0};
        NeighborList capped(capped_settings);
        // 1 um grains: 2 x (R_i + R_j) = 2 um, under 1 um + 3 um; 30 um grains: 30 + 3 um, under 60 um.
        CHECK(capped.interaction_range(0.5e-6, 0.5e-6) == doctest::Approx(2e-6).epsilon(1e-12));
        CHECK(capped.interaction_range(15e-6, 15e-6) == doctest::Approx(33e-6).epsilon(1e-12));
        CHECK(capped.interaction_range(0.5e-6, 15e-6) == doctest::Approx(18.5e-6).epsilon(1e-12));
        capped.build(s.particles, s.domain, 1);
        const Mismatch m = compare_with_brute_force(capped, s.particles, s.domain);
        CHECK(m.required > 100);
        CHECK(m.missing == 0);
        CHECK(m.extra == 0);
        CHECK(m.wrong_image == 0);
        NeighborList uncapped(NeighborList::Settings{s.skin, 1.0, false, 3e-6});
        uncapped.build(s.particles, s.domain, 1);
        MESSAGE("capped at 2 pair diameters: " << capped.pair_count()
                                               << " pairs; 3 um beyond contact alone: " << uncapped.pair_count());
        // The cap shortens every pair whose R_i + R_j is under 3 um, most of them: the fine classes
        // hold 90 % of the grains (2,376 pairs against 4,038 when written).
        CHECK(capped.pair_count() < 0.8 * uncapped.pair_count());
        NeighborList contacts(NeighborList::Settings{s.skin, 1.0, true});
        REQUIRE(contacts.fits_within(capped));
        contacts.build_within(capped, s.particles, s.domain, 1);
        NeighborList grid(NeighborList::Settings{s.skin, 1.0, true});
        grid.build(s.particles, s.domain, 1);
        CHECK(contacts.pair_count() == grid.pair_count());
        CHECK(compare_with_brute_force(contacts, s.particles, s.domain).missing == 0);
        // A cap below contact cannot hold the contacts; nor can a capped list hold an uncapped one.
        CHECK_FALSE(contacts.fits_within(NeighborList(NeighborList::Settings{s.skin, 1.0, false, 3e-6, 0.9})));
        CHECK_FALSE(uncapped.fits_within(capped));
        CHECK(capped.fits_within(uncapped));
    }

    TEST_CASE("neighbour list: filtering from a list that cannot hold every pair is refused") {
        Packed s = pack(ratio_30_table(), {true, true, true}, 70e-6, 0.35, 84);
        NeighborList target(NeighborList::Settings{s.skin, 1.0, true});
        NeighborList other_skin(NeighborList::Settings{2 * s.skin, 1.1, false});
        other_skin.build(s.particles, s.domain, 1);
        CHECK_THROWS_AS(target.build_within(other_skin, s.particles, s.domain, 1), std::logic_error);
        NeighborList shorter(NeighborList::Settings{s.skin, 0.5, false});
        shorter.build(s.particles, s.domain, 1);
        CHECK_THROWS_AS(target.build_within(shorter, s.particles, s.domain, 1), std::logic_error);
        NeighborList wide(NeighborList::Settings{s.skin, 1.1, false});
        wide.build(s.particles, s.domain, 1);
        s.particles.position[3].x += 0.1 * s.skin;  // the grains moved since the wide list was built
        CHECK_THROWS_AS(target.build_within(wide, s.particles, s.domain, 1), std::logic_error);
    }

    TEST_CASE("neighbour list: a periodic box shorter than twice the cutoff is refused") {
        Particles p;
        p.add({1, 1, 1}, 1.0, 1000, 0);
        p.add({3, 1, 1}, 0.5, 1000, 0);
        Domain d;
        d.lo = {0, 0, 0};
        d.hi = {4, 10, 10};
        d.periodic = {true, false, false};
        NeighborList list(NeighborList::Settings{0.1, 1.0, true});
        CHECK_THROWS_AS(list.build(p, d, 1), std::runtime_error);
    }

    // Size ratios beyond ~40:1 in a box many cells long: the largest grain's stencil spans more than
    // 64 cells along an axis. Regression test: NeighborList::build once kept at most 64 cells per axis
    // (fixed-size arrays in AxisRange), so the stencil of a big grain was cut short and some of its
    // partners were never listed (238 of 267 at 50:1; 143 of 145 at 36:1 in a minimal periodic box).
    // One coarse grain among fine ones on a lattice; its pairs are checked against brute force.
    TEST_CASE("neighbour list: the stencil of a grain 36 to 50 times the mean size is not truncated") {
        struct Case {
            double big_radius, box_x, centre_x;
            bool periodic_x;
        };
        for (const Case c : {Case{50, 400, 200, false}, Case{40, 161.4, 10, true}, Case{36, 146, 5, true}}) {
            CAPTURE(c.big_radius);
            CAPTURE(c.periodic_x);
            Particles p;
            Domain d;
            d.lo = {0, 0, 0};
            d.hi = {c.box_x, 2 * c.big_radius + 10, 2 * c.big_radius + 10};
            d.periodic = {c.periodic_x, false, false};
            const Vec3 centre{c.centre_x, c.big_radius + 5, c.big_radius + 5};
            p.add(centre, c.big_radius, 1000, 0);
            for (double x = 1.2; x < d.hi.x - 1; x += 2.5)
                for (double y = 1.2; y < d.hi.y - 1; y += 2.5)
                    for (double z = 1.2; z < d.hi.z - 1; z += 2.5) {
                        const Vec3 q{x, y, z};
                        if (norm(d.separation(centre, q)) < c.big_radius + 1.05) continue;
                        p.add(q, 1.0, 1000, 0);
                    }
            NeighborList list(NeighborList::Settings{0.2, 1.0, true});
            list.build(p, d, 1);
            std::size_t listed = list.offsets[1] - list.offsets[0], brute = 0;
            for (std::size_t j = 1; j < p.size(); ++j)
                if (norm(d.separation(p.position[0], p.position[j])) < list.pair_cutoff(c.big_radius, 1.0)) ++brute;
            CHECK(brute > 100);
            CHECK(listed == brute);
        }
    }

}  // TEST_SUITE
