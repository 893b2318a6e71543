#include "scene/units.hpp"

#include <cctype>
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
        {"rad", {1.0, dimensionless, false}},
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
        char* end = nullptr;
        exponent = static_cast<int>(std::strtol(exp_text.c_str(), &end, 10));
        if (*end != '\0' || exponent == 0) throw UnitError("bad power '" + token + "' in \"" + whole + "\"");
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
    const char* begin = text.c_str();
    char* end = nullptr;
    const double number = std::strtod(begin, &end);
    if (end == begin) throw UnitError("\"" + text + "\" does not start with a number");
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
