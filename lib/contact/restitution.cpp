#include "contact/restitution.hpp"

#include <cmath>

namespace mrjam {

double damping_beta_for_restitution(double e) {
    const double l = std::log(e);
    return -l / std::sqrt(l * l + M_PI * M_PI);
}

double hertz_contact_duration(double reduced_mass, double reduced_radius, double effective_youngs,
                              double impact_speed) {
    const double k = 15.0 * reduced_mass / (16.0 * std::sqrt(reduced_radius) * effective_youngs);
    return 2.9432 * std::pow(k, 0.4) * std::pow(impact_speed, -0.2);
}

}  // namespace mrjam
