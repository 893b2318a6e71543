#include "scene/units.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

namespace mrjam::units {
namespace {

struct UnitDef {
    double scale;
    Dimension dim;
    bool prefixable;
};

const std::map<std::string, UnitDef>& unit_table() {
    static const std::map<std::string, UnitDef> table = {
        {"m", {1.0, length, true}},
        {"g", {1e-3, mass, true}},
        {"s", {1.0, time, true}},
        {"A", {1.0, {{0, 0, 0, 1}}, true}},
        {"N", {1.0, force, true}},
        {"Pa", {1.0, pressure, true}},
        {"J", {1.0, energy, true}},
        {"W", {1.0, {{2, 1, -3, 0}}, true}},
        {"Hz", {1.0, frequency, true}},
        {"T", {1.0, magnetic_flux_density, true}},
        {"G", {1e-4, magnetic_flux_density, false}},  // gauss, no prefixes (clash with giga)
        {"Oe", {1e3 / (4 * M_PI), magnetic_field, false}},
        {"P", {0.1, viscosity, true}},  // poise, so "cP" works
        {"bar", {1e5, pressure, true}},
        {"rad", {1.0, dimensionless, true}},  // urad/s: the source writes spins in urad/s
        {"deg", {M_PI / 180.0, dimensionless, false}},
        {"min", {60.0, time, false}},
        {"h", {3600.0, time, false}},
        {"L", {1e-3, {{3, 0, 0, 0}}, true}},
        {"%", {0.01, dimensionless, false}},
    };
    return table;
}

double prefix_scale(const std::string& p) {
    static const std::map<std::string, double> prefixes = {{"p", 1e-12},     {"n", 1e-9}, {"u", 1e-6}, {"\u00b5", 1e-6},
                                                           {"\u03bc", 1e-6}, {"m", 1e-3}, {"c", 1e-2}, {"d", 1e-1},
                                                           {"k", 1e3},       {"M", 1e6},  {"G", 1e9}};
    auto it = prefixes.find(p);
    return it == prefixes.end() ? 0.0 : it->second;
}

Quantity power(const UnitDef& u, double scale, int exponent) {
    Quantity q{std::pow(u.scale * scale, exponent), {}};
    for (int k = 0; k < 4; ++k) q.dimension.exponent[k] = u.dim.exponent[k] * exponent;
    return q;
}

// The largest power a unit may carry in a scene.
constexpr long kLargestPower = 9;

// The length of the decimal number at the start of `s` ([+-] digits [. digits] [e [+-] digits],
// or [+-] . digits ...), 0 if there is none.
std::size_t decimal_number_length(const char* s) {
    std::size_t k = 0;
    auto digit = [&](std::size_t at) { return std::isdigit(static_cast<unsigned char>(s[at])) != 0; };
    if (s[k] == '+' || s[k] == '-') ++k;
    std::size_t mantissa = 0;
    while (digit(k)) ++k, ++mantissa;
    if (s[k] == '.') {
        ++k;
        while (digit(k)) ++k, ++mantissa;
    }
    if (mantissa == 0) return 0;
    if (s[k] == 'e' || s[k] == 'E') {
        std::size_t e = k + 1;
        if (s[e] == '+' || s[e] == '-') ++e;
        if (digit(e)) {
            while (digit(e)) ++e;
            k = e;
        }
    }
    return k;
}

// One factor such as "um", "m3", "s^-1", "kg".
Quantity parse_factor(const std::string& token, const std::string& whole) {
    std::size_t split = token.size();
    while (split > 0 && (std::isdigit(static_cast<unsigned char>(token[split - 1])) || token[split - 1] == '-' ||
                         token[split - 1] == '^'))
        --split;
    std::string symbol = token.substr(0, split);
    std::string exp_text = token.substr(split);
    if (!exp_text.empty() && exp_text[0] == '^') exp_text.erase(0, 1);
    int exponent = 1;
    if (!exp_text.empty()) {
        // Read as a long and bounded before it becomes an int: 4294967297 cast to int was 1. No
        // unit of a scene needs a power beyond 9 (m3, s2, m^-3).
        char* end = nullptr;
        errno = 0;
        const long power_read = std::strtol(exp_text.c_str(), &end, 10);
        if (*end != '\0' || power_read == 0 || errno == ERANGE || power_read > kLargestPower ||
            power_read < -kLargestPower)
            throw UnitError("bad power '" + token + "' in \"" + whole +
                            "\" (a power is a non-zero whole number of at most " + std::to_string(kLargestPower) + ")");
        exponent = static_cast<int>(power_read);
    }
    const auto& table = unit_table();
    if (auto it = table.find(symbol); it != table.end()) return power(it->second, 1.0, exponent);
    // Try a prefix of one or two bytes (µ is two bytes in UTF-8).
    for (std::size_t plen : {std::size_t{1}, std::size_t{2}}) {
        if (symbol.size() <= plen) continue;
        const double ps = prefix_scale(symbol.substr(0, plen));
        auto it = table.find(symbol.substr(plen));
        if (ps > 0 && it != table.end() && it->second.prefixable) return power(it->second, ps, exponent);
    }
    throw UnitError("unknown unit '" + symbol + "' in \"" + whole +
                    "\" (known: m g s A N Pa J W Hz T G Oe P bar rad deg min h L %, with prefixes p n u m c k M G)");
}

void multiply(Quantity& acc, const Quantity& f, int sign) {
    acc.value = sign > 0 ? acc.value * f.value : acc.value / f.value;
    for (int k = 0; k < 4; ++k) acc.dimension.exponent[k] += sign * f.dimension.exponent[k];
}

}  // namespace

std::string describe(const Dimension& d) {
    static const char* names[4] = {"m", "kg", "s", "A"};
    std::ostringstream out;
    bool first = true;
    for (int k = 0; k < 4; ++k) {
        if (d.exponent[k] == 0) continue;
        if (!first) out << ' ';
        out << names[k];
        if (d.exponent[k] != 1) out << '^' << d.exponent[k];
        first = false;
    }
    return first ? std::string("dimensionless") : out.str();
}

std::string spoken(const Dimension& d) {
    // As a scene writes them: "T" rather than "kg s^-2 A^-1". Where two quantities share base
    // units (surface energy and stiffness) the names say both.
    static const std::pair<Dimension, const char*> named[] = {
        {length, "m, e.g. \"1.2 mm\""},
        {mass, "kg"},
        {time, "s, e.g. \"0.2 ms\""},
        {frequency, "1/s, e.g. \"100 1/s\""},
        {velocity, "m/s, e.g. \"0.273 m/s\""},
        {acceleration, "m/s2, e.g. \"9.81 m/s2\""},
        {force, "N"},
        {pressure, "Pa, e.g. \"105 kPa\" or \"1 GPa\""},
        {energy, "J"},
        {surface_energy, "J/m2 or N/m"},
        {density, "kg/m3, e.g. \"7800 kg/m3\""},
        {viscosity, "Pa s, e.g. \"0.16 Pa s\""},
        {damping, "N s/m"},
        {magnetic_flux_density, "T, e.g. \"230 mT\""},
        {magnetic_field, "A/m, e.g. \"1.7e6 A/m\""},
        {magnetic_moment, "A m2"},
    };
    for (const auto& [dim, name] : named)
        if (dim == d) return name;
    return describe(d);
}

Quantity parse(const std::string& text) {
    // The whole string is read: a NUL inside it would end the C string early and leave the rest
    // unread ("5 mm" then anything).
    if (text.find('\0') != std::string::npos) throw UnitError("\"" + text + "\" contains a NUL character");
    const char* begin = text.c_str();
    while (*begin == ' ' || *begin == '\t') ++begin;
    const std::size_t digits = decimal_number_length(begin);
    if (digits == 0) throw UnitError("\"" + text + "\" does not start with a decimal number");
    char* end = nullptr;
    const double number = std::strtod(begin, &end);
    // strtod also reads hexadecimal ("0x10" is 16), "inf" and leading spaces: only the decimal
    // number the scene format writes is taken.
    if (end != begin + digits) throw UnitError("\"" + text + "\" does not start with a decimal number");
    if (!std::isfinite(number)) throw UnitError("\"" + text + "\" is not a finite number");
    Quantity q{number, dimensionless};
    std::string rest(end);
    int sign = +1;
    std::string token;
    auto flush = [&] {
        if (token.empty()) return;
        if (token != "1") multiply(q, parse_factor(token, text), sign);
        token.clear();
    };
    for (char c : rest) {
        if (c == ' ' || c == '*' || c == '.' || c == '\t') {
            flush();
        } else if (c == '/') {
            flush();
            if (sign < 0) throw UnitError("more than one '/' in \"" + text + "\"");
            sign = -1;
        } else {
            token += c;
        }
    }
    flush();
    return q;
}

double parse_as(const std::string& text, const Dimension& expected) {
    const Quantity q = parse(text);
    // J/m2 and N/m share base units with stiffness; dimension equality is all that matters.
    if (!(q.dimension == expected))
        throw UnitError("\"" + text + "\" has units of " + describe(q.dimension) + ", expected " + spoken(expected));
    return q.value;
}

}  // namespace mrjam::units
