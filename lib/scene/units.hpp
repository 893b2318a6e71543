#pragma once
// Quantities with units. Users think in micrometres, millitesla and kilopascal, so a scene value
// may be a plain SI number or a string such as "6.7 um", "600 mT", "10 mPa s", "60 kJ/m3".
// The string is parsed into SI and its dimension checked against what the field expects.
#include <array>
#include <stdexcept>
#include <string>

namespace mrjam::units {

// Exponents of the SI base units m, kg, s, A.
struct Dimension {
    std::array<int, 4> exponent{0, 0, 0, 0};
    constexpr bool operator==(const Dimension&) const = default;
};

inline constexpr Dimension dimensionless{{0, 0, 0, 0}};
inline constexpr Dimension length{{1, 0, 0, 0}};
inline constexpr Dimension mass{{0, 1, 0, 0}};
inline constexpr Dimension time{{0, 0, 1, 0}};
inline constexpr Dimension frequency{{0, 0, -1, 0}};  // also shear rate, 1/s
inline constexpr Dimension velocity{{1, 0, -1, 0}};
inline constexpr Dimension acceleration{{1, 0, -2, 0}};
inline constexpr Dimension force{{1, 1, -2, 0}};
inline constexpr Dimension pressure{{-1, 1, -2, 0}};  // also stress, modulus, J/m3
inline constexpr Dimension energy{{2, 1, -2, 0}};
inline constexpr Dimension surface_energy{{0, 1, -2, 0}};  // J/m2 = N/m
inline constexpr Dimension stiffness{{0, 1, -2, 0}};       // N/m, same base units as J/m2
inline constexpr Dimension density{{-3, 1, 0, 0}};
inline constexpr Dimension viscosity{{-1, 1, -1, 0}};               // Pa s
inline constexpr Dimension damping{{0, 1, -1, 0}};                  // N s/m
inline constexpr Dimension magnetic_flux_density{{0, 1, -2, -1}};   // tesla
inline constexpr Dimension magnetic_field{{-1, 0, 0, 1}};           // A/m, also magnetisation
inline constexpr Dimension magnetic_moment{{2, 0, 0, 1}};           // A m^2
inline constexpr Dimension gravitational_constant{{3, -1, -2, 0}};  // m^3 / (kg s^2)

// Human-readable form of a dimension, e.g. "m" or "kg m^-1 s^-2", for error messages.
std::string describe(const Dimension&);
// The unit a scene would write for this dimension, with an example ("T, e.g. \"230 mT\""); the
// base units where the dimension has no common name.
std::string spoken(const Dimension&);

struct Quantity {
    double value;  // SI
    Dimension dimension;
};

class UnitError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Parses "<number> [unit expression]". Unit expressions: products of units separated by
// spaces, '*' or '.', one optional '/' (everything after it is in the denominator), powers as
// m3, m^3 or s-1. Prefixes p n u µ m c k M G on every unit except kg. Throws UnitError.
Quantity parse(const std::string& text);

// Parses and checks the dimension; the message names what was expected.
double parse_as(const std::string& text, const Dimension& expected);

}  // namespace mrjam::units
