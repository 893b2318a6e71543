// Quantities with units (lib/scene/units.hpp): the strings users write in scene files parse to
// the right SI value and dimension, and wrong or unknown units are refused with UnitError.
#include <doctest/doctest.h>

#include <string>

#include "rel_approx.hpp"
#include "scene/units.hpp"

using mrjam_test::rel;

namespace {

namespace units = mrjam::units;
using units::Dimension;

// parse_as with the expected dimension, compared to the SI value to 1e-12 relative.
void check(const std::string& text, const Dimension& dim, double si) {
    CAPTURE(text);
    const units::Quantity q = units::parse(text);
    CHECK(q.dimension == dim);
    CHECK(q.value == rel(si).epsilon(1e-12));
    CHECK(units::parse_as(text, dim) == rel(si).epsilon(1e-12));
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("units: the quantities of the scene format parse to SI") {
        check("6.7 um", units::length, 6.7e-6);
        check("600 mT", units::magnetic_flux_density, 0.6);
        check("10 mPa s", units::viscosity, 0.01);
        check("60 kJ/m3", units::pressure, 6e4);
        check("105 kPa", units::pressure, 1.05e5);
        check("1 GPa", units::pressure, 1e9);
        check("7800 kg/m3", units::density, 7800);
        check("9.81 m/s2", units::acceleration, 9.81);
        check("100 1/s", units::frequency, 100);
        check("0.2 ns", units::time, 2e-10);
    }

    TEST_CASE("units: spellings of the same quantity agree") {
        check("6.7um", units::length, 6.7e-6);        // no space
        check("6.7 \u00b5m", units::length, 6.7e-6);  // micro sign
        check("6.7 \u03bcm", units::length, 6.7e-6);  // Greek mu
        check("10 mPa*s", units::viscosity, 0.01);
        check("10 mPa.s", units::viscosity, 0.01);
        check("10 cP", units::viscosity, 0.01);  // centipoise
        check("9.81 m s^-2", units::acceleration, 9.81);
        check("9.81 m s-2", units::acceleration, 9.81);
        check("9.81 m/s^2", units::acceleration, 9.81);
        check("100 Hz", units::frequency, 100);
        check("100 s-1", units::frequency, 100);
        check("7.8 g/cm3", units::density, 7800);
        check("1e-3 m", units::length, 1e-3);
        check("-2.5 mm", units::length, -2.5e-3);
        check("1 bar", units::pressure, 1e5);
        check("2 min", units::time, 120);
        check("50 %", units::dimensionless, 0.5);
        check("3", units::dimensionless, 3);
        check("0.05 J/m2", units::surface_energy, 0.05);
        check("1000 N/m", units::stiffness, 1000);
    }

    TEST_CASE("units: a dimension mismatch throws UnitError naming both dimensions") {
        CHECK_THROWS_AS(units::parse_as("6.7 um", units::pressure), units::UnitError);
        CHECK_THROWS_AS(units::parse_as("1 GPa", units::length), units::UnitError);
        CHECK_THROWS_AS(units::parse_as("10 mPa", units::viscosity), units::UnitError);  // missing the s
        CHECK_THROWS_AS(units::parse_as("9.81 m/s", units::acceleration), units::UnitError);
        CHECK_THROWS_AS(units::parse_as("5 m", units::dimensionless), units::UnitError);
        try {
            units::parse_as("7800 kg/m2", units::density);
            FAIL("expected UnitError");
        } catch (const units::UnitError& e) {
            const std::string msg = e.what();
            CHECK(msg.find("7800 kg/m2") != std::string::npos);
            CHECK(msg.find(units::spoken(units::density)) != std::string::npos);
        }
    }

    TEST_CASE("units: unknown units and malformed strings throw UnitError") {
        CHECK_THROWS_AS(units::parse("6.7 parsecs"), units::UnitError);
        CHECK_THROWS_AS(units::parse_as("6.7 parsecs", units::length), units::UnitError);
        CHECK_THROWS_AS(units::parse("6.7 furlongs"), units::UnitError);
        CHECK_THROWS_AS(units::parse("um"), units::UnitError);  // no number
        CHECK_THROWS_AS(units::parse(""), units::UnitError);
        CHECK_THROWS_AS(units::parse("5 m/s/s"), units::UnitError);  // two slashes
        CHECK_THROWS_AS(units::parse("5 m^0"), units::UnitError);    // zero power
        CHECK_THROWS_AS(units::parse("5 m^x"), units::UnitError);
        CHECK_THROWS_AS(units::parse("inf m"), units::UnitError);
        CHECK_THROWS_AS(units::parse("nan Pa"), units::UnitError);
        CHECK_THROWS_AS(units::parse("1 kkg"), units::UnitError);  // prefix on kg
        CHECK_THROWS_AS(units::parse("1 mG"), units::UnitError);   // gauss takes no prefix
        // What the C number and integer readers accept but a scene does not mean: a hexadecimal
        // number (strtod read "0x10 mm" as 16 mm), a power past an int (4294967297 wrapped to
        // 1), a power no unit has, and a NUL that ended the string early.
        CHECK_THROWS_AS(units::parse("0x10 mm"), units::UnitError);
        CHECK_THROWS_AS(units::parse("0x1p4 m"), units::UnitError);
        CHECK_THROWS_AS(units::parse("1 m^4294967297"), units::UnitError);
        CHECK_THROWS_AS(units::parse("1 m^99999999999999999999"), units::UnitError);
        CHECK_THROWS_AS(units::parse("1 m^10"), units::UnitError);
        CHECK_THROWS_AS(units::parse(std::string("5 mm\0 of junk", 14)), units::UnitError);
        CHECK_THROWS_AS(units::parse(".e3 m"), units::UnitError);
        // ... while every decimal spelling still reads as before.
        CHECK(units::parse("1e-3 m").value == doctest::Approx(1e-3).epsilon(1e-15));
        CHECK(units::parse("-.5 m").value == -0.5);
        CHECK(units::parse("+2.5E2 mm").value == doctest::Approx(0.25).epsilon(1e-15));
        CHECK(units::parse("  3 um").value == doctest::Approx(3e-6).epsilon(1e-15));
        CHECK(units::parse("2 m^-3").dimension == units::parse("2 1/m3").dimension);
        CHECK(units::parse("7 m^9").value == 7);
        try {
            units::parse("6.7 parsecs");
            FAIL("expected UnitError");
        } catch (const units::UnitError& e) {
            CHECK(std::string(e.what()).find("parsecs") != std::string::npos);
        }
    }

    TEST_CASE("units: describe names the base units") {
        CHECK(units::describe(units::length) == "m");
        CHECK(units::describe(units::dimensionless) == "dimensionless");
        CHECK(units::describe(units::pressure) == "m^-1 kg s^-2");
    }

    TEST_CASE("units: a wrong unit is answered with the unit a scene writes, and an example") {
        try {
            units::parse_as("5 mm", units::magnetic_flux_density);
            FAIL("expected UnitError");
        } catch (const units::UnitError& e) {
            CHECK(std::string(e.what()) == "\"5 mm\" has units of m, expected T, e.g. \"230 mT\"");
        }
        CHECK(units::spoken(units::viscosity) == "Pa s, e.g. \"0.16 Pa s\"");
        CHECK(units::spoken(units::magnetic_moment) == "A m2");
        CHECK(units::spoken(units::Dimension{{1, 1, 0, 0}}) == "m kg");  // no common name: base units
    }

}  // TEST_SUITE
