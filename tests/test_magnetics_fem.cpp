// The magnetostatic pipeline (gmsh mesh -> GetDP scalar-potential solve -> sampling) checked
// against closed-form answers and exact properties of linear magnetostatics.
#include <doctest/doctest.h>

#include <cmath>

#include "magnetics/bare_magnet.hpp"
#include "magnetics/epm_field.hpp"
#include "test_support.hpp"

using namespace mrjam;
using namespace mrjam::magnetics;
using mrjam_test::TempDir;

namespace {

bool verbose() { return std::getenv("MRJAM_TEST_VERBOSE") != nullptr; }

// sqrt(mean |B_fem - B_exact|^2) / sqrt(mean |B_exact|^2) along a line of probes.
double relative_rms(const std::vector<Vec3>& fem, const LineRequest& line, const Cuboid& magnet) {
    double num = 0, den = 0;
    for (std::size_t i = 0; i < fem.size(); ++i) {
        const double t = fem.size() > 1 ? static_cast<double>(i) / (fem.size() - 1) : 0.0;
        const Vec3 x = line.from + t * (line.to - line.from);
        const Vec3 exact = cuboid_flux_density(magnet, x);
        num += norm2(fem[i] - exact);
        den += norm2(exact);
    }
    return std::sqrt(num / den);
}

}  // namespace

TEST_SUITE("physics") {
    // The verification: one NdFeB-sized block (1.6 x 1.6 x 3.2 mm, B_r = 1.35 T along its
    // long axis) in air. Along the axis, from just off the pole face to 2 magnet lengths away, the
    // RMS error must be within 1% at the standard element size (0.2 mm, the valve's standard fluid
    // size); off the axis (a line beside the magnet, parallel to it) within 2%. Halving the element
    // count per length must make both errors larger: the solution converges to the closed form.
    TEST_CASE("magnetics: a bare cuboid magnet's FEM field matches the closed-form prism field") {
        // GetDP is part of the tool (scripts/install-deps.sh installs it): its absence fails, not skips.
        REQUIRE_MESSAGE(!find_getdp().empty(), "getdp is not installed: run scripts/install-deps.sh");
        const Cuboid magnet{{0, 0, 0}, {1.6e-3, 1.6e-3, 3.2e-3}, {0, 0, 1.35}};
        const std::vector<LineRequest> lines{{{0, 0, 1.65e-3}, {0, 0, 8e-3}, 41},  // axis, outside the pole
                                             {{1.3e-3, 0.4e-3, -4e-3}, {1.3e-3, 0.4e-3, 4e-3}, 41}};  // beside it
        TempDir dir("mrjam_bare_magnet");
        auto errors = [&](double size) {
            BareMagnetMesh mesh;
            mesh.magnet_size = size;
            const auto s = solve_bare_magnet(magnet, mesh, lines, dir.path / std::to_string(size));
            REQUIRE(s.lines.size() == 2);
            REQUIRE(s.lines[0].size() == 41);
            const double axis = relative_rms(s.lines[0], lines[0], magnet),
                         side = relative_rms(s.lines[1], lines[1], magnet);
            if (verbose())
                MESSAGE("element " << size * 1e3 << " mm: " << s.elements << " tets, " << s.unknowns << " unknowns, "
                                   << s.seconds << " s; RMS error axis " << axis << ", beside " << side);
            return std::pair{axis, side};
        };
        const auto [axis, side] = errors(0.2e-3);
        CHECK(axis < 0.01);
        CHECK(side < 0.02);
        const auto [axis_coarse, side_coarse] = errors(0.4e-3);
        CHECK(axis_coarse > axis);
        CHECK(side_coarse > side);
    }

    // Magnetostatics with linear materials is linear in the sources: the field of the partially
    // switched valve (alnico reversed at 1.25 T against NdFeB at 1.35 T) is the combination
    // B_partial = (1 - r)/2 B_on + (1 + r)/2 B_off with r = 1.25/1.35, at every point, on the same
    // mesh, to the solver's tolerance. This checks the whole chain: remanence signs, region
    // assignment, the sampled field map. The OFF state's active field must also be far below ON.
    TEST_CASE("magnetics: EPM ON, OFF and partial states superpose exactly (linear materials)") {
        // GetDP is part of the tool (scripts/install-deps.sh installs it): its absence fails, not skips.
        REQUIRE_MESSAGE(!find_getdp().empty(), "getdp is not installed: run scripts/install-deps.sh");
        TempDir dir("mrjam_epm_superpose");
        EpmFieldRequest request;
        request.mesh.fluid_size = 0.4e-3;
        request.mesh.device_size = 0.8e-3;
        request.mesh.far_size = 5e-3;
        request.map_spacing = 0.3e-3;
        request.picture_pixels = 0;
        request.model.valve.upstream_length = 2.5e-3;
        request.model.valve.downstream_length = 2.5e-3;
        auto solve = [&](double polarity, double alnico, const std::string& name) {
            EpmFieldRequest r = request;
            r.model.magnets.alnico_polarity = polarity;
            r.model.magnets.alnico.remanence = alnico;
            r.work_dir = dir.path / name;
            return compute_epm_field(r);
        };
        const EpmField on = solve(1, 1.35, "on"), off = solve(-1, 1.35, "off"), partial = solve(-1, 1.25, "partial");
        REQUIRE(on.fluid_map.values.size() == partial.fluid_map.values.size());
        const double r = 1.25 / 1.35;
        double worst = 0, scale = 0;
        for (std::size_t i = 0; i < on.fluid_map.values.size(); ++i) {
            const Vec3 predicted = 0.5 * (1 - r) * on.fluid_map.values[i] + 0.5 * (1 + r) * off.fluid_map.values[i];
            worst = std::max(worst, norm(predicted - partial.fluid_map.values[i]));
            scale = std::max(scale, norm(on.fluid_map.values[i]));
        }
        if (verbose())
            MESSAGE("mean active |B|: on " << on.mean_b_active << " T, off " << off.mean_b_active << " T, partial "
                                           << partial.mean_b_active << " T; superposition residual " << worst / scale);
        // CG stops at a relative residual of 1e-10; the map's sampled values inherit ~1e-8 of the peak.
        CHECK(worst < 1e-6 * scale);
        CHECK(off.mean_b_active < 0.05 * on.mean_b_active);
        CHECK(partial.mean_b_active < 0.2 * on.mean_b_active);
    }

}  // TEST_SUITE
