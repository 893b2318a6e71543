#pragma once
// Numbers as messages and reports show them to a user.
#include <sstream>
#include <string>

namespace mrjam {

// The shortest of fixed and scientific notation at 6 (or `significant`) significant digits
// ("1.1", "2.5e-07"), where std::to_string would print "1.100000" and "0.000000".
inline std::string format_number(double v, int significant = 6) {
    std::ostringstream s;
    s.precision(significant);
    s << v;
    return s.str();
}

}  // namespace mrjam
