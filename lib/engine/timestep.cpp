#include "timestep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contact/restitution.hpp"
#include "core/format.hpp"
#include "terms/drag_term.hpp"
#include "terms/pair_damping_term.hpp"
#include "terms/self_gravity_term.hpp"

namespace mrjam {

namespace {

// Self-gravity's time scale: an orbit grazing a grain of density rho has the period
// sqrt(3 pi / (G rho)), whatever its size; a tenth of it (so the safety fraction gives 50-100 steps
// an orbit). Infinity without self-gravity. Every grain's density bounds its neighbours' fall.
double self_gravity_time(const System& s) {
    const SelfGravityTerm* t = s.terms.find<SelfGravityTerm>();
    const Particles& p = s.particles;
    if (!t || p.size() == 0) return std::numeric_limits<double>::infinity();
    double rho = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        rho = std::max(rho, p.mass[i] / (4.0 / 3.0 * M_PI * p.radius[i] * p.radius[i] * p.radius[i]));
    return 0.1 * std::sqrt(3 * M_PI / (t->settings().constant * rho));
}

// The grain with the least of some measure, in one pass.
struct Shortest {
    static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    double value = std::numeric_limits<double>::infinity();
    std::size_t grain = kNone;
    void offer(double v, std::size_t i) {
        if (grain == kNone || v < value) value = v, grain = i;
    }
};

// Grain i's mass over what its material's density gives its size: 1 unless mass-scaled (exactly
// 1 then, so a run without scaling keeps its step to the last bit).
double mass_scale(const Material& mat, const Particles& p, std::size_t i) {
    const double r = p.radius[i];
    const double scale = p.mass[i] / (mat.density * 4.0 / 3.0 * M_PI * r * r * r);
    return std::fabs(scale - 1) < 1e-9 ? 1.0 : scale;
}

}  // namespace

TimestepLimits timestep_limits(const System& s, double characteristic_speed) {
    TimestepLimits lim;
    const double inf = std::numeric_limits<double>::infinity();
    lim.rayleigh = lim.hertz = lim.drag = lim.stokes = lim.pair_damping = inf;
    const Particles& p = s.particles;
    const double viscosity = carrier_viscosity(s), pair_damping = pair_damping_coefficient(s);
    // The grains of each material that set its limits: the smallest, unless some carry more mass
    // than their size gives (a batch's mass_scaling). The Rayleigh time, r sqrt(rho / G), and the
    // Stokes time, m / (6 pi mu r), are shortest for the least m / r; the Hertz time of a pair of
    // alike grains, ~ (m^2 / r)^(1/5), for the least m^2 / r; the pair damping's for the least m.
    std::vector<Shortest> rayleigh(s.materials.size()), hertz(s.materials.size()), damping(s.materials.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double m = p.mass[i], r = p.radius[i];
        rayleigh[p.material[i]].offer(m / r, i);
        hertz[p.material[i]].offer(m * m / r, i);
        damping[p.material[i]].offer(m, i);
    }
    for (std::size_t m = 0; m < s.materials.size(); ++m) {
        if (rayleigh[m].grain == Shortest::kNone) continue;
        const Material& mat = s.materials[m];
        if (s.physics.contact) {
            const std::size_t i = rayleigh[m].grain, h = hertz[m].grain;
            const double r = p.radius[i];
            const double density = mat.density * mass_scale(mat, p, i);
            lim.rayleigh = std::min(lim.rayleigh, M_PI * r * std::sqrt(density / mat.shear_modulus()) /
                                                      (0.1631 * mat.poisson_ratio + 0.8766));
            // Two such grains meeting head on.
            const double ystar = s.pairs(static_cast<std::uint16_t>(m), static_cast<std::uint16_t>(m)).effective_youngs;
            lim.hertz = std::min(
                lim.hertz, hertz_contact_duration(0.5 * p.mass[h], 0.5 * p.radius[h], ystar, characteristic_speed));
            // Against a wall (R* = R, m* = m): shorter than grain-grain when the wall is stiffer.
            for (const Wall& w : s.walls) {
                const double ystar_wall = s.pairs(static_cast<std::uint16_t>(m), w.material).effective_youngs;
                lim.hertz = std::min(lim.hertz,
                                     hertz_contact_duration(p.mass[h], p.radius[h], ystar_wall, characteristic_speed));
            }
        }
        const std::size_t i = rayleigh[m].grain;
        if (viscosity > 0) lim.stokes = std::min(lim.stokes, p.mass[i] / (6.0 * M_PI * viscosity * p.radius[i]));
        // Pair damping relaxes the relative velocity of two such grains in m* / c (m* = m/2).
        // Explicit integration is stable up to 2 m* / (z c) with z contacts, so the default
        // safety fraction 0.1 of this time covers up to 20 contacts.
        if (pair_damping > 0)
            lim.pair_damping = std::min(lim.pair_damping, 0.5 * p.mass[damping[m].grain] / pair_damping);
    }
    lim.drag = std::min(lim.stokes, lim.pair_damping);
    lim.gravity = self_gravity_time(s);
    lim.critical = std::min({lim.rayleigh, lim.hertz, lim.drag, lim.gravity});
    lim.limiting = lim.critical == lim.rayleigh ? "Rayleigh time of the smallest grain"
                   : lim.critical == lim.hertz  ? "Hertz contact time of the smallest pair (or grain and wall)"
                   : lim.critical == lim.drag   ? "drag (Stokes, or pair damping) relaxation time of the smallest grain"
                                                : "a tenth of a grazing orbit's period about the densest grain "
                                                  "(self-gravity)";
    lim.stable_limit = kMaxStepFraction * lim.critical;
    return lim;
}

// Explicit drag is stable only for steps below twice the Stokes relaxation time, so a viscous
// carrier or fine grains can set a step far below what the contacts need: the run is still right,
// but that many times longer (1e4 Pa s took the valve's 44 um grains from a 36 ns step to 0.005 ns),
// which a user should hear before waiting for it.
// Without a contact law there is nothing to compare with, and no warning.
std::string drag_limited_step_warning(const TimestepLimits& l) {
    constexpr double kNotable = 10;
    const double contact = std::min(l.rayleigh, l.hertz);
    if (!std::isfinite(contact) || !(l.drag < contact / kNotable)) return {};
    const std::string ratio = format_number(std::round(contact / l.drag));
    if (l.pair_damping <= l.stokes)
        return "the pair damping's relaxation time (" + format_number(l.drag, 3) +
               " s, m* / c of the two smallest grains) sets the time step, " + ratio +
               " times shorter than the contacts need, and the run takes that many more steps; a smaller "
               "contact/pair_damping shortens it";
    return "the drag's relaxation time (" + format_number(l.drag, 3) + " s, the smallest grain's m / (6 pi mu R)) " +
           "sets the time step, " + ratio +
           " times shorter than the contacts need: the grains are overdamped by the carrier and the run "
           "takes that many more steps; a lower viscosity or larger grains shorten it";
}

}  // namespace mrjam
