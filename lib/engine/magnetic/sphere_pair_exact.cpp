#include "magnetic/sphere_pair_exact.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "magnetic/magnetic_model.hpp"

namespace mrjam {

namespace {

// The sphere's reply to an incident regular harmonic of order n (radius 1): A_n = -gamma_n B_n.
double reply(double mu, int n) { return n * (mu - 1.0) / (n * mu + n + 1.0); }

int azimuthal_order(PairOrientation orientation) { return orientation == PairOrientation::axial ? 0 : 1; }

}  // namespace

// Hobson's theorem, (d/dx + i d/dy)^m (d/dz)^(n-m) (1/r) = (-1)^n (n-m)! r^-(n+1) P_n^m e^{i m phi},
// applied to 1/|r - s z| = sum_k sign(s)^k r^k P_k / |s|^(k+1), with d/dz r^k P_k = k r^(k-1) P_(k-1)
// and (d/dx + i d/dy) r^k P_k = -r^(k-1) P_(k-1)^1 e^{i phi}. Factorials by lgamma: orders reach
// thousands, where the binomial and |s|^-(l+n+1) each overflow but their product is below 1.
double translation_coefficient(int m, int l, int n, double offset) {
    if (m < 0 || m > 1 || l < m || n < std::max(m, 0) || (m == 1 && n < 1))
        throw std::invalid_argument("translation_coefficient: orders out of range");
    const int k = l + n;
    const double log_magnitude =
        m == 0
            ? std::lgamma(k + 1.0) - std::lgamma(n + 1.0) - std::lgamma(l + 1.0) - (k + 1) * std::log(std::abs(offset))
            : std::lgamma(k + 1.0) - std::lgamma(n + 0.0) - std::lgamma(l + 2.0) - (k + 1) * std::log(std::abs(offset));
    const bool negative_offset_sign = offset < 0 && (k % 2 == 1);  // sign(s)^k
    const bool hobson_sign = (n + m) % 2 == 1;                     // (-1)^n, and the extra -1 for m = 1
    const double sign = (negative_offset_sign != hobson_sign) ? -1.0 : 1.0;
    return sign * std::exp(log_magnitude);
}

SpherePairResponse sphere_pair_response(double mu, double separation, PairOrientation orientation, int order) {
    if (!(separation > 2.0)) throw std::invalid_argument("sphere pair: the centre distance must exceed the diameter");
    if (order < 1) throw std::invalid_argument("sphere pair: order must be at least 1");
    const int m = azimuthal_order(orientation);
    const int size = 2 * order;  // A^1_1..A^1_N, then A^2_1..A^2_N
    Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(size, size), dmatrix = Eigen::MatrixXd::Zero(size, size);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(size);
    for (int sphere = 0; sphere < 2; ++sphere) {
        const double offset = sphere == 0 ? separation : -separation;  // the other centre, seen from this one
        for (int l = 1; l <= order; ++l) {
            const int row = sphere * order + (l - 1);
            const double g = reply(mu, l);
            matrix(row, row) = 1.0;
            for (int n = 1; n <= order; ++n) {
                const int col = (1 - sphere) * order + (n - 1);
                const double t = g * translation_coefficient(m, l, n, offset);
                matrix(row, col) = t;
                dmatrix(row, col) = -t * (l + n + 1) / separation;
            }
        }
        // The applied potential is -r P_1^m e^{i m phi} about either centre: B_1 = -1.
        rhs(sphere * order) = reply(mu, 1);
    }
    // Dense LU with partial pivoting (the systems are a few thousand unknowns at most); the
    // derivative in the separation from the same factors: M da = -(dM/ds) a.
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(matrix);
    const Eigen::VectorXd a = lu.solve(rhs);
    if (!a.allFinite()) throw std::runtime_error("sphere pair: singular multipole system");
    const Eigen::VectorXd da = lu.solve(-(dmatrix * a));
    return {a(0) + a(order), da(0) + da(order), order};
}

SpherePairResponse converged_sphere_pair_response(double mu, double separation, PairOrientation orientation,
                                                  double relative_tolerance, int max_order) {
    SpherePairResponse previous = sphere_pair_response(mu, separation, orientation, 8);
    for (int order = 16; order <= max_order; order *= 2) {
        const SpherePairResponse next = sphere_pair_response(mu, separation, orientation, order);
        const bool alpha_done = std::abs(next.polarisability - previous.polarisability) <=
                                relative_tolerance * std::abs(next.polarisability);
        const bool force_done = std::abs(next.dpolarisability_ds - previous.dpolarisability_ds) <=
                                relative_tolerance * std::abs(next.dpolarisability_ds);
        if (alpha_done && force_done) return next;
        previous = next;
    }
    char message[200];
    std::snprintf(message, sizeof message,
                  "sphere pair: the multipole series did not converge by order %d at a gap of %.3g radii; "
                  "raise max_order or widen the gap",
                  max_order, separation - 2.0);
    throw std::runtime_error(message);
}

SpherePairResponse mutual_dipole_pair_response(double mu, double separation, PairOrientation orientation) {
    const double beta = clausius_mossotti(mu);
    // The other dipole's field at this centre, per unit of its moment over 4 pi: 2/s^3 along the
    // line of centres, -1/s^3 across it.
    const double k = orientation == PairOrientation::axial ? 2.0 : -1.0;
    const double s3 = separation * separation * separation;
    const double denominator = 1.0 - k * beta / s3;
    const double alpha = 2.0 * beta / denominator;
    const double dalpha = -2.0 * beta * (3.0 * k * beta / (s3 * separation)) / (denominator * denominator);
    return {alpha, dalpha, 1};
}

}  // namespace mrjam
