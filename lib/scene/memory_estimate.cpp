#include "scene/memory_estimate.hpp"

#include <algorithm>
#include <cmath>

#include "core/format.hpp"
#include "core/physical_memory.hpp"
#include "scene/scene_node.hpp"

namespace mrjam {

namespace {

constexpr double kDensePacking = 0.64;
constexpr double kBytesPerGrain = 1.0e3;  // the grain arrays and per-grain term state
// A listed pair: partner, image, range (13 B) in the list and again in the rebuild's chunk; a
// contact pair also its history (48 B) and flag, kept twice while the list is rebuilt.
constexpr double kBytesPerMagneticPair = 26;
constexpr double kBytesPerContactPair = 124;

double pairs_within(double cutoff, double mean_volume, std::size_t grains) {
    const double neighbours = kDensePacking / mean_volume * 4.0 / 3.0 * M_PI * cutoff * cutoff * cutoff;
    return 0.5 * static_cast<double>(grains) * std::min(neighbours, static_cast<double>(grains) - 1);
}

}  // namespace

PairMemoryEstimate estimate_pair_memory(const System& s) {
    const Particles& p = s.particles;
    PairMemoryEstimate e;
    if (p.size() == 0) return e;
    double r_sum = 0, v_sum = 0;
    for (double r : p.radius) {
        r_sum += r;
        v_sum += 4.0 / 3.0 * M_PI * r * r * r;
    }
    const double r_mean = r_sum / p.size(), v_mean = v_sum / p.size();
    e.contact_pairs = pairs_within(s.contacts.pair_cutoff(r_mean, r_mean), v_mean, p.size());
    if (s.magnetic.enabled)
        e.magnetic_pairs = pairs_within(s.magnetic.pairs.pair_cutoff(r_mean, r_mean), v_mean, p.size());
    e.bytes =
        kBytesPerGrain * p.size() + kBytesPerContactPair * e.contact_pairs + kBytesPerMagneticPair * e.magnetic_pairs;
    return e;
}

void check_pair_memory(const System& s) {
    const double memory = physical_memory_bytes();
    const PairMemoryEstimate e = estimate_pair_memory(s);
    if (!(memory > 0) || e.bytes <= 0.8 * memory) return;
    const bool magnetic = kBytesPerMagneticPair * e.magnetic_pairs > kBytesPerContactPair * e.contact_pairs;
    const std::string sizes = format_number(e.bytes / 1e9, 3) + " GB (" + format_number(s.particles.size()) +
                              " grains, about " + format_number(e.contact_pairs, 3) + " contact and " +
                              format_number(e.magnetic_pairs, 3) + " magnetic pairs listed at a dense packing)";
    const std::string machine = "this machine has " + format_number(memory / 1e9, 3) + " GB";
    if (magnetic)
        throw SceneError("/magnetic/cutoff", "the magnetic pair lists would need up to " + sizes + "; " + machine +
                                                 ": shorten the cutoff (it is long next to the grains) or use "
                                                 "fewer grains");
    throw SceneError("/grains", "the grains and their contact lists would need up to " + sizes + "; " + machine +
                                    ": use fewer grains");
}

}  // namespace mrjam
