#include "contact/restitution.hpp"

#include <cmath>

namespace mrjam {

double damping_beta_for_restitution(double e) {
    const double l = std::log(e);
    return -l / std::sqrt(l * l + M_PI * M_PI);
}

double hertz_contact_duration(double reduced_mass, double reduced_radius, double effective_youngs,
                              double impact_speed) {
    // Coefficient 2 * integral_0^1 (1 - x^(5/2))^(-1/2) dx = 0.8 B(2/5, 1/2) = 2.94329...
    static const double coefficient = 0.8 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
    const double k = 15.0 * reduced_mass / (16.0 * std::sqrt(reduced_radius) * effective_youngs);
    return coefficient * std::pow(k, 0.4) * std::pow(impact_speed, -0.2);
}

}  // namespace mrjam
