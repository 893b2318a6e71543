#include "shear/dimensionless.hpp"

#include <limits>

#include "magnetic/magnetic_model.hpp"

namespace mrjam {

double magnetic_stress_scale(double flux_density, double beta) {
    const double h0 = flux_density / kMu0;
    return 2 * kMu0 * beta * beta * h0 * h0;
}

double mason_number(double viscosity, double shear_rate, double flux_density, double beta) {
    const double scale = magnetic_stress_scale(flux_density, beta);
    return scale > 0 ? viscosity * shear_rate / scale : std::numeric_limits<double>::infinity();
}

}  // namespace mrjam
