#include "io/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "io/svg_figure.hpp"
#include "io/svg_raster.hpp"

namespace mrjam {

std::string svg_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else
            out += c;
    }
    return out;
}

double nice_step(double span, int count) {
    const double raw = span / count;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

std::string svg_number(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

namespace {}  // namespace

namespace {

// One axis: its range in plotted units (log10 of the value on a log axis) and its ticks.
struct Axis {
    bool log = false;
    double lo = 0, hi = 1, step = 1;
    double plotted(double v) const { return log ? std::log10(v) : v; }
    bool shows(double v) const { return !log || v > 0; }
    std::string label(double t) const { return log ? "1e" + svg_number(t) : svg_number(t); }
};

// Range of the plotted values (lo > hi when there are none), widened to whole ticks.
Axis make_axis(bool log, double lo, double hi, bool from_zero, bool pad_top) {
    Axis a;
    a.log = log;
    if (lo > hi) {
        lo = 0;
        hi = 1;
    }
    if (log) {
        a.lo = std::floor(lo);
        a.hi = std::ceil(hi);
        if (a.hi <= a.lo) a.hi = a.lo + 1;
        a.step = std::max(1.0, std::ceil((a.hi - a.lo) / 12));  // at most about a dozen decades labelled
        return a;
    }
    if (from_zero) lo = std::min(lo, 0.0);
    if (hi <= lo) hi = lo + 1;
    if (pad_top) hi += 0.05 * (hi - lo);
    a.step = nice_step(hi - lo, 5);
    a.hi = std::ceil(hi / a.step) * a.step;
    a.lo = std::floor(lo / a.step) * a.step;
    return a;
}

// The bar below and above point k of a series (0 where it has none).
std::pair<double, double> bar(const PlotSeries& s, std::size_t k) {
    if (!s.error_low.empty() || !s.error_high.empty())
        return {k < s.error_low.size() ? s.error_low[k] : 0.0, k < s.error_high.size() ? s.error_high[k] : 0.0};
    const double e = k < s.error.size() ? s.error[k] : 0.0;
    return {e, e};
}

}  // namespace

SvgPanel plot_panel(const Plot& plot) {
    // The legend sits right of the frame; the canvas widens for long labels (about 7 units a
    // character at 12 px sans-serif) instead of cutting them off.
    std::size_t longest = 0;
    for (const auto& s : plot.series) longest = std::max(longest, s.label.size());
    const double H = 480, left = 80, top = 40, bottom = 60, pw = 440;
    const double right = std::max(200.0, 51.0 + 7.0 * static_cast<double>(longest)), W = left + pw + right;
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    const Axis xprobe{plot.log_x}, yprobe{plot.log_y};
    for (const auto& s : plot.series)
        for (std::size_t k = 0; k < s.x.size(); ++k) {
            const auto [below, above] = bar(s, k);
            if (!xprobe.shows(s.x[k]) || !yprobe.shows(s.y[k])) continue;
            xmin = std::min(xmin, xprobe.plotted(s.x[k]));
            xmax = std::max(xmax, xprobe.plotted(s.x[k]));
            ymin = std::min(ymin, yprobe.plotted(plot.log_y ? s.y[k] : s.y[k] - below));
            ymax = std::max(ymax, yprobe.plotted(s.y[k] + above));
        }
    const Axis xa = make_axis(plot.log_x, xmin, xmax, true, false);
    const Axis ya = make_axis(plot.log_y, ymin, ymax, plot.y_from_zero, true);
    const double ph = H - top - bottom;
    auto X = [&](double x) { return left + (xa.plotted(x) - xa.lo) / (xa.hi - xa.lo) * pw; };
    auto Y = [&](double y) { return top + ph - (ya.plotted(y) - ya.lo) / (ya.hi - ya.lo) * ph; };
    auto XT = [&](double t) { return left + (t - xa.lo) / (xa.hi - xa.lo) * pw; };
    auto YT = [&](double t) { return top + ph - (t - ya.lo) / (ya.hi - ya.lo) * ph; };

    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" << svg_escape(plot.title)
      << "</text>\n";
    for (double x = xa.lo; x <= xa.hi + 1e-9 * xa.step; x += xa.step) {
        o << "<line x1=\"" << XT(x) << "\" y1=\"" << top << "\" x2=\"" << XT(x) << "\" y2=\"" << top + ph
          << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << XT(x) << "\" y=\"" << top + ph + 18 << "\" text-anchor=\"middle\">" << xa.label(x)
          << "</text>\n";
    }
    for (double y = ya.lo; y <= ya.hi + 1e-9 * ya.step; y += ya.step) {
        o << "<line x1=\"" << left << "\" y1=\"" << YT(y) << "\" x2=\"" << left + pw << "\" y2=\"" << YT(y)
          << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << left - 6 << "\" y=\"" << YT(y) + 4 << "\" text-anchor=\"end\">" << ya.label(y)
          << "</text>\n";
    }
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 15 << "\" text-anchor=\"middle\">"
      << svg_escape(plot.x_label) << "</text>\n";
    o << "<text transform=\"translate(20," << top + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << svg_escape(plot.y_label) << "</text>\n";
    double ly = top + 10;
    for (const auto& s : plot.series) {
        const char* dash = s.dashed ? "\" stroke-dasharray=\"6,4" : "";
        if (s.line && s.x.size() > 1) {
            o << "<polyline fill=\"none\" stroke=\"" << s.colour << dash << "\" stroke-width=\"1.5\" points=\"";
            for (std::size_t k = 0; k < s.x.size(); ++k)
                if (xa.shows(s.x[k]) && ya.shows(s.y[k])) o << X(s.x[k]) << "," << Y(s.y[k]) << " ";
            o << "\"/>\n";
        } else {
            for (std::size_t k = 0; k < s.x.size(); ++k) {
                if (!xa.shows(s.x[k]) || !ya.shows(s.y[k])) continue;
                const auto [below, above] = bar(s, k);
                if (below + above > 0 && ya.shows(s.y[k] - below))
                    o << "<line x1=\"" << X(s.x[k]) << "\" y1=\"" << Y(s.y[k] - below) << "\" x2=\"" << X(s.x[k])
                      << "\" y2=\"" << Y(s.y[k] + above) << "\" stroke=\"" << s.colour << "\"/>\n";
                o << "<circle cx=\"" << X(s.x[k]) << "\" cy=\"" << Y(s.y[k]) << "\" r=\"4\" fill=\""
                  << (s.hollow ? "white" : s.colour) << "\" stroke=\"" << s.colour << "\"/>\n";
            }
        }
        const double lx = left + pw + 15;
        if (s.label.empty()) continue;  // a series the legend names with another (the lower error line)
        if (s.line)
            o << "<line x1=\"" << lx << "\" y1=\"" << ly << "\" x2=\"" << lx + 20 << "\" y2=\"" << ly << "\" stroke=\""
              << s.colour << dash << "\" stroke-width=\"1.5\"/>\n";
        else
            o << "<circle cx=\"" << lx + 10 << "\" cy=\"" << ly << "\" r=\"4\" fill=\""
              << (s.hollow ? "white" : s.colour) << "\" stroke=\"" << s.colour << "\"/>\n";
        o << "<text x=\"" << lx + 26 << "\" y=\"" << ly + 4 << "\">" << svg_escape(s.label) << "</text>\n";
        ly += 20;
    }
    o << "</svg>\n";
    return {o.str(), W, H};
}

void write_svg(const std::string& path, const Plot& plot) { write_figure(path, plot_panel(plot).svg); }

}  // namespace mrjam
