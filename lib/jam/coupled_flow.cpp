#include "jam/coupled_flow.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/quadrature.hpp"
#include "fluid/brinkman_slice.hpp"
#include "fluid/valve_flow.hpp"

namespace mrjam {

namespace {

constexpr double pi = std::numbers::pi;

}  // namespace

double clear_stretch_pressure(const ValveGeometry& valve, double z_lo, double z_hi, double jet_length, double viscosity,
                              double q) {
    // Midpoint rule on 4000 pieces: R_f(z) is piecewise linear, R_f^-4 smooth between its breaks.
    const int n = 4000;
    const double dz = (z_hi - z_lo) / n;
    double p = 0;
    for (int i = 0; i < n; ++i) {
        const double r = jet_stream_radius(valve, jet_length, z_lo + (i + 0.5) * dz);
        p += 8.0 * viscosity * q / (pi * r * r * r * r) * dz;
    }
    return p;
}

CoupledFlow::CoupledFlow(const ValveGeometry& valve, const CoupledFlowSettings& settings)
    : set_(settings),
      field_(std::make_shared<CoupledValveFlow>(valve, settings.z_lo, settings.z_hi, settings.cell_length,
                                                settings.rings, settings.jet_length)) {
    const auto& slices = field_->slices();
    const int m = field_->rings();
    if (!(set_.wall_gap >= 0) || set_.wall_gap > 0.5 * valve.throat_radius() / m)
        throw std::invalid_argument("coupled flow: the rings must be at least a grain diameter wide in the throat");
    volume_.assign(slices.size() * static_cast<std::size_t>(m), 0.0);
    // Ring j of slice k: the slab-cut annulus between j R_f(z) / m and (j + 1) R_f(z) / m, integrated
    // along the slice by composite Simpson (R_f is linear inside a slice: it never straddles a break).
    for (std::size_t k = 0; k < slices.size(); ++k)
        for (int j = 0; j < m; ++j) {
            auto ring = [&](double z) {
                const double R = field_->stream_radius(z);
                const double outer = j + 1 < m || !slices[k].walled ? (j + 1) * R / m : R - set_.wall_gap;
                return slab_section(outer, set_.slab_half_thickness) -
                       slab_section(j * R / m, set_.slab_half_thickness);
            };
            volume_[k * static_cast<std::size_t>(m) + static_cast<std::size_t>(j)] =
                simpson_inside(ring, slices[k].z_lo, slices[k].z_hi, 8);
        }
    // The clear fluid: each slice's profile at unit pressure gradient sets its conductance, the
    // circuit's size and (scaled to Q0) the field before the first update.
    q0_ = ValveFlow(valve, set_.bore_speed).reference_flow_rate();
    double resistance = 0;  // sum dz / Qa of the clear slices
    std::vector<double> u(volume_.size());
    for (std::size_t k = 0; k < slices.size(); ++k) {
        const BrinkmanRings clear{slices[k].radius, set_.viscosity, std::vector<double>(m, 0.0),
                                  std::vector<double>(m, 0.0)};
        const std::vector<double> unit = brinkman_profile(clear, 1.0);
        const double conductance = ring_flow_rate(unit, slices[k].radius);
        resistance += (slices[k].z_hi - slices[k].z_lo) / conductance;
        for (int j = 0; j < m; ++j)
            u[k * static_cast<std::size_t>(m) + static_cast<std::size_t>(j)] = q0_ / conductance * unit[j];
    }
    clear_pressure_ = q0_ * resistance;
    if (!(set_.supply_pressure > clear_pressure_))
        throw std::invalid_argument("fluid/supply_pressure: below what the clear fluid needs through the stretch");
    circuit_resistance_ = (set_.supply_pressure - clear_pressure_) / q0_;
    field_->set_field(u, std::vector<double>(volume_.size(), 1.0));
}

AxialResistanceState CoupledFlow::update(const System& s, double supply) const {
    const auto& slices = field_->slices();
    const auto m = static_cast<std::size_t>(field_->rings());
    const std::size_t cells = volume_.size();
    std::vector<double> grain_volume(cells, 0.0), radii(cells, 0.0), radius_speed(cells, 0.0);
    const auto& g = s.particles;
    for (std::size_t i = 0; i < g.size(); ++i) {
        const Vec3& x = g.position[i];
        const int ring = field_->ring_at(x);
        if (ring < 0) continue;  // in the jet's still corner
        const std::size_t c = field_->slice_at(x.z) * m + static_cast<std::size_t>(ring);
        const double a = g.radius[i];
        grain_volume[c] += 4.0 / 3.0 * pi * a * a * a;
        radii[c] += a;
        radius_speed[c] += a * g.velocity[i].z;
    }
    AxialResistanceState out;
    slice_pressure_.assign(slices.size(), 0.0);
    slice_fraction_.assign(slices.size(), 0.0);
    std::vector<double> factor(cells, 1.0);
    std::vector<double> unit(cells), grains(cells);  // a_k and b_k, slice-major
    std::vector<double> qa(slices.size()), qb(slices.size());
    double sum_b = 0, sum_resistance = 0;
    BrinkmanRings rings;
    rings.viscosity = set_.viscosity;
    rings.beta.resize(m);
    rings.grain_speed.resize(m);
    for (std::size_t k = 0; k < slices.size(); ++k) {
        rings.radius = slices[k].radius;
        std::fill(rings.grain_speed.begin(), rings.grain_speed.end(), 0.0);
        double slice_grains = 0, slice_volume = 0;
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t c = k * m + j;
            const double phi = grain_volume[c] / volume_[c];
            factor[c] = kozeny_carman_factor(phi, set_.feed_fraction);
            out.max_drag_factor = std::max(out.max_drag_factor, factor[c]);
            rings.beta[j] = 6.0 * pi * set_.viscosity * factor[c] * radii[c] / volume_[c];
            slice_grains += grain_volume[c];
            slice_volume += volume_[c];
        }
        out.max_fraction = std::max(out.max_fraction, slice_grains / slice_volume);
        slice_fraction_[k] = slice_grains / slice_volume;
        const std::vector<double> a_k = brinkman_profile(rings, 1.0);
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t c = k * m + j;
            rings.grain_speed[j] = radii[c] > 0 ? radius_speed[c] / radii[c] : 0.0;
        }
        const std::vector<double> b_k = brinkman_profile(rings, 0.0);
        qa[k] = ring_flow_rate(a_k, slices[k].radius);
        qb[k] = ring_flow_rate(b_k, slices[k].radius);
        for (std::size_t j = 0; j < m; ++j) {
            unit[k * m + j] = a_k[j];
            grains[k * m + j] = b_k[j];
        }
        const double dz = slices[k].z_hi - slices[k].z_lo;
        sum_b += dz * qb[k] / qa[k];
        sum_resistance += dz / qa[k];
    }
    // P = R_c Q + sum_k dz_k (Q - Qb_k) / Qa_k; clear fluid runs at Q0 P / P_0 at most.
    const double drive_pressure = supply >= 0 ? supply : set_.supply_pressure;
    const double q = std::clamp((drive_pressure + sum_b) / (circuit_resistance_ + sum_resistance), 0.0,
                                q0_ * drive_pressure / set_.supply_pressure);
    std::vector<double> u(cells);
    out.stretch_pressure = 0;
    for (std::size_t k = 0; k < slices.size(); ++k) {
        const double gradient = (q - qb[k]) / qa[k];
        slice_pressure_[k] = gradient * (slices[k].z_hi - slices[k].z_lo);
        out.stretch_pressure += slice_pressure_[k];
        for (std::size_t j = 0; j < m; ++j) u[k * m + j] = gradient * unit[k * m + j] + grains[k * m + j];
    }
    out.scale = q / q0_;
    out.arrested_pressure = q0_ * sum_resistance;  // the grains at rest, as binned, at Q0
    field_->set_field(u, factor);
    return out;
}

}  // namespace mrjam
