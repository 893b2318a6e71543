// Fig. 4.15 for a scaling scene: the forces between two touching grains against their radius.
#include "asteroid/scaling_study.hpp"
#include "core/format.hpp"
#include "io/svg_plot.hpp"

namespace mrjam {

void write_scaling_plot(const ScalingSpec& spec, const std::string& path) {
    static const char* kColours[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                     "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
    const std::vector<double> radii = spec.radii();
    Plot plot;
    plot.title = "Forces between two touching grains (" + format_number(spec.density) + " kg/m3)";
    plot.x_label = "grain radius R (m)";
    plot.y_label = "force (N)";
    plot.log_x = plot.log_y = true;
    auto add = [&](const std::string& label, const PowerLaw& law, const char* colour, bool dashed) {
        PlotSeries s;
        s.label = label;
        s.x = radii;
        for (double r : radii) s.y.push_back(law.at(r));
        s.colour = colour;
        s.line = true;
        s.dashed = dashed;
        plot.series.push_back(s);
    };
    static const char* kGreys[] = {"#000000", "#555555", "#999999"};
    std::size_t w = 0;
    for (double g : spec.surface_gravities)
        add("weight, g = " + format_number(g) + " m/s2", surface_gravity_force(spec.density, g), kGreys[w++ % 3],
            false);
    add(std::string("self-gravity (") + formula_name(spec.self_gravity) + ")",
        self_gravity_force(spec.density, spec.self_gravity), "#b8860b", false);
    std::size_t c = 0;
    for (double S : spec.cleanliness)
        add("cohesion, S = " + format_number(S), cohesion_force(S), kGreys[c++ % 3], true);
    std::size_t k = 0;
    for (double b : spec.flux_densities)
        add(std::string(model_name(spec.dominance_model)) + ", " + format_number(b) + " T",
            induced_pair_force(spec.grain, b, spec.dominance_model, spec.exact_gap), kColours[k++ % 10], false);
    for (double m : spec.magnetisations)
        add("permanent, " + format_number(m) + " A/m", dipole_pair_force(m), kColours[k++ % 10], true);
    write_svg(path, plot);
}

}  // namespace mrjam
