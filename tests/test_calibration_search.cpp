// The shear calibration's derivative-free search (lib/shear/calibration.hpp, minimise_in_box,
// NLopt's bounded Nelder-Mead) on objectives whose minimum is known.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "shear/calibration.hpp"

using mrjam::CalibrationParameter;

namespace {

struct Trace {
    std::vector<std::vector<double>> points;
    std::vector<double> values;
    double best_value() const {
        double b = INFINITY;
        for (double v : values) b = std::min(b, v);
        return b;
    }
    std::vector<double> best_point() const {
        std::size_t k = 0;
        for (std::size_t i = 1; i < values.size(); ++i)
            if (values[i] < values[k]) k = i;
        return points[k];
    }
};

bool inside(const std::vector<double>& x, const std::vector<CalibrationParameter>& box) {
    for (std::size_t k = 0; k < x.size(); ++k)
        if (x[k] < box[k].lo || x[k] > box[k].hi) return false;
    return true;
}

}  // namespace

TEST_SUITE("unit") {
    TEST_CASE("calibration search: one parameter finds a parabola's minimum inside the box") {
        const std::vector<CalibrationParameter> box = {{"friction", "/material/friction", 0.05, 0.5}};
        Trace t;
        const bool stop = false;
        mrjam::minimise_in_box(
            box, 30,
            [&](const std::vector<double>& x) {
                t.points.push_back(x);
                t.values.push_back((x[0] - 0.17) * (x[0] - 0.17));
                return t.values.back();
            },
            stop);
        CHECK(t.values.size() <= 30);
        for (const auto& x : t.points) CHECK(inside(x, box));
        // 30 evaluations shrink the bracket to well under a hundredth of the 0.45 range.
        CHECK(std::abs(t.best_point()[0] - 0.17) < 2e-3);
    }

    TEST_CASE("calibration search: two parameters find a tilted valley's minimum, and one on the bound") {
        const std::vector<CalibrationParameter> box = {{"a", "/a", 0.0, 2.0}, {"b", "/b", -1.0, 1.0}};
        const bool stop = false;
        Trace valley;
        mrjam::minimise_in_box(
            box, 60,
            [&](const std::vector<double>& x) {
                const double u = x[0] - 1.3, v = x[1] + 0.4;
                valley.points.push_back(x);
                valley.values.push_back(u * u + v * v + 1.5 * u * v);  // positive definite, tilted axes
                return valley.values.back();
            },
            stop);
        for (const auto& x : valley.points) CHECK(inside(x, box));
        CHECK(std::abs(valley.best_point()[0] - 1.3) < 0.02);
        CHECK(std::abs(valley.best_point()[1] + 0.4) < 0.02);
        // The unconstrained minimum (3, 0) lies outside: the search ends on the bound a = 2.
        Trace bound;
        mrjam::minimise_in_box(
            box, 60,
            [&](const std::vector<double>& x) {
                bound.points.push_back(x);
                bound.values.push_back((x[0] - 3) * (x[0] - 3) + x[1] * x[1]);
                return bound.values.back();
            },
            stop);
        for (const auto& x : bound.points) CHECK(inside(x, box));
        CHECK(std::abs(bound.best_point()[0] - 2.0) < 0.02);
        CHECK(std::abs(bound.best_point()[1]) < 0.05);
    }

    TEST_CASE("calibration search: an interrupt stops it after the current evaluation") {
        const std::vector<CalibrationParameter> box = {{"a", "/a", 0.0, 1.0}, {"b", "/b", 0.0, 1.0}};
        bool stop = false;
        int calls = 0;
        mrjam::minimise_in_box(
            box, 50,
            [&](const std::vector<double>& x) {
                if (++calls == 5) stop = true;  // Ctrl-C during the fifth study
                return x[0] + x[1];
            },
            stop);
        CHECK(calls == 5);
    }
}
