#pragma once
// The side profile of a heap that ran out from behind a gate (section 4.4 of the source): the
// surface height in bins along the run-out; the angle of repose as the chord of the face between
// where the surface falls through 90 % and 10 % of the plateau's height, and the upper (90-50 %)
// and lower (50-10 %) chords apart (the source saw two slopes for its 5 mm grains: steep on top,
// unenhanced at the bottom); and straight least-squares fits to the bins between 10 % and 90 % of
// the peak. The chords are what the report calls the angle: a magnetised heap can end in a cliff
// narrower than a bin, which the fits (bins inside the band only) do not see.
#include <nlohmann/json.hpp>
#include <vector>

#include "particles.hpp"

namespace mrjam {

struct SlopeFit {
    int points = 0;        // bins fitted (fewer than 3: no fit)
    double slope = 0;      // dz/dx
    double intercept = 0;  // m
    double angle_deg = 0;  // atan(|slope|)
};

// A chord of the face: the surface's downhill crossings of two heights, interpolated between bin
// centres (bins beyond the front read 0), and the angle of the line through them.
struct FaceChord {
    bool found = false;  // both crossings exist (a front against the end wall may have no 10 %)
    double x_high = 0, x_low = 0, z_high = 0, z_low = 0;  // m
    double angle_deg = 0;
};

struct HeapProfile {
    double bin = 0;                          // m
    std::vector<double> x, height;           // bin centres from the back wall; surface height there (m)
    std::vector<double> top;                 // the highest grain's top per bin, before the running median
    double peak = 0;                         // m
    double plateau = 0;                      // m, the median surface height behind the gate
    FaceChord face, face_upper, face_lower;  // 90-10 %, 90-50 %, 50-10 % of the plateau
    SlopeFit slope, upper, lower;            // fits to 10-90 %, 50-90 %, 10-50 % of the peak, downhill of it
    double volume = 0;                       // m3 under the surface (bulk, pores included)
    double runout = 0;                       // m, the farthest grain's front beyond the gate
};

// Surface height per bin: the top of the highest grain whose centre falls in it, then a running
// median over three bins, so that a single magnetised chain standing on the heap (or lying ahead
// of it) is not taken for the surface: with the raw tops one upright chain on a plateau set the
// peak and moved the fitted slope onto the plateau (5 mT: 13 degrees for a face of about 30).
HeapProfile measure_heap(const Particles& p, double length, double width, double gate, double bin);

// A least-squares line through the points; fewer than 3 points leave points < 3 and no fit.
SlopeFit fit_slope(const std::vector<double>& x, const std::vector<double>& z);

nlohmann::json to_json(const HeapProfile& h);

}  // namespace mrjam
