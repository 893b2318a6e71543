// Steady shear of a small magnetised Lees-Edwards cell: the virial stress of the box (through the
// sliding images) against the momentum flux across the sliding boundary itself (method of planes).
// Momentum conservation makes the flux the same through every plane in steady homogeneous shear,
// so the two agree on average; a virial that took z_i - z_j without the image (off by Lz for
// the pairs through the boundary), or images without the offset, would not.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>

#include "integrator.hpp"
#include "scene/scene.hpp"
#include "shear/block_average.hpp"
#include "shear/shear_spec.hpp"
#include "shear/shear_stress.hpp"
#include "test_support.hpp"

using namespace mrjam;
using json = nlohmann::json;

TEST_SUITE("physics") {
    TEST_CASE("lees-edwards: in steady shear the virial equals the momentum flux through the sliding boundary") {
        const json input = {
            {"size", {{"distribution", "single"}, {"diameter", "4 um"}}},
            {"cell", {{"size", {"30 um", "30 um", "30 um"}}, {"boundaries", "lees_edwards"}}},
            {"material", mrjam_test::chapter2_iron()},
            {"fluid", {{"viscosity", "10 mPa s"}}},
            {"field", {{"flux_density", "300 mT"}}},
            {"output", {{"directory", (std::filesystem::temp_directory_path() / "mrjam_le_stress").string()}}}};
        const ShearSpec spec = read_shear_spec(input, "quick");
        Scene sc = build_scene(engine_scene(spec, spec.flux_density), BuildOptions{});
        System& s = sc.system;
        s.domain.lees_edwards = true;
        choose_timestep(sc);
        const double rate = 3000, L = spec.cell.z;
        s.domain.shear_velocity = rate * L;
        s.flow = std::make_shared<SimpleShearFlow>(0, 2, rate, 0.5 * L);
        prepare(s);
        // A strain of 0.2 builds the sheared structure; then 200 samples over a strain of 0.3.
        advance_steps(s, static_cast<long>(0.2 / rate / s.dt));
        const long every = static_cast<long>(0.3 / rate / s.dt / 200);
        std::vector<double> virial, plane, difference;
        double kinetic_bound = 0;
        for (int n = 0; n < 200; ++n) {
            advance_steps(s, every);
            virial.push_back(lees_edwards_stress(s));
            plane.push_back(lees_edwards_boundary_stress(s));
            difference.push_back(virial.back() - plane.back());
            // The kinetic virial term: the size of the convective flux the plane sum leaves out.
            double kin = 0;
            for (std::size_t i = 0; i < s.particles.size(); ++i) {
                const Vec3 u = s.flow->velocity(s.particles.position[i], s.time);
                kin += s.particles.mass[i] * (s.particles.velocity[i].x - u.x) * s.particles.velocity[i].z;
            }
            kinetic_bound = std::max(kinetic_bound, std::abs(kin) / (L * L * L));
        }
        const BlockAverage v = block_average(virial, 10), p = block_average(plane, 10),
                           d = block_average(difference, 10);
        MESSAGE(s.particles.size() << " grains: virial " << v.mean << " +- " << v.error << " Pa, boundary flux "
                                   << p.mean << " +- " << p.error << " Pa, difference " << d.mean << " +- " << d.error
                                   << " Pa, kinetic term up to " << kinetic_bound << " Pa");
        CHECK(v.mean > 5 * v.error);  // a real, resolved stress, not noise about zero
        // Equal up to three standard errors of the paired difference and the omitted kinetic flux.
        CHECK(std::abs(d.mean) <= 3 * d.error + kinetic_bound);
        std::filesystem::remove_all(spec.output.directory);
    }

}  // TEST_SUITE
