#pragma once
// Analytic spin limits of a self-gravitating body, to set beside the spin-up's events:
// - the rigid sphere's: a surface grain at the equator lifts off at omega^2 = 4 pi G rho / 3;
// - Holsapple's (2007, Icarus 187, 500-509) for a cohesionless Drucker-Prager body: the
//   volume-averaged stresses of a uniform ellipsoid spinning about its shortest axis c,
//     s_x = (rho w^2 - 2 pi G rho^2 A_x) a^2 / 5,  s_y = (rho w^2 - 2 pi G rho^2 A_y) b^2 / 5,
//     s_z = -2 pi G rho^2 A_z c^2 / 5  (tension positive),
//   at the yield surface sqrt(J2) + s I1 = 0 with s = 2 sin(phi) / (sqrt(3) (3 - sin(phi))), the
//   outer cone fitted to Mohr-Coulomb in triaxial compression. A_i are the ellipsoid's gravity
//   shape constants (2/3 each for a sphere). For a sphere the limit is
//     w^2 = (4 pi G rho / 3) 3 s / (1 / sqrt(3) + 2 s):  0 at phi = 0, the rigid sphere's at 90 deg.
#include <array>

namespace mrjam {

// A_i = a b c Int_0^inf du / ((a_i^2 + u) sqrt((a^2 + u)(b^2 + u)(c^2 + u))); they sum to 2.
std::array<double, 3> ellipsoid_shape_constants(double a, double b, double c);

double rigid_sphere_spin_limit(double density);  // rad/s

// The spin (rad/s) at which the ellipsoid of semi-axes a >= b >= c (spinning about c) at bulk
// `density` reaches the cohesionless Drucker-Prager limit for the friction angle (rad).
double drucker_prager_spin_limit(double density, const std::array<double, 3>& semi_axes, double friction_angle);

// The friction angle (rad) whose Drucker-Prager limit is `spin`; NaN if it exceeds the 90-degree
// limit (no friction alone holds the body there).
double friction_angle_for_spin(double density, const std::array<double, 3>& semi_axes, double spin);

}  // namespace mrjam
