#include "shear/flow_curve_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>

namespace mrjam {
namespace {

constexpr int kMaxParams = 3;

// Linear least squares y ~ sum_k c_k basis_k(row): coefficients, and the covariance as the larger
// (per parameter) of the residual-scatter and the propagated-error-bar estimates.
struct LinearFit {
    bool ok = false;
    std::array<double, kMaxParams> coef{};
    std::array<double, kMaxParams> sigma{};
    double ssr = 0;
};

LinearFit least_squares(const std::vector<std::array<double, kMaxParams>>& rows, const std::vector<double>& y,
                        const std::vector<double>& y_error, int p) {
    LinearFit fit;
    const std::size_t n = rows.size();
    if (n < static_cast<std::size_t>(p)) return fit;
    // The normal equations (p <= 3): inverted by Eigen, whose inverse is needed for the errors.
    Eigen::MatrixXd design(n, p);
    Eigen::VectorXd values(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < p; ++a) design(static_cast<Eigen::Index>(i), a) = rows[i][a];
        values(static_cast<Eigen::Index>(i)) = y[i];
    }
    const Eigen::MatrixXd normal = design.transpose() * design;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(normal);
    if (!lu.isInvertible()) return fit;
    const Eigen::MatrixXd inv = lu.inverse();
    const Eigen::VectorXd coef = inv * (design.transpose() * values);
    for (int a = 0; a < p; ++a) fit.coef[a] = coef(a);
    for (std::size_t i = 0; i < n; ++i) {
        double model = 0;
        for (int a = 0; a < p; ++a) model += fit.coef[a] * rows[i][a];
        fit.ssr += (y[i] - model) * (y[i] - model);
    }
    // Propagated: c = inv A^T y, so cov = inv A^T diag(s^2) A inv.
    std::array<double, kMaxParams> var_prop{};
    for (std::size_t i = 0; i < n; ++i) {
        std::array<double, kMaxParams> g{};  // d coef / d y_i
        for (int a = 0; a < p; ++a)
            for (int b = 0; b < p; ++b) g[a] += inv(a, b) * rows[i][b];
        for (int a = 0; a < p; ++a) var_prop[a] += g[a] * g[a] * y_error[i] * y_error[i];
    }
    const double s2 = n > static_cast<std::size_t>(p) ? fit.ssr / static_cast<double>(n - p) : 0.0;
    for (int a = 0; a < p; ++a) fit.sigma[a] = std::sqrt(std::max(var_prop[a], s2 * inv(a, a)));
    fit.ok = true;
    return fit;
}

double rms_of(const std::vector<FlowPoint>& pts, const ModelFit& f) {
    double s = 0;
    for (const auto& q : pts) s += (q.stress - f.stress_at(q.rate)) * (q.stress - f.stress_at(q.rate));
    return pts.empty() ? 0.0 : std::sqrt(s / static_cast<double>(pts.size()));
}

std::vector<FlowPoint> usable(const std::vector<FlowPoint>& curve, double min_rate) {
    std::vector<FlowPoint> out;
    for (const auto& q : curve)
        if (q.rate >= min_rate && q.rate > 0 && std::isfinite(q.stress)) out.push_back(q);
    return out;
}

}  // namespace

double ModelFit::stress_at(double rate) const {
    if (model == "bingham") return yield_stress + viscosity * rate;
    if (model == "casson") {
        const double s = std::sqrt(yield_stress) + std::sqrt(viscosity * rate);
        return s * s;
    }
    return yield_stress + consistency * std::pow(rate, flow_index);
}

ModelFit fit_bingham(const std::vector<FlowPoint>& curve, double min_rate) {
    ModelFit f;
    f.model = "bingham";
    f.min_rate = min_rate;
    const auto pts = usable(curve, min_rate);
    f.points = pts.size();
    if (pts.size() < 2) {
        f.note = "needs at least two rates at or above " + std::to_string(min_rate) + " 1/s";
        return f;
    }
    std::vector<std::array<double, kMaxParams>> rows;
    std::vector<double> y, e;
    for (const auto& q : pts) {
        rows.push_back({1.0, q.rate, 0.0});
        y.push_back(q.stress);
        e.push_back(q.error);
    }
    const LinearFit lf = least_squares(rows, y, e, 2);
    if (!lf.ok) {
        f.note = "rates are all equal";
        return f;
    }
    f.ok = true;
    f.yield_stress = lf.coef[0];
    f.yield_stress_error = lf.sigma[0];
    f.viscosity = lf.coef[1];
    f.viscosity_error = lf.sigma[1];
    f.rms_residual = rms_of(pts, f);
    // Said, as for Casson: a short or noisy study can fit a line that no Bingham fluid has.
    if (f.yield_stress < 0) f.note = "negative intercept: no yield stress in the Bingham sense";
    if (f.viscosity < 0) f.note = "stress falls with rate: the Bingham viscosity is not defined";
    return f;
}

ModelFit fit_casson(const std::vector<FlowPoint>& curve) {
    ModelFit f;
    f.model = "casson";
    std::vector<FlowPoint> pts;
    for (const auto& q : usable(curve, 0.0))
        if (q.stress > 0) pts.push_back(q);
    f.points = pts.size();
    if (pts.size() < 2) {
        f.note = "needs at least two rates with positive stress";
        return f;
    }
    std::vector<std::array<double, kMaxParams>> rows;
    std::vector<double> y, e;
    for (const auto& q : pts) {
        rows.push_back({1.0, std::sqrt(q.rate), 0.0});
        y.push_back(std::sqrt(q.stress));
        e.push_back(q.error / (2.0 * std::sqrt(q.stress)));  // d sqrt(tau) = d tau / (2 sqrt(tau))
    }
    const LinearFit lf = least_squares(rows, y, e, 2);
    if (!lf.ok) {
        f.note = "rates are all equal";
        return f;
    }
    f.ok = true;
    const double a = lf.coef[0], b = lf.coef[1];
    if (a < 0) f.note = "negative intercept of sqrt(tau): no yield stress in the Casson sense";
    if (b < 0) f.note = "stress falls with rate: the Casson viscosity is not defined";
    f.yield_stress = a * a;
    f.yield_stress_error = 2 * std::abs(a) * lf.sigma[0];
    f.viscosity = b * b;
    f.viscosity_error = 2 * std::abs(b) * lf.sigma[1];
    f.rms_residual = rms_of(pts, f);
    return f;
}

ModelFit fit_herschel_bulkley(const std::vector<FlowPoint>& curve) {
    ModelFit f;
    f.model = "herschel_bulkley";
    const auto pts = usable(curve, 0.0);
    f.points = pts.size();
    if (pts.size() < 3) {
        f.note = "needs at least three rates";
        return f;
    }
    // For a fixed flow index the model is linear in (tau_y, K): minimise the residual over n
    // alone by golden-section search, solving the linear problem at each n.
    auto solve = [&](double n, LinearFit& lf) {
        std::vector<std::array<double, kMaxParams>> rows;
        std::vector<double> y, e;
        for (const auto& q : pts) {
            rows.push_back({1.0, std::pow(q.rate, n), 0.0});
            y.push_back(q.stress);
            e.push_back(q.error);
        }
        lf = least_squares(rows, y, e, 2);
        return lf.ok ? lf.ssr : 1e300;
    };
    // The residual need not be unimodal in n over a wide interval: bracket on a coarse grid first.
    const double n_lo = 0.02, n_hi = 3.0;
    const int grid = 150;
    double best_n = n_lo, best = 1e300;
    LinearFit lf;
    for (int k = 0; k <= grid; ++k) {
        const double n = n_lo + (n_hi - n_lo) * k / grid;
        const double r = solve(n, lf);
        if (r < best) {
            best = r;
            best_n = n;
        }
    }
    const double step = (n_hi - n_lo) / grid;
    double a = std::max(n_lo, best_n - step), b = std::min(n_hi, best_n + step);
    const double g = (std::sqrt(5.0) - 1) / 2;
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = solve(c, lf), fd = solve(d, lf);
    for (int it = 0; it < 200 && b - a > 1e-13; ++it) {
        if (fc < fd) {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = solve(c, lf);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = solve(d, lf);
        }
    }
    const double n = 0.5 * (a + b);
    if (solve(n, lf) >= 1e300) {
        f.note = "rates are all equal";
        return f;
    }
    f.ok = true;
    f.flow_index = n;
    f.yield_stress = lf.coef[0];
    f.consistency = lf.coef[1];
    // Uncertainties from the full three-parameter linearisation at the optimum.
    std::vector<std::array<double, kMaxParams>> rows;
    std::vector<double> y, e;
    for (const auto& q : pts) {
        const double gn = std::pow(q.rate, n);
        rows.push_back({1.0, gn, f.consistency * gn * std::log(q.rate)});
        y.push_back(q.stress);
        e.push_back(q.error);
    }
    const LinearFit lin = least_squares(rows, y, e, 3);
    if (lin.ok) {
        f.yield_stress_error = lin.sigma[0];
        f.flow_index_error = lin.sigma[2];
    } else {
        f.note = "flow index poorly determined (singular linearisation)";
    }
    f.rms_residual = rms_of(pts, f);
    // A flat or non-monotonic curve leaves n undetermined: the search then stops at a bound and
    // tau_y trades off against K without meaning.
    if (n < n_lo + 1e-3 || n > n_hi - 1e-3)
        f.note = "flow index at the search bound (" + std::to_string(n_lo) + " to " + std::to_string(n_hi) +
                 "): the curve does not determine it, so this yield stress is not meaningful";
    return f;
}

nlohmann::json to_json(const ModelFit& f) {
    nlohmann::json j = {{"model", f.model}, {"ok", f.ok}, {"points", f.points}};
    if (!f.note.empty()) j["note"] = f.note;
    if (!f.ok) return j;
    j["yield_stress_Pa"] = f.yield_stress;
    j["yield_stress_error_Pa"] = f.yield_stress_error;
    j["rms_residual_Pa"] = f.rms_residual;
    if (f.model == "herschel_bulkley") {
        j["consistency_Pa_s_n"] = f.consistency;
        j["flow_index"] = f.flow_index;
        j["flow_index_error"] = f.flow_index_error;
    } else {
        j["plastic_viscosity_Pa_s"] = f.viscosity;
        j["plastic_viscosity_error_Pa_s"] = f.viscosity_error;
    }
    if (f.model == "bingham") j["min_rate_1_s"] = f.min_rate;
    return j;
}

}  // namespace mrjam
