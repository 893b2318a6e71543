#include "jam/bingham_plug.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

std::string number_text(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
}

// Perimeter of the disc of radius R cut by the rectangle |x| <= X, |y| <= Y (the slot's section,
// geometry/slot_orifice.hpp): the circle's arcs inside the rectangle plus the rectangle's edges
// inside the disc. The wetted perimeter, where the plug's wall stress acts.
double disc_rectangle_perimeter(double R, double X, double Y) {
    X = std::min(X, R);
    Y = std::min(Y, R);
    // In the first quadrant the circle is inside the rectangle for acos(X/R) <= theta <= asin(Y/R)
    // (an empty range when the corner is inside the disc).
    const double arc = 4.0 * R * std::max(0.0, std::asin(Y / R) - std::acos(X / R));
    // The edges x = +-X (X < R) lie in the disc for |y| <= sqrt(R^2 - X^2) and in the rectangle for |y| <= Y.
    auto edges = [R](double a, double b) { return a < R ? 4.0 * std::min(b, std::sqrt(R * R - a * a)) : 0.0; };
    return arc + edges(X, Y) + edges(Y, X);
}

// z in the slot's taper where the rectangle's corners cross the bore circle: the perimeter has a
// kink there (an edge's length switches from the rectangle's to the chord's), so the quadrature
// splits at it. Same root as SlotOrifice::constriction_volume; NaN if there is none in the taper.
double slot_corner_crossing_z(const ValveGeometry& v) {
    const SlotOrifice s = v.slot();
    const double R = s.bore_radius, hw = s.half_width, hh = s.half_height;
    const double aw = R - hw, ah = R - hh;  // X = hw + aw t, Y = hh + ah t, t = 0 at the slot, 1 at the bore
    const double qa = aw * aw + ah * ah, qb = 2.0 * (hw * aw + hh * ah), qc = hw * hw + hh * hh - R * R;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (!(qa > 0) || disc < 0) return std::nan("");
    const double t = (-qb + std::sqrt(disc)) / (2.0 * qa);
    if (!(t > 0 && t < 1)) return std::nan("");
    return s.throat_start_z - t * (s.throat_start_z - s.taper_start_z);
}

// The ends of the pieces on which the passage's geometry is smooth, ascending, from
// -upstream_length to downstream_length.
std::vector<double> piece_ends(const ValveGeometry& v) {
    const double z0 = -v.upstream_length, z1 = v.downstream_length;
    std::vector<double> ends{z0, v.taper_start_z(), -0.5 * v.throat_length, v.throat_end_z(), z1};
    if (v.is_slot() && v.taper_length > 0) ends.push_back(slot_corner_crossing_z(v));
    std::erase_if(ends, [&](double z) { return !(z >= z0 && z <= z1); });  // NaN goes too
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    return ends;
}

struct Sample {
    double z, yield_stress;
};

// The length over which the piecewise-linear interpolant of the samples exceeds `level`.
double length_above(const std::vector<Sample>& s, double level) {
    double length = 0;
    for (std::size_t i = 1; i < s.size(); ++i) {
        const double dz = s[i].z - s[i - 1].z, t0 = s[i - 1].yield_stress - level, t1 = s[i].yield_stress - level;
        if (t0 > 0 && t1 > 0)
            length += dz;
        else if (t0 > 0 || t1 > 0)
            length += dz * std::max(t0, t1) / std::abs(t1 - t0);
    }
    return length;
}

// The value at a JSON pointer, or null when the report has none there.
nlohmann::json at_pointer(const nlohmann::json& j, const std::string& pointer) {
    const nlohmann::json::json_pointer p(pointer);
    return j.contains(p) ? j.at(p) : nlohmann::json();
}

// A point of a shear report: the number at `pointer`, finite and non-negative, or SceneError at
// `path` naming the report's key.
double report_value(const nlohmann::json& value, const std::string& pointer, const std::string& path,
                    const std::string& what) {
    if (!value.is_number())
        throw SceneError(path, "the shear report's " + pointer + " must be a number (" + what + "), not " +
                                   value.dump() + "; is it a report written by `mrjam shear`?");
    const double x = value.get<double>();
    if (!std::isfinite(x) || x < 0)
        throw SceneError(path, "the shear report's " + pointer + " is " + number_text(x) + " (" + what +
                                   "); a yield-stress table needs finite non-negative values: rerun the "
                                   "shear study (more strain, another seed) or leave this point out");
    return x;
}

// Composite Simpson of f over [a, b] with n (even) intervals; f(z, first) is told which sample
// is the piece's first. Graded: in u with z = a + (b - a) u^2, which turns a (z - a)^(k/2)
// behaviour at a into a power of u, smooth, so the rule keeps its h^4 error there.
template <class F>
double simpson(double a, double b, long n, bool graded, F&& f) {
    double sum = 0;
    for (long i = 0; i <= n; ++i) {
        const double u = i == n ? 1.0 : static_cast<double>(i) / static_cast<double>(n);
        const double z = i == n ? b : a + (b - a) * (graded ? u * u : u);
        const double dz_du = graded ? 2.0 * (b - a) * u : b - a;
        const double weight = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
        sum += weight * dz_du * f(z, i == 0);
    }
    return sum / (3.0 * static_cast<double>(n));
}

}  // namespace

YieldStressTable::YieldStressTable(std::vector<YieldStressPoint> points, const std::string& path)
    : points_(std::move(points)) {
    if (points_.empty())
        throw SceneError(path, "a yield-stress table needs at least one [flux density, yield stress] point");
    for (std::size_t k = 0; k < points_.size(); ++k) {
        const std::string at = path + "/" + std::to_string(k);
        const double b = points_[k].flux_density, tau = points_[k].yield_stress;
        if (!std::isfinite(b) || b < 0)
            throw SceneError(at + "/0", "the flux density must be finite and non-negative, not " + number_text(b));
        if (k > 0 && !(b > points_[k - 1].flux_density))
            throw SceneError(at + "/0", "the flux densities must be strictly ascending (" + number_text(b) +
                                            " T follows " + number_text(points_[k - 1].flux_density) + " T)");
        if (!std::isfinite(tau) || tau < 0)
            throw SceneError(at + "/1", "the yield stress must be finite and non-negative, not " + number_text(tau));
    }
}

double YieldStressTable::yield_stress(double flux_density) const {
    const double b = std::abs(flux_density);
    const auto& p = points_;
    if (b >= p.back().flux_density) return p.back().yield_stress;  // held beyond the table
    const auto hi =
        std::lower_bound(p.begin(), p.end(), b, [](const YieldStressPoint& q, double x) { return q.flux_density < x; });
    // Below the first field: from (0, 0), or the first value itself when the table starts at 0.
    const double b0 = hi == p.begin() ? 0.0 : std::prev(hi)->flux_density;
    const double t0 = hi == p.begin() ? 0.0 : std::prev(hi)->yield_stress;
    if (hi->flux_density == b0) return hi->yield_stress;  // a table starting at B = 0, read at 0
    return t0 + (hi->yield_stress - t0) * (b - b0) / (hi->flux_density - b0);
}

bool YieldStressTable::extrapolated(double flux_density) const {
    return std::abs(flux_density) > points_.back().flux_density;
}

nlohmann::json YieldStressTable::to_json() const {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& p : points_)
        out.push_back({{"flux_density_T", p.flux_density}, {"yield_stress_Pa", p.yield_stress}, {"source", p.source}});
    return out;
}

YieldStressTable yield_stress_table_from_shear_report(const nlohmann::json& report, const std::string& path,
                                                      bool include_field_sweep) {
    if (!report.is_object() || at_pointer(report, "/mode") != "shear")
        throw SceneError(path,
                         "is not a `mrjam shear` report (its \"mode\" must be \"shear\"; a calibration "
                         "report holds no yield-stress table)");
    const nlohmann::json results = at_pointer(report, "/results");
    if (!results.is_object()) throw SceneError(path, "the shear report has no \"results\" object");
    std::vector<YieldStressPoint> points;
    // The Bingham intercept is a yield stress proper, but only of a complete ladder (a partial
    // report's fit uses the rates finished so far) and only when the fit succeeded (else null).
    const bool complete = at_pointer(results, "/flow_curve_complete") == true;
    if (complete && !at_pointer(results, "/yield_stress_Pa").is_null()) {
        const std::string key = "/inputs/field/flux_density";  // resolved, so in T
        const double b = report_value(at_pointer(report, key), key, path, "the main cell's field, T");
        points.push_back({b,
                          report_value(at_pointer(results, "/yield_stress_Pa"), "/results/yield_stress_Pa", path,
                                       "the Bingham yield stress, Pa"),
                          "results.yield_stress_Pa"});
    }
    const nlohmann::json sweep = at_pointer(results, "/field_sweep");
    for (std::size_t k = 0; include_field_sweep && sweep.is_array() && k < sweep.size(); ++k) {
        const std::string at = "/results/field_sweep/" + std::to_string(k);
        const double b = report_value(at_pointer(report, at + "/flux_density_T"), at + "/flux_density_T", path, "T");
        const double tau = report_value(at_pointer(report, at + "/stress_Pa"), at + "/stress_Pa", path, "Pa");
        // The main cell's Bingham intercept wins over a one-rate stress at the same field.
        if (std::none_of(points.begin(), points.end(), [b](const YieldStressPoint& p) { return p.flux_density == b; }))
            points.push_back({b, tau, "results.field_sweep[" + std::to_string(k) + "].stress_Pa"});
    }
    if (points.empty())
        throw SceneError(path,
                         "the shear report holds no usable yield stress: results.yield_stress_Pa is null or "
                         "the flow curve is incomplete (results.flow_curve_complete), and there is no "
                         "results.field_sweep; finish the study (mrjam shear --resume) or add a field_sweep");
    std::sort(points.begin(), points.end(),
              [](const YieldStressPoint& a, const YieldStressPoint& b) { return a.flux_density < b.flux_density; });
    // Two sweep cells at one field would make the table refuse with its own index; say it here.
    for (std::size_t k = 1; k < points.size(); ++k)
        if (points[k].flux_density == points[k - 1].flux_density)
            throw SceneError(path, "the shear report has two yield stresses at " + number_text(points[k].flux_density) +
                                       " T (" + points[k - 1].source + ", " + points[k].source + ")");
    return YieldStressTable(std::move(points), path);
}

double passage_hydraulic_diameter(const ValveGeometry& valve, double z) {
    if (!valve.is_slot()) return 2.0 * valve.passage_radius(z);
    const SlotOrifice s = valve.slot();
    const double R = s.bore_radius, X = s.half_x(z), Y = s.half_y(z);
    return 4.0 * SlotOrifice::disc_rectangle_area(R, std::min(X, R), std::min(Y, R)) /
           disc_rectangle_perimeter(R, X, Y);
}

BinghamPlugEstimate bingham_plug_hold(const ValveGeometry& valve,
                                      const std::function<double(double z)>& flux_density_on_axis,
                                      const YieldStressTable& table, double supply_pressure, int samples) {
    if (samples < 2) throw std::invalid_argument("bingham_plug_hold: samples must be at least 2");
    if (!(supply_pressure > 0)) throw std::invalid_argument("bingham_plug_hold: the supply pressure must be positive");
    const std::vector<double> ends = piece_ends(valve);
    const double total = valve.upstream_length + valve.downstream_length;
    if (ends.size() < 2 || !(total > 0)) throw std::invalid_argument("bingham_plug_hold: the passage has no length");

    BinghamPlugEstimate out;
    out.supply_pressure = supply_pressure;
    out.table_last_flux_density = table.last_flux_density();
    out.passage_length = total;
    std::vector<Sample> trace;  // every sample in z order, for the plug length
    auto yield_stress_at = [&](double z) {
        const double b = std::abs(flux_density_on_axis(z));
        if (!std::isfinite(b))
            throw std::invalid_argument("bingham_plug_hold: B is not finite at z = " + number_text(z));
        out.peak_flux_density = std::max(out.peak_flux_density, b);
        out.table_extrapolated = out.table_extrapolated || table.extrapolated(b);
        const double tau = table.yield_stress(b);
        trace.push_back({z, tau});
        ++out.samples;
        return tau;
    };
    for (std::size_t k = 1; k < ends.size(); ++k) {
        const double a = ends[k - 1], b = ends[k];
        const long n = 2 * std::max(1L, std::lround(0.5 * samples * (b - a) / total));
        // At the exit the passage steps back to the bore; passage_radius gives the throat's value
        // at the exit itself (the left limit), so the piece downstream of it looks one ulp inside.
        const bool after_step = a == valve.throat_end_z();
        // A slot's taper faces start tangent to the bore circle: there A and P go as (z - a)^(3/2).
        const bool graded = valve.is_slot() && valve.taper_length > 0 && a == valve.taper_start_z();
        out.hold_pressure += simpson(a, b, n, graded, [&](double z, bool first) {
            return 4.0 * yield_stress_at(z) /
                   passage_hydraulic_diameter(valve, first && after_step ? std::nextafter(a, b) : z);
        });
        ++out.pieces;
    }
    for (const Sample& s : trace) out.peak_yield_stress = std::max(out.peak_yield_stress, s.yield_stress);
    out.plug_length = out.peak_yield_stress > 0 ? length_above(trace, 0.5 * out.peak_yield_stress) : 0.0;
    out.margin = out.hold_pressure / supply_pressure;
    out.jams = out.hold_pressure > supply_pressure;
    return out;
}

nlohmann::json BinghamPlugEstimate::to_json() const {
    return {{"model", "Bingham plug: dP_hold = integral of 4 tau_y(B(z)) / d(z) dz over the passage"},
            {"quadrature", "composite Simpson, split at the geometry's kinks"},
            {"hold_pressure_Pa", hold_pressure},
            {"supply_pressure_Pa", supply_pressure},
            {"margin", margin},
            {"jams", jams},
            {"plug_length_m", plug_length},
            {"peak_yield_stress_Pa", peak_yield_stress},
            {"peak_flux_density_T", peak_flux_density},
            {"table_extrapolated", table_extrapolated},
            {"table_last_flux_density_T", table_last_flux_density},
            {"passage_length_m", passage_length},
            {"pieces", pieces},
            {"samples", samples}};
}

}  // namespace mrjam
