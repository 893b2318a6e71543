#pragma once
// Grain size distributions for insertion (diameters in metres).
//
// A distribution is a number-weighted mixture of components; each component is either a set
// of discrete size classes (single size, or a digitised table such as a laser-diffraction
// report) or a truncated lognormal. Keeping mixtures as components rather than discretising
// them means a mixture that contains a lognormal part is still sampled and averaged exactly.
//
// All randomness goes through mrjam::Rng so a seed gives the same grains everywhere.
#include <utility>
#include <variant>
#include <vector>

#include "core/random.hpp"

namespace mrjam {

class SizeDistribution {
public:
    enum class FrequencyBasis { number, volume };

    // One size class with its share of the grain count.
    struct SizeClass {
        double diameter;
        double number_fraction;
    };

    // Every grain has this diameter. Throws std::invalid_argument unless diameter > 0.
    static SizeDistribution single(double diameter);

    // Number-weighted lognormal: ln d ~ N(ln median_diameter, sigma_ln^2), truncated to
    // [min_diameter, max_diameter] (sampled by rejection). Throws std::invalid_argument for
    // non-positive sizes or sigma, min >= max, or a window holding under 0.1% of the
    // untruncated distribution (rejection would then be hopelessly slow).
    static SizeDistribution lognormal(double median_diameter, double sigma_ln, double min_diameter,
                                      double max_diameter);

    // Discrete size classes, e.g. a digitised laser-diffraction table: each listed diameter is a
    // class. Volume frequencies are converted to number frequencies n_i ∝ f_i / d_i^3.
    // Frequencies need not sum to 1; classes with zero frequency are dropped (so min/max
    // diameter describe grains that can actually be drawn). Throws std::invalid_argument for an
    // empty table, size mismatch, non-positive or non-finite diameter, negative or non-finite
    // frequency, or all-zero frequencies.
    static SizeDistribution table(std::vector<double> diameters, std::vector<double> frequencies, FrequencyBasis basis);

    // Parts weighted by their share of SOLID VOLUME (e.g. {{fine, 33}, {coarse, 67}}); shares
    // need not sum to 1. Any kind of part is supported exactly, lognormal ones included: a
    // part's number weight is share / mean_particle_volume(part). Discrete parts are merged
    // into one table (identical diameters combined). Throws std::invalid_argument for no
    // parts, a negative or non-finite share, or all-zero shares.
    static SizeDistribution mixture(const std::vector<std::pair<SizeDistribution, double>>& parts);

    // One diameter.
    double sample(Rng& rng) const;

    double min_diameter() const;
    double max_diameter() const;

    // Number-weighted mean of pi d^3 / 6. Exact: sums for discrete classes, the closed form of
    // the truncated lognormal moment E[d^3] for lognormal parts.
    double mean_particle_volume() const;
    // Number-weighted mean diameter (same exactness).
    double mean_diameter_number() const;

    // Draws diameters until their total volume reaches solid_volume; the draw that reaches it is
    // kept only if that brings the total closer to the target than leaving it out. Returned
    // largest first (placing large grains first packs better). Throws std::invalid_argument for
    // a negative or non-finite volume, or one needing more than 1e8 grains.
    std::vector<double> sample_for_volume(double solid_volume, Rng& rng) const;

    // The size classes with number fractions (summing to 1) when the distribution is purely
    // discrete; throws std::logic_error if it has a lognormal part.
    std::vector<SizeClass> discrete_classes() const;

    bool is_discrete() const;

private:
    struct Discrete {
        std::vector<double> diameters;
        std::vector<double> fractions;  // number fractions, sum 1
        std::vector<double> cdf;        // running sum of fractions, last entry exactly 1
    };
    struct Lognormal {
        double mu;     // ln of the median diameter
        double sigma;  // standard deviation of ln d
        double min_d;
        double max_d;
    };
    using Component = std::variant<Discrete, Lognormal>;

    static Discrete make_discrete(std::vector<double> diameters, std::vector<double> fractions);
    static double sample_component(const Component& c, Rng& rng);
    static double component_moment(const Component& c, int k);  // number-weighted E[d^k]
    static double component_min(const Component& c);
    static double component_max(const Component& c);
    double moment(int k) const;

    std::vector<Component> components_;
    std::vector<double> weights_;  // number fraction of each component, sum 1
    std::vector<double> weight_cdf_;
};

}  // namespace mrjam
