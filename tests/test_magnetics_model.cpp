// The EPM valve description: impossible geometry is refused with the field to fix, and the
// circuit estimate obeys the exact properties of a linear reluctance network.
#include <doctest/doctest.h>

#include "geometry/valve.hpp"
#include "magnetics/magnetic_circuit.hpp"
#include "rel_approx.hpp"

using mrjam_test::rel;

using namespace mrjam;
using namespace mrjam::magnetics;

namespace {
bool mentions(const std::vector<std::string>& problems, const std::string& what) {
    for (const auto& p : problems)
        if (p.find(what) != std::string::npos) return true;
    return false;
}
}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("valve geometry: passage radius, volume and presets") {
        ValveGeometry v;
        v.constriction_diameter = constriction_preset("20x");
        CHECK(v.constriction_diameter == rel(0.88e-3));
        CHECK(constriction_preset("40x") == rel(1.76e-3));
        CHECK(constriction_preset("50x") == 0.0);
        CHECK(v.passage_radius(-3e-3) == rel(v.bore_radius()));
        CHECK(v.passage_radius(0.0) == rel(v.throat_radius()));
        CHECK(v.passage_radius(v.throat_end_z() + 1e-6) == rel(v.bore_radius()));
        const double mid = v.taper_start_z() + 0.5 * v.taper_length;
        CHECK(v.passage_radius(mid) == rel(0.5 * (v.bore_radius() + v.throat_radius())));
        CHECK(v.in_fluid({0, 0, 0}));
        CHECK_FALSE(v.in_fluid({0.9 * v.bore_radius(), 0, 0}));  // inside the bore radius but not the throat
        CHECK(v.in_fluid({0.9 * v.bore_radius(), 0, -3e-3}));
        // Volume by midpoint integration of pi r(z)^2.
        double volume = 0;
        const int n = 200000;
        const double dz = (v.upstream_length + v.downstream_length) / n;
        for (int i = 0; i < n; ++i) {
            const double r = v.passage_radius(-v.upstream_length + (i + 0.5) * dz);
            volume += M_PI * r * r * dz;
        }
        CHECK(v.fluid_volume() == rel(volume).epsilon(1e-5));
        CHECK(v.problems().empty());
    }

    TEST_CASE("EPM model: impossible geometry names the field and the fix") {
        EpmModel ok;
        CHECK(ok.problems().empty());
        EpmModel m = ok;
        m.valve.constriction_diameter = 3e-3;
        CHECK(mentions(m.problems(), "/valve/constriction_diameter"));
        m = ok;
        m.bracket.thickness = -1e-3;
        CHECK(mentions(m.problems(), "/bracket/thickness"));
        m = ok;
        m.bracket.width = 3e-3;  // narrower than two 1.6 mm magnets side by side
        CHECK(mentions(m.problems(), "do not fit the caps"));
        m = ok;
        m.valve.wall_thickness = 0.8e-3;  // the body no longer fits between the brackets
        CHECK(mentions(m.problems(), "does not fit between the brackets"));
        m = ok;
        m.bracket.variant = BracketVariant::curved;
        m.bracket.cutout_radius = 1.3e-3;
        CHECK(mentions(m.problems(), "/bracket/cutout_radius"));
        m = ok;
        m.bracket.variant = BracketVariant::insert;
        m.bracket.insert_width = 5e-3;
        CHECK(mentions(m.problems(), "/bracket/insert_width"));
        m = ok;
        m.valve.downstream_length = 2e-3;  // ends at the caps' edge (4 mm wide): gmsh's cut failed there
        CHECK(mentions(m.problems(), "/valve/downstream_length"));
        CHECK_FALSE(mentions(m.problems(), "/valve/upstream_length"));
    }

    // A reluctance network with linear elements: flux is linear in the sources, equal and opposite
    // magnets cancel exactly, bridging the wall with iron raises the field, and brackets that do
    // not reach the tube (unguided) leave it weaker.
    TEST_CASE("magnetic circuit estimate: linearity, exact OFF cancellation, variant ordering") {
        EpmModel m;
        const double on = circuit_field(m).mean_b_active;
        CHECK(on > 0);
        EpmModel half = m;
        half.magnets.ndfeb.remanence *= 0.5;
        half.magnets.alnico.remanence *= 0.5;
        CHECK(circuit_field(half).mean_b_active == rel(0.5 * on).epsilon(1e-12));
        EpmModel off = m;
        off.magnets.alnico_polarity = -1;
        CHECK(circuit_field(off).mean_b_active == doctest::Approx(0.0).scale(1.0).epsilon(1e-15));
        EpmModel insert = m;
        insert.bracket.variant = BracketVariant::insert;
        CHECK(circuit_field(insert).mean_b_active > on);  // iron replaces air in series with the fluid
        EpmModel unguided = m;
        unguided.bracket.variant = BracketVariant::unguided;
        CHECK(circuit_field(unguided).mean_b_active < 0.5 * on);
    }

}  // TEST_SUITE
