#include "asteroid/heap_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace mrjam {

SlopeFit fit_slope(const std::vector<double>& x, const std::vector<double>& z) {
    SlopeFit f;
    f.points = static_cast<int>(x.size());
    if (f.points < 3) return f;
    double sx = 0, sz = 0, sxx = 0, sxz = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sx += x[i];
        sz += z[i];
        sxx += x[i] * x[i];
        sxz += x[i] * z[i];
    }
    const double n = static_cast<double>(x.size()), det = n * sxx - sx * sx;
    if (det == 0) {
        f.points = 0;
        return f;
    }
    f.slope = (n * sxz - sx * sz) / det;
    f.intercept = (sz - f.slope * sx) / n;
    f.angle_deg = std::atan(std::fabs(f.slope)) * 180.0 / M_PI;
    return f;
}

namespace {

// The median surface height of the bins behind the gate: the column's top where it stood, which a
// chain standing on it (one bin) does not move.
double plateau_height(const HeapProfile& h, double gate) {
    std::vector<double> behind;
    for (std::size_t k = 0; k < h.x.size(); ++k)
        if (h.x[k] < gate) behind.push_back(h.height[k]);
    if (behind.empty()) return h.peak;
    std::nth_element(behind.begin(), behind.begin() + behind.size() / 2, behind.end());
    return behind[behind.size() / 2];
}

// Downhill of the last bin at or above `high`: where the surface first falls below `high`, and
// then below `low`, each interpolated between the bin centres on either side.
FaceChord face_chord(const HeapProfile& h, double high, double low) {
    FaceChord c;
    c.z_high = high;
    c.z_low = low;
    std::size_t start = h.height.size();
    for (std::size_t k = 0; k < h.height.size(); ++k)
        if (h.height[k] >= high) start = k;
    if (start + 1 >= h.height.size()) return c;
    auto crossing = [&](double level, std::size_t from, double& x) {
        for (std::size_t k = from + 1; k < h.height.size(); ++k)
            if (h.height[k] < level) {
                const double above = h.height[k - 1], below = h.height[k];
                x = h.x[k - 1] + (h.x[k] - h.x[k - 1]) * (above - level) / (above - below);
                return true;
            }
        return false;
    };
    if (!crossing(high, start, c.x_high) || !crossing(low, start, c.x_low) || c.x_low <= c.x_high) return c;
    c.found = true;
    c.angle_deg = std::atan((high - low) / (c.x_low - c.x_high)) * 180.0 / M_PI;
    return c;
}

}  // namespace

HeapProfile measure_heap(const Particles& p, double length, double width, double gate, double bin) {
    HeapProfile h;
    h.bin = bin;
    const std::size_t bins = static_cast<std::size_t>(std::ceil(length / bin));
    h.height.assign(bins, 0.0);
    double front = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.position[i].x;
        const std::size_t k = std::min(bins - 1, static_cast<std::size_t>(std::max(0.0, x) / bin));
        h.height[k] = std::max(h.height[k], p.position[i].z + p.radius[i]);
        front = std::max(front, x + p.radius[i]);
    }
    for (std::size_t k = 0; k < bins; ++k) h.x.push_back((k + 0.5) * bin);
    h.top = h.height;
    for (std::size_t k = 0; k < bins; ++k) {
        double w[3] = {h.top[k > 0 ? k - 1 : k], h.top[k], h.top[k + 1 < bins ? k + 1 : k]};
        std::sort(w, w + 3);
        h.height[k] = w[1];
    }
    h.peak = *std::max_element(h.height.begin(), h.height.end());
    for (double z : h.height) h.volume += z * bin * width;
    h.runout = std::max(0.0, front - gate);
    // Downhill of the last bin at 90 % of the peak: the slope, its upper and lower halves.
    std::size_t start = 0;
    for (std::size_t k = 0; k < bins; ++k)
        if (h.height[k] >= 0.9 * h.peak) start = k;
    std::vector<double> xs, zs, xu, zu, xl, zl;
    for (std::size_t k = start; k < bins; ++k) {
        const double z = h.height[k];
        if (z <= 0.1 * h.peak || z >= 0.9 * h.peak) continue;
        xs.push_back(h.x[k]);
        zs.push_back(z);
        (z >= 0.5 * h.peak ? xu : xl).push_back(h.x[k]);
        (z >= 0.5 * h.peak ? zu : zl).push_back(z);
    }
    h.slope = fit_slope(xs, zs);
    h.upper = fit_slope(xu, zu);
    h.lower = fit_slope(xl, zl);
    h.plateau = plateau_height(h, gate);
    h.face = face_chord(h, 0.9 * h.plateau, 0.1 * h.plateau);
    h.face_upper = face_chord(h, 0.9 * h.plateau, 0.5 * h.plateau);
    h.face_lower = face_chord(h, 0.5 * h.plateau, 0.1 * h.plateau);
    return h;
}

nlohmann::json to_json(const HeapProfile& h) {
    auto fit = [](const SlopeFit& f) -> nlohmann::json {
        if (f.points < 3) return {{"points", f.points}, {"angle_deg", nullptr}};
        return {{"points", f.points}, {"angle_deg", f.angle_deg}, {"slope", f.slope}, {"intercept_m", f.intercept}};
    };
    auto chord = [](const FaceChord& c) -> nlohmann::json {
        if (!c.found) return {{"angle_deg", nullptr}};
        return {{"angle_deg", c.angle_deg}, {"from_m", {c.x_high, c.z_high}}, {"to_m", {c.x_low, c.z_low}}};
    };
    return {
        {"bin_m", h.bin},
        {"peak_height_m", h.peak},
        {"plateau_height_m", h.plateau},
        {"angle_of_repose", chord(h.face)},
        {"upper_slope", chord(h.face_upper)},
        {"lower_slope", chord(h.face_lower)},
        {"fitted", {{"angle_of_repose", fit(h.slope)}, {"upper_slope", fit(h.upper)}, {"lower_slope", fit(h.lower)}}},
        {"heap_volume_m3", h.volume},
        {"runout_m", h.runout},
        {"x_m", h.x},
        {"surface_height_m", h.height},
        {"surface_top_m", h.top}};
}

}  // namespace mrjam
