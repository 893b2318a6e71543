#include "jam/axial_resistance.hpp"

#include <algorithm>
#include <cmath>

#include "core/quadrature.hpp"
#include "terms/drag_term.hpp"

namespace mrjam {

double slab_section(double r, double h) {
    if (h <= 0 || h >= r) return M_PI * r * r;
    return 2.0 * (h * std::sqrt(r * r - h * h) + r * r * std::asin(h / r));
}

AxialResistance::AxialResistance(const ValveGeometry& valve, double slab_half_thickness, double z_lo, double z_hi,
                                 double cell_length, double feed_fraction, double supply_pressure)
    : z_lo_(z_lo), feed_(feed_fraction), pressure_(supply_pressure) {
    const std::size_t n = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround((z_hi - z_lo) / cell_length)));
    dz_ = (z_hi - z_lo) / n;
    volume_.resize(n);
    // The section is smooth between the valve's breakpoints (taper start, throat start, orifice
    // exit; it jumps at the exit), so each cell is split there and each piece integrated by
    // composite Simpson: exact for the full bore's quadratic cone, ~1e-9 for the slab's chord.
    const std::vector<double> breaks{valve.taper_start_z(), -0.5 * valve.throat_length, valve.throat_end_z()};
    auto section = [&](double z) { return slab_section(valve.passage_radius(z), slab_half_thickness); };
    for (std::size_t k = 0; k < n; ++k) {
        const double a = z_lo + k * dz_, b = a + dz_;
        std::vector<double> edges{a};
        for (double z : breaks)
            if (z > a && z < b) edges.push_back(z);
        edges.push_back(b);
        double v = 0;
        for (std::size_t e = 0; e + 1 < edges.size(); ++e) v += simpson_inside(section, edges[e], edges[e + 1], 8);
        volume_[k] = v;
    }
}

double kozeny_carman_factor(double phi, double feed) {
    // Capped below random close packing: a cell's count can exceed it when grain centres
    // crowd a cell boundary, and the factor must stay finite for the explicit step.
    phi = std::min(phi, 0.62);
    const double kc = phi * (1 - feed) * (1 - feed) / (feed * (1 - phi) * (1 - phi));
    return std::max(1.0, kc);
}

double AxialResistance::drag_factor(double phi) const { return kozeny_carman_factor(phi, feed_); }

AxialResistanceState AxialResistance::update(const System& s, ValveFlow& flow, bool drive, double supply) const {
    const std::size_t n = volume_.size();
    const auto& g = s.particles;
    std::vector<double> grain_volume(n, 0.0), d1(n, 0.0), dv(n, 0.0);
    std::vector<int> cell_of(g.size(), -1);
    for (std::size_t i = 0; i < g.size(); ++i) {
        const double k = std::floor((g.position[i].z - z_lo_) / dz_);
        if (k < 0 || k >= static_cast<double>(n)) continue;
        const auto c = static_cast<std::size_t>(k);
        cell_of[i] = static_cast<int>(c);
        grain_volume[c] += 4.0 / 3.0 * M_PI * g.radius[i] * g.radius[i] * g.radius[i];
    }
    AxialResistanceState out;
    std::vector<double> factor(n, 1.0);
    for (std::size_t k = 0; k < n; ++k) {
        const double phi = grain_volume[k] / volume_[k];
        factor[k] = drive ? drag_factor(phi) : 1.0;
        out.max_fraction = std::max(out.max_fraction, phi);
        out.max_drag_factor = std::max(out.max_drag_factor, factor[k]);
    }
    const double viscosity = carrier_viscosity(s);
    for (std::size_t i = 0; i < g.size(); ++i) {
        if (cell_of[i] < 0) continue;
        const auto c = static_cast<std::size_t>(cell_of[i]);
        const double drag = 6.0 * M_PI * viscosity * g.radius[i] * factor[c];
        d1[c] += drag * flow.unscaled(g.position[i]).z;
        dv[c] += drag * g.velocity[i].z;
    }
    double sum_d1 = 0, sum_dv = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const double section = volume_[k] / dz_;
        sum_d1 += d1[k] / section;
        sum_dv += dv[k] / section;
    }
    // Grains moving faster than the fluid (a release surge) cannot make the fluid run above
    // the circuit's open flow in this model, nor backwards.
    out.arrested_pressure = sum_d1;
    if (!drive) {
        out.stretch_pressure = sum_d1 - sum_dv;
        return out;
    }
    const double drive_pressure = supply >= 0 ? supply : pressure_;
    out.scale = std::clamp((drive_pressure + sum_dv) / (pressure_ + sum_d1), 0.0, drive_pressure / pressure_);
    out.stretch_pressure = out.scale * sum_d1 - sum_dv;
    flow.set_drag_factors(z_lo_, dz_, std::move(factor));
    flow.set_scale(out.scale);
    return out;
}

}  // namespace mrjam
