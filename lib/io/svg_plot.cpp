#include "io/svg_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mrjam {
namespace {

std::string escape(const std::string& s) {
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

// "Nice" tick spacing: 1, 2 or 5 times a power of ten, about five ticks over the range.
double tick_step(double span) {
    const double raw = span / 5;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

std::string num(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

}  // namespace

void write_svg(const std::string& path, const Plot& plot) {
    const double W = 720, H = 480, left = 80, right = 200, top = 40, bottom = 60;
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (const auto& s : plot.series)
        for (std::size_t k = 0; k < s.x.size(); ++k) {
            const double e = k < s.error.size() ? s.error[k] : 0;
            xmin = std::min(xmin, s.x[k]);
            xmax = std::max(xmax, s.x[k]);
            ymin = std::min(ymin, s.y[k] - e);
            ymax = std::max(ymax, s.y[k] + e);
        }
    if (xmin > xmax) {
        xmin = 0;
        xmax = 1;
        ymin = 0;
        ymax = 1;
    }
    xmin = std::min(xmin, 0.0);
    if (plot.y_from_zero) ymin = std::min(ymin, 0.0);
    if (xmax <= xmin) xmax = xmin + 1;
    if (ymax <= ymin) ymax = ymin + 1;
    ymax += 0.05 * (ymax - ymin);
    const double xs = tick_step(xmax - xmin), ys = tick_step(ymax - ymin);
    xmax = std::ceil(xmax / xs) * xs;
    ymax = std::ceil(ymax / ys) * ys;
    xmin = std::floor(xmin / xs) * xs;
    ymin = std::floor(ymin / ys) * ys;
    const double pw = W - left - right, ph = H - top - bottom;
    auto X = [&](double x) { return left + (x - xmin) / (xmax - xmin) * pw; };
    auto Y = [&](double y) { return top + ph - (y - ymin) / (ymax - ymin) * ph; };

    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << W / 2 << "\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">" << escape(plot.title)
      << "</text>\n";
    for (double x = xmin; x <= xmax + 1e-9 * xs; x += xs) {
        o << "<line x1=\"" << X(x) << "\" y1=\"" << top << "\" x2=\"" << X(x) << "\" y2=\"" << top + ph
          << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << X(x) << "\" y=\"" << top + ph + 18 << "\" text-anchor=\"middle\">" << num(x)
          << "</text>\n";
    }
    for (double y = ymin; y <= ymax + 1e-9 * ys; y += ys) {
        o << "<line x1=\"" << left << "\" y1=\"" << Y(y) << "\" x2=\"" << left + pw << "\" y2=\"" << Y(y)
          << "\" stroke=\"#ddd\"/>\n";
        o << "<text x=\"" << left - 6 << "\" y=\"" << Y(y) + 4 << "\" text-anchor=\"end\">" << num(y) << "</text>\n";
    }
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 15 << "\" text-anchor=\"middle\">" << escape(plot.x_label)
      << "</text>\n";
    o << "<text transform=\"translate(20," << top + ph / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
      << escape(plot.y_label) << "</text>\n";
    double ly = top + 10;
    for (const auto& s : plot.series) {
        if (s.line && s.x.size() > 1) {
            o << "<polyline fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"1.5\" points=\"";
            for (std::size_t k = 0; k < s.x.size(); ++k) o << X(s.x[k]) << "," << Y(s.y[k]) << " ";
            o << "\"/>\n";
        } else {
            for (std::size_t k = 0; k < s.x.size(); ++k) {
                if (k < s.error.size() && s.error[k] > 0)
                    o << "<line x1=\"" << X(s.x[k]) << "\" y1=\"" << Y(s.y[k] - s.error[k]) << "\" x2=\"" << X(s.x[k])
                      << "\" y2=\"" << Y(s.y[k] + s.error[k]) << "\" stroke=\"" << s.colour << "\"/>\n";
                o << "<circle cx=\"" << X(s.x[k]) << "\" cy=\"" << Y(s.y[k]) << "\" r=\"4\" fill=\""
                  << (s.hollow ? "white" : s.colour) << "\" stroke=\"" << s.colour << "\"/>\n";
            }
        }
        const double lx = left + pw + 15;
        if (s.line)
            o << "<line x1=\"" << lx << "\" y1=\"" << ly << "\" x2=\"" << lx + 20 << "\" y2=\"" << ly << "\" stroke=\""
              << s.colour << "\" stroke-width=\"1.5\"/>\n";
        else
            o << "<circle cx=\"" << lx + 10 << "\" cy=\"" << ly << "\" r=\"4\" fill=\""
              << (s.hollow ? "white" : s.colour) << "\" stroke=\"" << s.colour << "\"/>\n";
        o << "<text x=\"" << lx + 26 << "\" y=\"" << ly + 4 << "\">" << escape(s.label) << "</text>\n";
        ly += 20;
    }
    o << "</svg>\n";
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    std::ofstream f(path);
    if (!f) throw std::runtime_error("cannot write " + path);
    f << o.str();
}

}  // namespace mrjam
