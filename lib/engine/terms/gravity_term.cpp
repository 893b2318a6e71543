#include "terms/gravity_term.hpp"

#include <cmath>

#include "system.hpp"

namespace mrjam {

double GravityTerm::effective_mass(double mass, double radius) const {
    const double volume = 4.0 / 3.0 * M_PI * radius * radius * radius;
    return mass - fluid_density_ * volume;
}

void GravityTerm::add_per_grain(const System& s, Vec3* f, std::size_t begin, std::size_t end) {
    const Particles& p = s.particles;
    for (std::size_t i = begin; i < end; ++i) f[i] += acceleration_ * effective_mass(p.mass[i], p.radius[i]);
}

double GravityTerm::potential_energy(const System& s) const {
    const Particles& p = s.particles;
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        e -= effective_mass(p.mass[i], p.radius[i]) * dot(acceleration_, p.position[i]);
    return e;
}

}  // namespace mrjam
