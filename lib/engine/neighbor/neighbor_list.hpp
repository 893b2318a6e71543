#pragma once
// Verlet neighbour list fed by a cell grid, with per-pair contact history.
//
// Half list: each pair is stored once, under its "owner", the larger grain (the lower index on a
// tie). A grain only searches the ball of radius cutoff(R_i, R_i) around itself for partners no
// larger than itself, which covers every pair it owns because the cutoff grows with both radii.
// So small grains search small neighbourhoods and the few big ones search wide: correct for any
// size ratio (Trendler's 0.67-24 um is 36:1), and cheap when big grains are rare.
//
// Pair cutoff = scale (R_i + R_j) + skin. Positions are wrapped into the box only at rebuild, so
// the periodic image shift of a pair is fixed between rebuilds and stored with it (no
// minimum-image arithmetic in the force loop). Rebuild when any grain has moved more than
// skin / 2 since the last build.
//
// Lees-Edwards: the images across z are displaced along x by the domain's shear offset, which
// moves between rebuilds. The shift table follows it each step (set_shear_offset), so a pair's
// stored image code stays valid; pairs through the z boundary are found at build time with the
// offset applied before the x minimum image. Their separation drifts by the offset's change, so
// the rebuild criterion is 2 max|dx| + |d offset| > skin (rebuild_displacement_sq(offset)).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iosfwd>
#include <limits>
#include <vector>

#include "contact/hertz_mindlin.hpp"
#include "core/domain.hpp"
#include "particles.hpp"

namespace mrjam {

class NeighborList {
public:
    struct Settings {
        double skin = 0;          // m
        double cutoff_scale = 1;  // multiple of R_i + R_j
        bool keep_history = true;
        double cutoff_extra = 0;  // m added to the interaction range (e.g. a magnetic range beyond contact)
        // > 0: the range is at most this multiple of R_i + R_j. With cutoff_extra it gives fine
        // grains a range in their own diameters while coarse pairs keep a range beyond contact
        // (Trendler's 33:67 fluid, whose fine grains would otherwise each list about 50 partners).
        double cutoff_max_scale = 0;
    };

    NeighborList() = default;
    explicit NeighborList(Settings s) : settings_(s) {}

    const Settings& settings() const { return settings_; }
    // Range within which a pair interacts, and the list cutoff (that range plus the skin).
    double interaction_range(double ri, double rj) const {
        const double range = settings_.cutoff_scale * (ri + rj) + settings_.cutoff_extra;
        return settings_.cutoff_max_scale > 0 ? std::min(range, settings_.cutoff_max_scale * (ri + rj)) : range;
    }
    double pair_cutoff(double ri, double rj) const { return interaction_range(ri, rj) + settings_.skin; }

    // Wraps positions into the periodic box, bins grains and rebuilds the list, carrying the
    // history of pairs that are still listed. Throws std::runtime_error when a periodic box is
    // too short for the cutoff (the minimum image would be ambiguous).
    void build(Particles& p, const Domain& domain, int threads);

    // The same list, filtered from a wider one (same skin, a reach at least as long) just built
    // at these positions: every pair this list holds is in the wider one, with the same owner and
    // image, so no grid search is needed. The contacts from the magnetic range, at a fraction of
    // a grid build. Pairs come in the wider list's order, which may differ from build()'s.
    void build_within(const NeighborList& wider, Particles& p, const Domain& domain, int threads);
    // True when every pair this list can hold is in `wider`: the same skin and a reach at least as
    // long for every pair of radii (each term of the wider range at least this one's, or, for a
    // range proportional to R_i + R_j like the contacts', the wider range's slopes no smaller).
    bool fits_within(const NeighborList& wider) const {
        const Settings& w = wider.settings_;
        const Settings& m = settings_;
        if (w.skin != m.skin) return false;
        const double inf = std::numeric_limits<double>::infinity();
        const double w_cap = w.cutoff_max_scale > 0 ? w.cutoff_max_scale : inf;
        const double m_cap = m.cutoff_max_scale > 0 ? m.cutoff_max_scale : inf;
        const bool termwise = w.cutoff_scale >= m.cutoff_scale && w.cutoff_extra >= m.cutoff_extra && w_cap >= m_cap;
        const bool proportional =
            m.cutoff_extra == 0 && std::min(w.cutoff_scale, w_cap) >= std::min(m.cutoff_scale, m_cap);
        return termwise || proportional;
    }

    bool needs_rebuild(const Particles& p, const Domain& domain, int threads) const;
    // A list left unbuilt while nothing uses it (the magnetic range with the magnet off) is marked
    // stale: its pairs stay as they were, and it is rebuilt before it is next needed.
    void mark_stale() { position_at_build_.clear(); }
    bool current(std::size_t grains) const {
        return position_at_build_.size() == grains && offsets.size() == grains + 1;
    }
    // Positions at the last build and the squared displacement that forces a rebuild, for passes
    // that already touch every position and test each grain themselves. Under Lees-Edwards the
    // offset's change since the build eats into the skin (negative: rebuild now).
    const Vec3* positions_at_build() const { return position_at_build_.data(); }
    double rebuild_displacement_sq(const Domain& domain) const {
        double half = 0.5 * settings_.skin;
        if (domain.lees_edwards) half -= 0.5 * std::abs(domain.shear_offset - offset_at_build_);
        return half > 0 ? half * half : -1.0;
    }
    // Moves the images across z to the domain's current Lees-Edwards offset and velocity.
    void set_shear_offset(const Domain& domain) {
        for (int a = 0; a < 27; ++a) {
            const int wz = a / 9 - 1;
            if (wz == 0) continue;
            shifts_[a].x = base_shift_x_[a] + wz * domain.shear_offset;
            velocity_shifts_[a].x = wz * domain.shear_velocity;
        }
    }

    // Pair k of owner i: k in [offsets[i], offsets[i+1]).
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> partners;
    std::vector<std::uint8_t> image;  // index into image_shift(): x_i - x_j + shift
    // history and touching are kept only with Settings::keep_history (the contact list); a list
    // without it (the magnetic range) leaves them empty.
    std::vector<ContactHistory> history;
    // 1 while the pair touches. History is zeroed when a contact starts, not every step a pair
    // is apart: a one-byte flag instead of a 48-byte write for each of the many listed pairs
    // that do not touch.
    std::vector<std::uint8_t> touching;
    // interaction_range(R_i, R_j)^2 per pair ((R_i + R_j)^2 for contacts), stored so the range
    // test reads the list sequentially instead of fetching the partner's radius.
    std::vector<double> range_sq;
    const Vec3& image_shift(std::uint8_t code) const { return shifts_[code]; }
    // Added to v_i - v_j: the partner's image velocity (non-zero only for Lees-Edwards images
    // across z), so contact damping and friction see the true relative velocity.
    const Vec3& image_velocity(std::uint8_t code) const { return velocity_shifts_[code]; }
    const Vec3* image_velocities() const { return velocity_shifts_; }

    std::size_t pair_count() const { return partners.size(); }

    // Drops the grains a removal took out (new_index[i]: grain i's index after the removal, or -1
    // if it went) and renumbers the rest, keeping every surviving pair with its image and
    // history, so the list stays valid without a rebuild. The removal keeps the grains' order,
    // so the ownership rule (larger grain, lower index on a tie) still picks the same owner.
    void remove_grains(const std::vector<std::int64_t>& new_index, std::size_t kept);

    // Checkpointing: the list, its history and the positions it was built at, so a resumed run
    // continues bit for bit.
    void save(std::ostream& out) const;
    void load(std::istream& in);
    long builds() const { return builds_; }

private:
    Settings settings_;
    std::vector<Vec3> position_at_build_;
    Vec3 shifts_[27];
    Vec3 velocity_shifts_[27] = {};
    double base_shift_x_[27] = {};  // x shift without the Lees-Edwards offset
    double offset_at_build_ = 0;
    long builds_ = 0;

    // Build scratch, kept between builds so each build reuses the last one's memory: the
    // previous list (its history is carried over) and one chunk of new pairs per thread.
    struct Chunk {
        std::vector<std::uint32_t> count;  // pairs per owner in this chunk
        std::vector<std::uint32_t> partner;
        std::vector<std::uint8_t> image;
        std::vector<ContactHistory> history;
        std::vector<std::uint8_t> touching;
        std::vector<double> range_sq;
    };
    std::vector<Chunk> chunks_;
    void set_images(const Domain& domain);
    bool begin_build(std::size_t n, int nthreads);  // true: carry the old list's history
    void push_pair(Chunk& ch, bool carry, std::uint32_t i, std::uint32_t j, std::uint8_t code, double range) const;
    void finish_build(const Particles& p, int nthreads);
    std::vector<std::uint32_t> old_offsets_, old_partners_;
    std::vector<ContactHistory> old_history_;
    std::vector<std::uint8_t> old_touching_;
};

}  // namespace mrjam
