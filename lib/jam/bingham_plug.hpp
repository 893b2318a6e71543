#pragma once
// The continuum tier of the jam predictor (issue #38 part 4): the pressure a magnetised MR fluid
// plug holds in the valve, treating the fluid as a Bingham plastic whose yield stress comes from
// the shear-cell mode (`mrjam shear`, docs/shear.md). No grains, no jamming arches: this is the
// "traditional MR valve" bound of the source (section 1, eq. 1.1; section 3.1, eq. 3.1), against
// which the granular tiers' holding pressure can be compared.
//
// Model. A plug of Bingham fluid in a passage of hydraulic diameter d(z) (the diameter for the
// circular orifice; 4 A / P for a slot, A the section's area and P its wetted perimeter) is held
// by the yield stress on its wall: on a slice dz the force balance A dP = tau_y P dz gives
// dP = 4 tau_y dz / d. It yields when the pressure difference across it exceeds
//
//     dP_hold = integral over the passage of 4 tau_y(B(z)) / d(z) dz,
//
// which for a uniform field in a straight pipe of length L is the dP = 4 tau_y L / d (the
// source's eq. 1.1 / 3.1, P_flow ~ tau_y L / d, is the same balance written as an estimate without
// the geometric factor 4). The passage is the modelled length, z from -upstream_length to
// downstream_length. B(z) is the flux density's magnitude on the axis; tau_y(B) is interpolated
// linearly in B from a table measured by the shear mode (YieldStressTable). The valve "jams" in
// this tier when dP_hold exceeds the supply pressure.
//
// Limits of the model: the field is taken on the axis for the whole section (the EPM's field is
// stronger near the poles, so the wall's yield stress can differ); the yield stress is the bulk
// value of a shear cell (no wall slip, no grain-scale arching, no dependence on the gap between
// grains and the throat, which is what the granular tiers add).
//
// Quadrature: composite Simpson on each piece of the passage where the geometry is smooth. The
// passage is split at the taper's ends (kinks of d(z)), at the exit (d steps back to the bore)
// and, for a slot, where the rectangle's corners cross the bore circle (a kink of the perimeter).
// A slot's taper faces also start tangent to the bore, so near the taper start A and P vary as
// (z - z_start)^(3/2): that piece is integrated in u, z = z_start + length u^2, where they are
// smooth. For an integrand smooth on every piece the error is sum over pieces of
// L_k h_k^4 |f''''| / 180: it falls as samples^-4. tau_y(B(z)) has kinks of its own where B(z) crosses a table field
// (the table is piecewise linear), and a trilinear field map has them at its node planes; those are not located, so
// with them the error falls as samples^-2 (a kink costs O(h^2) of the panel holding it). A few thousand samples over
// the 8 mm valve make either far below the table's own uncertainty.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/valve.hpp"

namespace mrjam {

struct YieldStressPoint {
    double flux_density = 0;  // T
    double yield_stress = 0;  // Pa
    std::string source;       // where the value came from (a report key), for the report; may be empty
};

// tau_y(B) from measured points, linear in B between them. Below the first field it is linear
// from (0, 0), unless the table starts at B = 0 (a fluid with a yield stress at zero field);
// beyond the last field the last value is held, and extrapolated() says so: a shear cell says
// nothing about stronger fields (the real fluid saturates, the source's linear dipoles do not).
class YieldStressTable {
public:
    // Throws SceneError for an empty table (at `path`) or a bad point k (at `path`/k/0 for its field,
    // `path`/k/1 for its yield stress, as if the table were written [[B, tau_y], ...]): fields
    // must be finite, non-negative and strictly ascending, yield stresses finite and non-negative.
    YieldStressTable(std::vector<YieldStressPoint> points, const std::string& path);

    double yield_stress(double flux_density) const;  // Pa, at |flux_density|
    bool extrapolated(double flux_density) const;    // |flux_density| beyond the last field
    double last_flux_density() const { return points_.back().flux_density; }
    const std::vector<YieldStressPoint>& points() const { return points_; }
    nlohmann::json to_json() const;  // [{flux_density_T, yield_stress_Pa, source}]

private:
    std::vector<YieldStressPoint> points_;
};

// The table a `mrjam shear` report holds (mode "shear"; docs/shear.md):
//  - results.yield_stress_Pa, the Bingham intercept of the main flow curve, at the main cell's
//    field inputs.field.flux_density (T), when the flow curve is complete
//    (results.flow_curve_complete) and the fit succeeded (otherwise it is null);
//  - with include_field_sweep, results.field_sweep[k].stress_Pa at flux_density_T: the stress of
//    one fresh cell per field at ONE shear rate (rate_1_s, 100 1/s by default), which for a
//    Bingham fluid is tau_y + eta_p rate, so an upper estimate of tau_y. Where a sweep field equals
//    the main field, the Bingham intercept is kept.
// Points are sorted by field; each carries its report key in `source`. Throws SceneError at
// `path` (the key or file that named the report) whose message names the report's key, for a
// report of another mode, a negative or non-finite value, or a report with no usable point.
YieldStressTable yield_stress_table_from_shear_report(const nlohmann::json& report, const std::string& path,
                                                      bool include_field_sweep = true);

struct BinghamPlugEstimate {
    double hold_pressure = 0;            // Pa, dP_hold
    double supply_pressure = 0;          // Pa
    double margin = 0;                   // dP_hold / supply: above 1 the plug holds
    bool jams = false;                   // dP_hold > supply
    double plug_length = 0;              // m where tau_y exceeds half its peak on the samples (descriptive only)
    double peak_yield_stress = 0;        // Pa, largest on the samples
    double peak_flux_density = 0;        // T, largest |B| on the samples
    bool table_extrapolated = false;     // some sample's |B| is beyond the table's last field
    double table_last_flux_density = 0;  // T
    double passage_length = 0;           // m, upstream_length + downstream_length
    int pieces = 0;                      // smooth pieces the passage was split into
    int samples = 0;                     // integrand evaluations
    nlohmann::json to_json() const;
};

// dP_hold for the valve's passage. `flux_density_on_axis(z)`: B on the axis at z, T (its sign is
// ignored). `samples`: Simpson intervals over the whole passage, at least 2, shared among the
// pieces in proportion to their lengths (each gets an even number, at least 2). Throws
// std::invalid_argument for samples < 2, a supply pressure that is not positive, a passage of no
// length or a non-finite B.
BinghamPlugEstimate bingham_plug_hold(const ValveGeometry& valve,
                                      const std::function<double(double z)>& flux_density_on_axis,
                                      const YieldStressTable& table, double supply_pressure, int samples);

// Hydraulic diameter of the passage at z (4 A / P): 2 passage_radius(z) for the circular
// orifice. At the exit z = throat_end_z() it is the throat's (the left limit), as passage_radius.
double passage_hydraulic_diameter(const ValveGeometry& valve, double z);

}  // namespace mrjam
