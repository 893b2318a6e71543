#include "fluid/coupled_valve_flow.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/quadrature.hpp"

namespace mrjam {

CoupledValveFlow::CoupledValveFlow(const ValveGeometry& valve, double z_lo, double z_hi, double cell_length, int rings,
                                   double jet_length)
    : valve_(valve), rings_(rings), jet_length_(jet_length) {
    if (rings < 1 || !(cell_length > 0) || !(z_hi > z_lo) || !(jet_length > 0))
        throw std::invalid_argument(
            "coupled valve flow: needs rings >= 1, a positive cell and jet length and z_hi > z_lo");
    std::vector<double> cuts{z_lo};
    const double exit = valve.throat_end_z();
    for (double z : {valve.taper_start_z(), -0.5 * valve.throat_length, exit, exit + jet_length})
        if (z > cuts.back() + 1e-12 * (z_hi - z_lo) && z < z_hi) cuts.push_back(z);
    cuts.push_back(z_hi);
    for (std::size_t p = 0; p + 1 < cuts.size(); ++p) {
        const double a = cuts[p], b = cuts[p + 1];
        const auto n = std::max<long>(1, std::lround((b - a) / cell_length));
        for (long i = 0; i < n; ++i) {
            const double lo = a + (b - a) * static_cast<double>(i) / static_cast<double>(n);
            const double hi = a + (b - a) * static_cast<double>(i + 1) / static_cast<double>(n);
            const double mid = 0.5 * (lo + hi);
            slices_.push_back(
                {lo, hi, resistance_radius(lo, hi), mid < exit || mid > exit + jet_length, static_cast<int>(p)});
        }
    }
    speed_.assign(slices_.size() * static_cast<std::size_t>(rings_), 0.0);
    factor_.assign(speed_.size(), 1.0);
    build_slice_table();
}

void CoupledValveFlow::build_slice_table() {
    const double lo = slices_.front().z_lo, hi = slices_.back().z_hi;
    double narrowest = hi - lo;
    for (const FlowSlice& s : slices_) narrowest = std::min(narrowest, s.z_hi - s.z_lo);
    const auto bins = static_cast<std::size_t>(std::ceil((hi - lo) / narrowest));
    table_origin_ = lo;
    table_inverse_width_ = static_cast<double>(bins) / (hi - lo);
    table_slice_.resize(bins);
    std::size_t k = 0;
    for (std::size_t b = 0; b < bins; ++b) {
        const double centre = lo + (static_cast<double>(b) + 0.5) / table_inverse_width_;
        while (k + 1 < slices_.size() && !(centre < slices_[k].z_hi)) ++k;
        table_slice_[b] = static_cast<std::uint32_t>(k);
    }
}

// The first slice whose upper end lies above z (the last if none; the first below the grid), as
// a binary search would find it: the table's guess is walked to the exact slice, so a rounding
// in the bin index never changes the answer.
std::size_t CoupledValveFlow::slice_at(double z) const {
    const double t = (z - table_origin_) * table_inverse_width_;
    const std::size_t last_bin = table_slice_.size() - 1;
    const std::size_t bin = t > 0 ? (t < static_cast<double>(last_bin) ? static_cast<std::size_t>(t) : last_bin) : 0;
    std::size_t k = table_slice_[bin];
    while (k > 0 && z < slices_[k - 1].z_hi) --k;
    while (k + 1 < slices_.size() && !(z < slices_[k].z_hi)) ++k;
    return k;
}

int CoupledValveFlow::ring_at(const Vec3& x) const {
    return ring_of(x.z, std::sqrt(x.x * x.x + x.y * x.y), stream_radius(x.z));
}

int CoupledValveFlow::ring_of(double z, double r, double rf) const {
    if (r >= rf && rf < valve_.passage_radius(z)) return -1;  // the jet's still corner
    return std::clamp(static_cast<int>(r / rf * rings_), 0, rings_ - 1);
}

double CoupledValveFlow::factor_in(double z, std::size_t k, double r, double rf) const {
    if (z < slices_.front().z_lo || z >= slices_.back().z_hi) return 1.0;
    const int j = ring_of(z, r, rf);
    return factor_[k * static_cast<std::size_t>(rings_) + static_cast<std::size_t>(j < 0 ? rings_ - 1 : j)];
}

double CoupledValveFlow::stream_radius(double z) const { return jet_stream_radius(valve_, jet_length_, z); }

// The radius whose Poiseuille resistance is the slice's: (mean of R_f^-4)^(-1/4), by composite
// Simpson (R_f is linear inside a slice). In the jet R_f doubles within a few slices, and the
// centre's radius alone would miss the clear resistance by ~10 % there.
double CoupledValveFlow::resistance_radius(double lo, double hi) const {
    auto inverse_fourth = [&](double z) { return std::pow(stream_radius(z), -4.0); };
    return std::pow(simpson_inside(inverse_fourth, lo, hi, 16) / (hi - lo), -0.25);
}

double CoupledValveFlow::stream_slope(double z) const { return jet_stream_slope(valve_, jet_length_, z); }

double CoupledValveFlow::slice_profile(std::size_t k, double xi) const {
    const double* u = speed_.data() + k * static_cast<std::size_t>(rings_);
    const double s = xi * rings_ - 0.5;  // in ring-centre units
    if (s <= 0) return u[0];             // the axis: du/dr = 0
    const int j = static_cast<int>(s);
    const double w = s - j;
    if (j + 1 >= rings_) return u[rings_ - 1] * std::max(0.0, 1.0 - 2.0 * w);  // to 0 at the wall, half a ring out
    return u[j] * (1.0 - w) + u[j + 1] * w;
}

Vec3 CoupledValveFlow::velocity(const Vec3& x, double) const {
    const double R = stream_radius(x.z);
    const double r = std::sqrt(x.x * x.x + x.y * x.y);
    if (r >= R) return {};
    return velocity_in(x, R, r, slice_at(x.z));
}

Vec3 CoupledValveFlow::velocity_in(const Vec3& x, double R, double r, std::size_t k) const {
    const double xi = r / R;
    // The neighbour to interpolate with: the slice centre on the other side of z, in the same piece.
    std::size_t other = k;
    if (x.z < slices_[k].centre() && k > 0 && slices_[k - 1].piece == slices_[k].piece) other = k - 1;
    if (x.z > slices_[k].centre() && k + 1 < slices_.size() && slices_[k + 1].piece == slices_[k].piece) other = k + 1;
    double flux_weighted = slice_profile(k, xi) * slices_[k].radius * slices_[k].radius;
    if (other != k) {
        const double ck = slices_[k].centre(), co = slices_[other].centre();
        const double w = (x.z - ck) / (co - ck);
        flux_weighted += w * (slice_profile(other, xi) * slices_[other].radius * slices_[other].radius - flux_weighted);
    }
    const double uz = flux_weighted / (R * R);
    const double radial = uz * stream_slope(x.z) / R;  // u_r / r: streamlines at fixed r / R_f
    return {radial * x.x, radial * x.y, uz};
}

double CoupledValveFlow::drag_factor(const Vec3& x) const {
    return factor_in(x.z, slice_at(x.z), std::sqrt(x.x * x.x + x.y * x.y), stream_radius(x.z));
}

FlowField::Drag CoupledValveFlow::drag_at(const Vec3& x, double) const {
    const double R = stream_radius(x.z);
    const double r = std::sqrt(x.x * x.x + x.y * x.y);
    const std::size_t k = slice_at(x.z);
    return {r >= R ? Vec3{} : velocity_in(x, R, r, k), factor_in(x.z, k, r, R)};
}

void CoupledValveFlow::set_field(const std::vector<double>& axial_speed, const std::vector<double>& drag_factors) {
    if (axial_speed.size() != speed_.size() || drag_factors.size() != factor_.size())
        throw std::invalid_argument("coupled valve flow: field of the wrong size for the grid");
    speed_ = axial_speed;
    factor_ = drag_factors;
}

}  // namespace mrjam
