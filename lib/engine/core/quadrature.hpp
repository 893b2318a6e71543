#pragma once
// Composite Simpson's rule on [lo, hi] with n (even) intervals, its two end samples taken a hair
// inside the interval (1e-12 of its length): the integrands here (passage sections, stream radii)
// jump at the valve's breakpoints, and an end sample on a break belongs to the piece beyond it.
namespace mrjam {

template <class F>
double simpson_inside(F f, double lo, double hi, int n) {
    const double h = (hi - lo) / n, eps = 1e-12 * (hi - lo);
    double sum = f(lo + eps) + f(hi - eps);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(lo + i * h);
    return sum * h / 3.0;
}

}  // namespace mrjam
