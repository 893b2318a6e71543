#include "geometry/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/physical_memory.hpp"

namespace mrjam {

namespace {

// A grain costs the engine about 2 kB with its contact and magnetic lists (measured: 1.6 kB at the
// jam quick tier's 2-diameter dipole cutoff, 2.0 kB at the standard tier's 3, on 72,226 grains;
// docs/notes/benchmark_log.md, "Memory per grain"), so more grains than memory / 2.5 kB would
// swap or be killed mid-run.
constexpr double kMostGrains = 1e8;       // whatever the memory: past it a run would take weeks
constexpr double kBytesPerGrain = 2.5e3;  // the measured 2 kB, with room for the larger cutoffs
double most_grains_in_memory() {
    const double memory = physical_memory_bytes();
    return memory > 0 ? std::min(kMostGrains, memory / kBytesPerGrain) : kMostGrains;
}

constexpr double kPi = 3.14159265358979323846;

double sphere_volume(double d) { return kPi / 6.0 * d * d * d; }

// P(a < Z < b) for a standard normal Z, using whichever tail keeps erfc accurate: subtracting
// two numbers close to 1 would lose the digits that matter for narrow or far-tail windows.
double normal_interval(double a, double b) {
    const double s = 1.0 / std::sqrt(2.0);
    if (a > 0.0) return 0.5 * (std::erfc(a * s) - std::erfc(b * s));
    return 0.5 * (std::erfc(-b * s) - std::erfc(-a * s));
}

// Index into a running-sum table for a uniform deviate in [0, 1).
std::size_t pick(const std::vector<double>& cdf, double u) {
    const auto it = std::upper_bound(cdf.begin(), cdf.end(), u);
    return std::min<std::size_t>(static_cast<std::size_t>(it - cdf.begin()), cdf.size() - 1);
}

std::vector<double> running_sum(const std::vector<double>& fractions) {
    std::vector<double> cdf(fractions.size());
    double acc = 0.0;
    for (std::size_t i = 0; i < fractions.size(); ++i) cdf[i] = acc += fractions[i];
    cdf.back() = 1.0;  // rounding must never leave u in [acc, 1) unmatched
    return cdf;
}

void require_positive(double v, const char* what) {
    if (!(v > 0.0) || !std::isfinite(v))
        throw std::invalid_argument(std::string("SizeDistribution: ") + what + " must be positive and finite (got " +
                                    std::to_string(v) + ")");
}

}  // namespace

SizeDistribution::Discrete SizeDistribution::make_discrete(std::vector<double> diameters,
                                                           std::vector<double> fractions) {
    double total = 0.0;
    for (double f : fractions) total += f;
    Discrete d;
    for (std::size_t i = 0; i < diameters.size(); ++i) {
        if (fractions[i] == 0.0) continue;
        d.diameters.push_back(diameters[i]);
        d.fractions.push_back(fractions[i] / total);
    }
    // Every class zero (a mixture whose parts weigh nothing, found by fuzzing): no distribution.
    if (d.fractions.empty() || !(total > 0.0) || !std::isfinite(total))
        throw std::invalid_argument("SizeDistribution: no size class has a positive, finite fraction");
    d.cdf = running_sum(d.fractions);
    return d;
}

SizeDistribution SizeDistribution::single(double diameter) {
    require_positive(diameter, "diameter");
    SizeDistribution s;
    s.components_.emplace_back(make_discrete({diameter}, {1.0}));
    s.weights_ = {1.0};
    s.weight_cdf_ = {1.0};
    return s;
}

SizeDistribution SizeDistribution::lognormal(double median_diameter, double sigma_ln, double min_diameter,
                                             double max_diameter) {
    require_positive(median_diameter, "lognormal median diameter");
    require_positive(sigma_ln, "lognormal sigma_ln (use single() for one size)");
    require_positive(min_diameter, "lognormal min diameter");
    require_positive(max_diameter, "lognormal max diameter");
    if (min_diameter >= max_diameter) throw std::invalid_argument("min diameter must be below max diameter");
    const Lognormal ln{std::log(median_diameter), sigma_ln, min_diameter, max_diameter};
    const double a = (std::log(min_diameter) - ln.mu) / sigma_ln;
    const double b = (std::log(max_diameter) - ln.mu) / sigma_ln;
    if (normal_interval(a, b) < 1e-3)
        throw std::invalid_argument(
            "[min, max] holds under 0.1% of the distribution; "
            "move the window towards the median or widen sigma");
    SizeDistribution s;
    s.components_.emplace_back(ln);
    s.weights_ = {1.0};
    s.weight_cdf_ = {1.0};
    return s;
}

SizeDistribution SizeDistribution::table(std::vector<double> diameters, std::vector<double> frequencies,
                                         FrequencyBasis basis) {
    if (diameters.empty()) throw std::invalid_argument("the table is empty");
    if (diameters.size() != frequencies.size())
        throw std::invalid_argument(std::to_string(diameters.size()) + " diameters but " +
                                    std::to_string(frequencies.size()) + " frequencies");
    double total = 0.0;
    for (std::size_t i = 0; i < diameters.size(); ++i) {
        if (!(diameters[i] > 0.0) || !std::isfinite(diameters[i]))
            throw std::invalid_argument("diameter #" + std::to_string(i) + " is not positive (" +
                                        std::to_string(diameters[i]) + ")");
        if (!(frequencies[i] >= 0.0) || !std::isfinite(frequencies[i]))
            throw std::invalid_argument("frequency #" + std::to_string(i) + " is negative or not finite (" +
                                        std::to_string(frequencies[i]) + ")");
        total += frequencies[i];
    }
    if (total == 0.0) throw std::invalid_argument("all frequencies are zero");

    if (basis == FrequencyBasis::volume) {
        // A volume share f_i is carried by grains of volume ∝ d_i^3, so their count ∝ f_i/d_i^3.
        // Dividing by the largest diameter first keeps the numbers O(1) for micron sizes.
        const double dmax = *std::max_element(diameters.begin(), diameters.end());
        for (std::size_t i = 0; i < diameters.size(); ++i) {
            const double rel = diameters[i] / dmax;
            frequencies[i] /= rel * rel * rel;
        }
    }
    SizeDistribution s;
    s.components_.emplace_back(make_discrete(std::move(diameters), std::move(frequencies)));
    s.weights_ = {1.0};
    s.weight_cdf_ = {1.0};
    return s;
}

SizeDistribution SizeDistribution::mixture(const std::vector<std::pair<SizeDistribution, double>>& parts) {
    if (parts.empty()) throw std::invalid_argument("no parts");
    double share_total = 0.0;
    for (const auto& [part, share] : parts) {
        if (!(share >= 0.0) || !std::isfinite(share))
            throw std::invalid_argument("a volume share is negative or not finite");
        share_total += share;
    }
    if (share_total == 0.0) throw std::invalid_argument("all volume shares are zero");

    // A part holding volume share w with mean grain volume V contributes w / V grains per unit
    // of solid volume; that is its number weight. Within a part, its own weights carry over.
    std::map<double, double> discrete;  // merged classes: diameter -> number weight
    std::vector<Component> others;
    std::vector<double> other_weights;
    double weight_total = 0.0;
    for (const auto& [part, share] : parts) {
        if (share == 0.0) continue;
        const double part_weight = share / part.mean_particle_volume();
        for (std::size_t c = 0; c < part.components_.size(); ++c) {
            const double w = part_weight * part.weights_[c];
            weight_total += w;
            if (const auto* d = std::get_if<Discrete>(&part.components_[c])) {
                for (std::size_t i = 0; i < d->diameters.size(); ++i) discrete[d->diameters[i]] += w * d->fractions[i];
            } else {
                others.push_back(part.components_[c]);
                other_weights.push_back(w);
            }
        }
    }

    SizeDistribution s;
    if (!discrete.empty()) {
        std::vector<double> ds, fs;
        double w = 0.0;
        for (const auto& [d, f] : discrete) {
            ds.push_back(d);
            fs.push_back(f);
            w += f;
        }
        s.components_.emplace_back(make_discrete(std::move(ds), std::move(fs)));
        s.weights_.push_back(w / weight_total);
    }
    for (std::size_t i = 0; i < others.size(); ++i) {
        s.components_.push_back(others[i]);
        s.weights_.push_back(other_weights[i] / weight_total);
    }
    s.weight_cdf_ = running_sum(s.weights_);
    return s;
}

double SizeDistribution::sample_component(const Component& c, Rng& rng) {
    if (const auto* d = std::get_if<Discrete>(&c)) {
        if (d->diameters.size() == 1) return d->diameters[0];
        return d->diameters[pick(d->cdf, rng.uniform())];
    }
    const auto& ln = std::get<Lognormal>(c);
    // Rejection is exact for truncation; construction guaranteed acceptance >= 0.1%.
    for (;;) {
        const double d = std::exp(ln.mu + ln.sigma * rng.normal());
        if (d >= ln.min_d && d <= ln.max_d) return d;
    }
}

double SizeDistribution::sample(Rng& rng) const {
    // With one component no deviate is spent choosing it, so single/table streams stay short.
    if (components_.size() == 1) return sample_component(components_[0], rng);
    return sample_component(components_[pick(weight_cdf_, rng.uniform())], rng);
}

double SizeDistribution::component_min(const Component& c) {
    if (const auto* d = std::get_if<Discrete>(&c)) return *std::min_element(d->diameters.begin(), d->diameters.end());
    return std::get<Lognormal>(c).min_d;
}

double SizeDistribution::component_max(const Component& c) {
    if (const auto* d = std::get_if<Discrete>(&c)) return *std::max_element(d->diameters.begin(), d->diameters.end());
    return std::get<Lognormal>(c).max_d;
}

double SizeDistribution::min_diameter() const {
    double m = component_min(components_[0]);
    for (const auto& c : components_) m = std::min(m, component_min(c));
    return m;
}

double SizeDistribution::max_diameter() const {
    double m = component_max(components_[0]);
    for (const auto& c : components_) m = std::max(m, component_max(c));
    return m;
}

double SizeDistribution::component_moment(const Component& c, int k) {
    if (const auto* d = std::get_if<Discrete>(&c)) {
        double m = 0.0;
        for (std::size_t i = 0; i < d->diameters.size(); ++i) m += d->fractions[i] * std::pow(d->diameters[i], k);
        return m;
    }
    // Truncated lognormal: E[d^k] = exp(k mu + k^2 s^2 / 2) * P(a - ks < Z < b - ks) / P(a < Z < b)
    // with a, b the standardised log bounds. Closed form, so no quadrature error.
    const auto& ln = std::get<Lognormal>(c);
    const double a = (std::log(ln.min_d) - ln.mu) / ln.sigma;
    const double b = (std::log(ln.max_d) - ln.mu) / ln.sigma;
    const double ks = k * ln.sigma;
    return std::exp(k * ln.mu + 0.5 * ks * ks) * normal_interval(a - ks, b - ks) / normal_interval(a, b);
}

double SizeDistribution::moment(int k) const {
    double m = 0.0;
    for (std::size_t c = 0; c < components_.size(); ++c) m += weights_[c] * component_moment(components_[c], k);
    return m;
}

double SizeDistribution::mean_particle_volume() const { return kPi / 6.0 * moment(3); }

double SizeDistribution::mean_diameter_number() const { return moment(1); }

std::vector<double> SizeDistribution::sample_for_volume(double solid_volume, Rng& rng) const {
    if (!(solid_volume >= 0.0) || !std::isfinite(solid_volume))
        throw std::invalid_argument("SizeDistribution::sample_for_volume: solid volume must be >= 0");
    const double expected = solid_volume / mean_particle_volume();
    if (expected > most_grains_in_memory()) {
        std::ostringstream msg;
        msg << std::setprecision(2) << "about " << expected << " grains would fill the region, more than the "
            << most_grains_in_memory() << " this machine's memory holds (" << kBytesPerGrain / 1e3
            << " kB each, lists included): use larger grains or a smaller region";
        throw std::invalid_argument(msg.str());
    }
    std::vector<double> out;
    out.reserve(static_cast<std::size_t>(expected * 1.1) + 1);
    double total = 0.0;
    for (;;) {
        const double d = sample(rng);
        const double v = sphere_volume(d);
        if (total + v < solid_volume) {
            out.push_back(d);
            total += v;
            continue;
        }
        if (total + v - solid_volume < solid_volume - total) out.push_back(d);
        break;
    }
    std::sort(out.begin(), out.end(), std::greater<>());
    return out;
}

bool SizeDistribution::is_discrete() const {
    return components_.size() == 1 && std::holds_alternative<Discrete>(components_[0]);
}

std::vector<SizeDistribution::SizeClass> SizeDistribution::discrete_classes() const {
    // Mixtures merge all discrete parts into one component, so "discrete" means exactly one.
    if (!is_discrete()) throw std::logic_error("SizeDistribution::discrete_classes: distribution has a lognormal part");
    const auto& d = std::get<Discrete>(components_[0]);
    std::vector<SizeClass> out;
    for (std::size_t i = 0; i < d.diameters.size(); ++i) out.push_back({d.diameters[i], d.fractions[i]});
    return out;
}

}  // namespace mrjam
