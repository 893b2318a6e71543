// Lees-Edwards (sliding periodic) boundaries: the neighbour list against a brute-force search
// through the sliding images, a contact straddling the sheared boundary against Hertz, a grain
// advected across the boundary keeping its peculiar velocity, and momentum conservation of the
// whole periodic system (up to the exact +-m V the wrap gives a grain crossing z).
#include <doctest/doctest.h>

#include <cmath>
#include <map>
#include <tuple>
#include <utility>

#include "core/random.hpp"
#include "geometry/packing.hpp"
#include "geometry/region.hpp"
#include "geometry/size_distribution.hpp"
#include "integrator.hpp"
#include "neighbor/neighbor_list.hpp"
#include "rel_approx.hpp"
#include "scene/scene.hpp"
#include "shear/shear_stress.hpp"

using mrjam_test::rel;

using namespace mrjam;
using json = nlohmann::json;

namespace {

constexpr double kBox = 40e-6;

json iron() {
    return {{"name", "iron"},         {"density", 7800},    {"youngs_modulus", 1e9},
            {"poisson_ratio", 0.278}, {"restitution", 0.1}, {"friction", 0.3}};
}

// Grains of one size at the given centres in a box periodic on all axes, switched to
// Lees-Edwards with the given offset and image velocity; `viscosity` 0: no fluid.
Scene sliding_box(const json& positions, double diameter, double viscosity, double offset, double image_velocity,
                  const Vec3& velocity = {}) {
    json scene = {{"domain", {{"lo", {0, 0, 0}}, {"hi", {kBox, kBox, kBox}}, {"periodic", "xyz"}}},
                  {"materials", {iron()}},
                  {"grains",
                   {{{"size", {{"distribution", "single"}, {"diameter", diameter}}},
                     {"velocity", {velocity.x, velocity.y, velocity.z}},
                     {"placement", {{"method", "list"}, {"positions", positions}}}}}},
                  {"run", {{"steps", 0}}}};
    if (viscosity > 0) scene["fluid"] = {{"viscosity", viscosity}};
    Scene s = build_scene(scene, BuildOptions{});
    s.system.domain.lees_edwards = true;
    s.system.domain.shear_offset = offset;
    s.system.domain.shear_velocity = image_velocity;
    choose_timestep(s);
    return s;
}

std::size_t grain_near(const System& s, const Vec3& x) {
    for (std::size_t i = 0; i < s.particles.size(); ++i)
        if (norm(s.particles.position[i] - x) < 1e-12) return i;
    FAIL("no grain at " << x.x << ", " << x.y << ", " << x.z);
    return 0;
}

// Every listed pair keyed by (lower, higher) index with x_owner - x_partner + shift.
std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, Vec3>> listed(const NeighborList& list,
                                                                                         const Particles& p) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, Vec3>> out;
    for (std::uint32_t i = 0; i + 1 < list.offsets.size(); ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            const auto key = i < j ? std::make_pair(i, j) : std::make_pair(j, i);
            const bool fresh =
                out.emplace(key, std::make_pair(i, p.position[i] - p.position[j] + list.image_shift(list.image[k])))
                    .second;
            if (!fresh) FAIL_CHECK("pair " << i << "-" << j << " listed twice");
        }
    return out;
}

// Counts pairs closer than `reach(i, j)` by the Lees-Edwards minimum image (Domain::separation)
// that the list misses or lists with another image.
struct Mismatch {
    std::size_t required = 0, missing = 0, wrong_image = 0;
};
template <class Reach>
Mismatch compare(const NeighborList& list, const Particles& p, const Domain& d, Reach reach) {
    const auto pairs = listed(list, p);
    Mismatch m;
    for (std::uint32_t i = 0; i < p.size(); ++i)
        for (std::uint32_t j = i + 1; j < p.size(); ++j) {
            const Vec3 sep = d.separation(p.position[i], p.position[j]);  // x_j - x_i
            if (norm(sep) >= reach(i, j) * (1 - 1e-12)) continue;
            ++m.required;
            const auto it = pairs.find({i, j});
            if (it == pairs.end()) {
                ++m.missing;
                continue;
            }
            const Vec3 expect = it->second.first == i ? -sep : sep;
            if (norm(it->second.second - expect) > 1e-9 * kBox) ++m.wrong_image;
        }
    return m;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("lees-edwards: the neighbour list holds exactly the brute-force pairs through the sliding images") {
        // A polydisperse packing (1 to 12 um) in a periodic 60 um box; the list is built at several
        // offsets, including the half period, and compared with a brute-force minimum image that
        // picks the z image first and shifts x by the offset.
        Domain d;
        d.lo = {0, 0, 0};
        d.hi = {60e-6, 50e-6, 55e-6};
        d.periodic = {true, true, true};
        Rng rng(7);
        const auto sizes = SizeDistribution::table({1e-6, 3e-6, 6e-6, 12e-6}, {0.5, 0.3, 0.15, 0.05},
                                                   SizeDistribution::FrequencyBasis::number);
        const PackingResult packed = random_packing(Region::box(d.lo, d.hi), d, sizes, 0.35, rng);
        d.lees_edwards = true;
        for (const double fraction : {0.0, 0.37, -0.5, 0.123, 0.49999}) {
            CAPTURE(fraction);
            Particles p;
            for (const Sphere& s : packed.spheres) p.add(s.centre, s.radius, 7800, 0);
            d.shear_offset = fraction * d.length().x;
            for (const double skin : {0.3e-6, 6e-6}) {
                CAPTURE(skin);
                NeighborList list(NeighborList::Settings{skin, 1.0, true});
                list.build(p, d, 1);
                const Mismatch m = compare(list, p, d, [&](std::uint32_t i, std::uint32_t j) {
                    return list.pair_cutoff(p.radius[i], p.radius[j]);
                });
                CHECK(m.required > 50);
                CHECK(m.missing == 0);
                CHECK(m.wrong_image == 0);
                CHECK(list.pair_count() == m.required);
            }
        }
    }

    TEST_CASE("lees-edwards: touching pairs stay listed while moves and the offset's change fit in the skin") {
        // 2 max|move| + |offset change| < skin: no rebuild is due, and every pair that touches after
        // the moves and the slide is listed with the image that makes it touch. Past the skin the list
        // asks for a rebuild.
        Domain d;
        d.lo = {0, 0, 0};
        d.hi = {50e-6, 50e-6, 50e-6};
        d.periodic = {true, true, true};
        Rng rng(9);
        const PackingResult packed =
            random_packing(Region::box(d.lo, d.hi), d, SizeDistribution::single(4e-6), 0.5, rng);
        d.lees_edwards = true;
        d.shear_offset = 0.3 * d.length().x;
        Particles p;
        for (const Sphere& s : packed.spheres) p.add(s.centre, s.radius, 7800, 0);
        const double skin = 0.8e-6;
        NeighborList list(NeighborList::Settings{skin, 1.0, true});
        list.build(p, d, 1);
        for (Vec3& x : p.position) {
            const Vec3 dir{rng.normal(), rng.normal(), rng.normal()};
            x += dir * (0.2 * skin / norm(dir));
        }
        d.shear_offset += 0.59 * skin;  // 2 x 0.2 + 0.59 = 0.99 skin
        list.set_shear_offset(d);
        REQUIRE_FALSE(list.needs_rebuild(p, d, 1));
        const Mismatch m =
            compare(list, p, d, [&](std::uint32_t i, std::uint32_t j) { return p.radius[i] + p.radius[j]; });
        CHECK(m.required > 20);
        CHECK(m.missing == 0);
        CHECK(m.wrong_image == 0);
        d.shear_offset += 0.02 * skin;
        CHECK(list.needs_rebuild(p, d, 1));
    }

    TEST_CASE("lees-edwards: contact history follows its pair when a grain is wrapped across the sheared boundary") {
        // Two touching grains through the boundary; grain a drifts out through the top (unwrapped,
        // as between rebuilds), the offset moves on, and the list is rebuilt: a is wrapped to the
        // bottom with x shifted by the offset, the pair is now listed through another image, and its
        // tangential spring and touching flag come with it; the separation is unchanged.
        Domain d;
        d.lo = {0, 0, 0};
        d.hi = {kBox, kBox, kBox};
        d.periodic = {true, true, true};
        d.lees_edwards = true;
        d.shear_offset = 11e-6;
        d.shear_velocity = 0.4;
        Particles p;
        p.add({25e-6, 20e-6, kBox - 1e-6}, 2e-6, 7800, 0);              // a, near the top
        p.add({25e-6 + 0.5e-6 - 11e-6, 20e-6, 2.6e-6}, 2e-6, 7800, 0);  // b, its image above touches a
        NeighborList list(NeighborList::Settings{0.5e-6, 1.0, true});
        list.build(p, d, 1);
        auto pair_of = [&]() {
            REQUIRE(list.pair_count() == 1);
            const std::uint32_t owner = list.offsets[1] > 0 ? 0 : 1;
            return std::make_pair(owner, list.offsets[owner]);
        };
        auto [owner, k] = pair_of();
        const std::uint8_t image_before = list.image[k];
        list.history[k].tangential = {1.25e-9, -2.5e-9, 0.5e-9};
        list.touching[k] = 1;
        const Vec3 sep_before = owner == 0 ? p.position[0] - p.position[1] + list.image_shift(image_before)
                                           : p.position[1] - p.position[0] + list.image_shift(image_before);
        p.position[0].z += 1.5e-6;  // a leaves through the top, b's image moves with it
        p.position[1].z += 1.5e-6;
        d.shear_offset += 0.1e-6;  // and the images slide
        const Vec3 v_before = p.velocity[0];
        list.build(p, d, 1);
        CHECK(p.position[0].z == rel(0.5e-6));                         // wrapped to the bottom
        CHECK(p.position[0].x == rel(25e-6 - d.shear_offset));         // x shifted by the offset
        CHECK(p.velocity[0].x == rel(v_before.x - d.shear_velocity));  // v_x by the image velocity
        std::tie(owner, k) = pair_of();
        CHECK(list.image[k] != image_before);
        CHECK(list.touching[k] == 1);
        CHECK(list.history[k].tangential.x == 1.25e-9);
        CHECK(list.history[k].tangential.y == -2.5e-9);
        const Vec3 sep_after = owner == 0 ? p.position[0] - p.position[1] + list.image_shift(list.image[k])
                                          : p.position[1] - p.position[0] + list.image_shift(list.image[k]);
        // The offset moved b's image by 0.1 um along x relative to a; nothing else changed.
        CHECK(norm(sep_after - (sep_before - Vec3{0.1e-6, 0, 0})) < 1e-15);
    }

}  // TEST_SUITE

TEST_SUITE("physics") {
    TEST_CASE(
        "lees-edwards: a pair straddling the sheared boundary has the sliding-image separation and the Hertz force") {
        // Grain a near the top, grain b near the bottom; b's image above sits at x_b + offset, z_b + Lz.
        // They overlap by 0.2 um through that image. Velocities are chosen so a moves exactly with b's
        // image (v_a = v_b + V): the contact then is purely elastic, F = (4/3) Y* sqrt(R* delta) delta
        // along the line of centres. Ignoring the image velocity would add normal damping and friction.
        const double diameter = 4e-6, R = 2e-6, offset = 13e-6, V = 0.6;
        const Vec3 xa{30e-6, 20e-6, kBox - 1.5e-6};
        const Vec3 d{1.9e-6, 0.7e-6, -3.1e-6};  // x_a - x_b,image, |d| = 3.7 um < 2R
        const Vec3 image_b = xa - d;
        const Vec3 xb{image_b.x - offset, image_b.y, image_b.z - kBox};
        Scene sc = sliding_box(json::array({{xa.x, xa.y, xa.z}, {xb.x, xb.y, xb.z}}), diameter, 0, offset, V);
        System& s = sc.system;
        const std::size_t a = grain_near(s, xa), b = grain_near(s, xb);
        s.particles.velocity[a] = {0.5 * V, 0, 0};
        s.particles.velocity[b] = {-0.5 * V, 0, 0};
        s.max_overlap_fraction = 0.5;  // the overlap is set by hand (0.15 R), not by an impact
        prepare(s);
        const double dist = norm(d), delta = 2 * R - dist, nu = 0.278;
        const double ystar = 1e9 / (2 * (1 - nu * nu)), rstar = R / 2;
        const Vec3 expected = d * ((4.0 / 3.0) * ystar * std::sqrt(rstar * delta) * delta / dist);
        CHECK(s.contact_stats.contacts == 1);
        CHECK(s.contact_stats.max_overlap_ratio == rel(delta / R).epsilon(1e-9));
        for (int k = 0; k < 3; ++k) {
            CHECK(s.particles.force[a][k] == rel(expected[k]).epsilon(1e-9));
            CHECK(s.particles.force[b][k] == rel(-expected[k]).epsilon(1e-9));
        }
        // Virial through the image: -(1/V) d_z f_x, the kinetic term vanishing (v_z = 0, no flow).
        const double volume = kBox * kBox * kBox;
        CHECK(lees_edwards_stress(s) == rel(-d.z * expected.x / volume).epsilon(1e-9));
    }

    TEST_CASE("lees-edwards: a grain carried across the sheared boundary keeps a continuous peculiar velocity") {
        // One grain in the affine flow u_x = rate (z - Lz/2) with Stokes drag, launched upward through
        // the top with a peculiar velocity p0 = (p_x0, 0, p_z0). With p = v - u(z), dp/dt = -p/tau -
        // rate p_z e_x, so p_z = p_z0 e^(-t/tau) and p_x = (p_x0 - rate p_z0 t) e^(-t/tau): smooth
        // through the crossing. The wrap changes x by the offset and v_x by -rate Lz, and u by the same
        // amount, so any mistake shows as a jump of rate Lz = 2 m/s against velocities of 1 m/s.
        const double rate = 5e4, V = rate * kBox, mu = 0.01, diameter = 4e-6;
        const Vec3 x0{20e-6, 20e-6, kBox - 0.3e-6};
        const double u0 = rate * (x0.z - 0.5 * kBox);
        const double px0 = 0.3, pz0 = 1.0;
        Scene sc = sliding_box(json::array({{x0.x, x0.y, x0.z}}), diameter, mu, 7e-6, V, Vec3{u0 + px0, 0, pz0});
        System& s = sc.system;
        s.flow = std::make_shared<SimpleShearFlow>(0, 2, rate, 0.5 * kBox);
        prepare(s);
        const double tau = s.particles.mass[0] / (6 * M_PI * mu * 0.5 * diameter);
        const long steps = static_cast<long>(3 * tau / s.dt);
        double worst = 0;
        int wraps = 0;
        double z_prev = s.particles.position[0].z;
        for (long n = 0; n < steps; ++n) {
            advance(s);
            const Vec3 x = s.particles.position[0], v = s.particles.velocity[0];
            if (x.z < z_prev - 0.5 * kBox) ++wraps;
            z_prev = x.z;
            const Vec3 p = v - s.flow->velocity(x, s.time);
            const double e = std::exp(-s.time / tau);
            worst = std::max(worst, std::abs(p.x - (px0 - rate * pz0 * s.time) * e));
            worst = std::max(worst, std::abs(p.z - pz0 * e));
        }
        CHECK(wraps == 1);
        CHECK(s.particles.position[0].z < 0.5 * kBox);  // the grain ended at the bottom, wrapped
        // The drag is evaluated with the half-step velocity, so the decay is first-order accurate:
        // an error of order (dt/tau) of the speeds involved (dt/tau ~ 1e-3 here), far below the jump
        // of rate Lz a wrong wrap would leave.
        MESSAGE("largest peculiar-velocity error " << worst << " m/s; dt/tau = " << s.dt / tau);
        CHECK(worst < 2 * (s.dt / tau) * (std::abs(px0) + pz0 + rate * pz0 * tau));
    }

    TEST_CASE("lees-edwards: the whole periodic system keeps its momentum in x without drag") {
        // A dense frictional gas in a sliding box, no fluid: pair forces are equal and opposite through
        // the sliding images, so sum m v changes only when a grain wraps across z, by exactly -m V per
        // crossing upward (+m V downward). y and z momentum are conserved outright.
        Domain d;
        d.lo = {0, 0, 0};
        d.hi = {kBox, kBox, kBox};
        d.periodic = {true, true, true};
        Rng rng(3);
        const PackingResult packed =
            random_packing(Region::box(d.lo, d.hi), d, SizeDistribution::single(4e-6), 0.35, rng);
        json pos = json::array();
        for (const Sphere& sp : packed.spheres) pos.push_back({sp.centre.x, sp.centre.y, sp.centre.z});
        const double V = 3.0;
        // Offset 0 at the start: the packing was made in an ordinary periodic box.
        Scene sc = sliding_box(pos, 4e-6, 0, 0, V);
        System& s = sc.system;
        Particles& p = s.particles;
        Vec3 mean{};
        for (std::size_t i = 0; i < p.size(); ++i) {
            p.velocity[i] = Vec3{rng.normal(), rng.normal(), rng.normal()} * 2.0;
            mean += p.velocity[i] / static_cast<double>(p.size());
        }
        for (auto& v : p.velocity) v -= mean;  // start from zero momentum
        prepare(s);
        auto momentum = [&] {
            Vec3 m{};
            for (std::size_t i = 0; i < p.size(); ++i) m += p.velocity[i] * p.mass[i];
            return m;
        };
        double scale = 0;  // sum m |v|: the size of the terms that must cancel
        for (std::size_t i = 0; i < p.size(); ++i) scale += p.mass[i] * norm(p.velocity[i]);
        const Vec3 p0 = momentum();
        double account = 0;  // momentum the wraps added: -m V per upward crossing
        long crossings = 0;
        std::vector<double> z_prev(p.size());
        std::size_t contacts = 0;
        for (long n = 0; n < 3000; ++n) {
            for (std::size_t i = 0; i < p.size(); ++i) z_prev[i] = p.position[i].z;
            advance(s);
            contacts = std::max(contacts, s.contact_stats.contacts);
            for (std::size_t i = 0; i < p.size(); ++i) {
                const double jump = std::nearbyint((p.position[i].z - z_prev[i]) / kBox);
                if (jump != 0) {
                    account += jump * p.mass[i] * V;
                    ++crossings;
                }
            }
        }
        const Vec3 p1 = momentum();
        MESSAGE(crossings << " crossings, up to " << contacts << " contacts at once, momentum drift "
                          << p1.x - p0.x - account);
        CHECK(crossings > 5);
        CHECK(contacts > 5);
        // Round-off only: ~1e-16 of sum m|v| per step, accumulated over 3000 steps, is below 1e-12.
        CHECK(std::abs(p1.x - p0.x - account) < 1e-12 * scale);
        CHECK(std::abs(p1.y - p0.y) < 1e-12 * scale);
        CHECK(std::abs(p1.z - p0.z) < 1e-12 * scale);
    }

}  // TEST_SUITE
