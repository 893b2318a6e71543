#include "neighbor/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/binary_io.hpp"

namespace mrjam {
namespace {

// Uniform grid over the box. Grains outside the box on a closed axis are clamped into the edge
// cells: merging cells never separates neighbours, so no pair is lost.
struct CellGrid {
    Vec3 lo;
    double size[3];
    int count[3];
    std::vector<std::uint32_t> start;  // first slot of each cell in `order`
    std::vector<std::uint32_t> order;  // grains sorted by cell
    std::vector<std::uint32_t> cell_of;
    // Each grain's position and radius copied in cell order, so the stencil's inner loop reads
    // its candidates sequentially instead of gathering them from the particle arrays.
    struct Binned {
        Vec3 x;
        double r;
    };
    std::vector<Binned> binned;

    int axis_cell(double x, int k) const {
        const int c = static_cast<int>(std::floor((x - lo[k]) / size[k]));
        return std::clamp(c, 0, count[k] - 1);
    }
    std::uint32_t cell_index(int cx, int cy, int cz) const {
        return static_cast<std::uint32_t>((cz * count[1] + cy) * count[0] + cx);
    }
};

CellGrid bin(const Particles& p, const Domain& domain, double target_size) {
    CellGrid g;
    g.lo = domain.lo;
    const Vec3 len = domain.length();
    // Cap the grid at ~4 cells per grain so a tiny cutoff in a big box cannot exhaust memory.
    const double max_cells = std::max<double>(64.0, 4.0 * static_cast<double>(p.size()));
    double h = target_size;
    while ((len.x / h) * (len.y / h) * (len.z / h) > max_cells) h *= 1.25;
    for (int k = 0; k < 3; ++k) {
        g.count[k] = std::max(1, static_cast<int>(std::floor(len[k] / h)));
        g.size[k] = len[k] / g.count[k];
    }
    const std::size_t ncell = static_cast<std::size_t>(g.count[0]) * g.count[1] * g.count[2];
    g.start.assign(ncell + 1, 0);
    g.cell_of.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3& x = p.position[i];
        const std::uint32_t c = g.cell_index(g.axis_cell(x.x, 0), g.axis_cell(x.y, 1), g.axis_cell(x.z, 2));
        g.cell_of[i] = c;
        ++g.start[c + 1];
    }
    for (std::size_t c = 0; c < ncell; ++c) g.start[c + 1] += g.start[c];
    g.order.resize(p.size());
    std::vector<std::uint32_t> fill(g.start.begin(), g.start.end() - 1);
    for (std::size_t i = 0; i < p.size(); ++i) g.order[fill[g.cell_of[i]]++] = static_cast<std::uint32_t>(i);
    g.binned.resize(p.size());
    for (std::size_t s = 0; s < p.size(); ++s) g.binned[s] = {p.position[g.order[s]], p.radius[g.order[s]]};
    return g;
}

// Cells along one axis within `reach` cells of c, each once, with the periodic wrap recorded.
// Sized at run time: a grain 40 times the mean spans more than a hundred cells.
struct AxisRange {
    std::vector<int> cell;
    std::vector<int> wrap;     // -1, 0, +1 periods added to the partner's coordinate; 2 = minimum image
    std::vector<double> gap2;  // squared distance along the axis from the grain to the cell (0: unknown)
    int n = 0;
    void push(int c, int w) {
        if (n == static_cast<int>(cell.size())) {
            cell.push_back(c);
            wrap.push_back(w);
            gap2.push_back(0);
        } else {
            cell[n] = c;
            wrap[n] = w;
            gap2[n] = 0;
        }
        ++n;
    }
};

void axis_range(int c, int reach, int count, bool periodic, AxisRange& r) {
    r.n = 0;
    if (periodic && 2 * reach + 1 >= count) {
        // The stencil covers the whole period: visit every cell once; the image is chosen per
        // pair by minimum image below.
        for (int k = 0; k < count; ++k) r.push(k, 2);
        return;
    }
    for (int d = -reach; d <= reach; ++d) {
        int k = c + d, w = 0;
        if (periodic) {
            if (k < 0) {
                k += count;
                w = -1;
            } else if (k >= count) {
                k -= count;
                w = +1;
            }
        } else if (k < 0 || k >= count) {
            continue;
        }
        r.push(k, w);
    }
}

// Each cell's distance along axis k from coordinate x, so the stencil can skip the cells of its
// cube that lie wholly outside the grain's reach (about half of a stencil three cells deep). A
// cell at the end of a closed axis also holds the grains clamped into it from beyond the box, so
// it reaches to infinity on that side; a whole-period entry (wrap 2) is never skipped.
void axis_gaps(const CellGrid& g, int k, double x, double box_length, bool periodic, AxisRange& r) {
    for (int a = 0; a < r.n; ++a) {
        if (r.wrap[a] == 2) {
            r.gap2[a] = 0;
            continue;
        }
        const int c = r.cell[a];
        const double shift = r.wrap[a] * box_length;
        const double lo = (!periodic && c == 0) ? -INFINITY : g.lo[k] + c * g.size[k] + shift;
        const double hi = (!periodic && c == g.count[k] - 1) ? INFINITY : g.lo[k] + (c + 1) * g.size[k] + shift;
        const double gap = std::max({0.0, lo - x, x - hi});
        r.gap2[a] = gap * gap;
    }
}

// The owners split into one contiguous chunk per thread (deterministic for a given thread count);
// fill(chunk, begin, end) lists the pairs of owners begin..end-1 into the chunk.
template <class Chunks, class Fill>
void fill_chunks(Chunks& chunks, std::size_t n, int nthreads, Fill fill) {
#pragma omp parallel num_threads(nthreads)
    {
        const int t = omp_get_thread_num();
        const std::size_t begin = n * t / nthreads, end = n * (t + 1) / nthreads;
        auto& ch = chunks[t];
        ch.count.assign(end - begin, 0);
        fill(ch, begin, end);
    }
}

// The pair's owner: the larger grain, the lower index on a tie. Bitwise, so the candidate loop
// below compiles without a branch for it.
inline bool owns(double ri, std::uint32_t i, double rj, std::uint32_t j) { return (rj < ri) | ((rj == ri) & (j > i)); }

// The index into the 27 image shifts of a partner sitting w periods away: the shift -w L is added
// to x_i - x_j.
inline std::uint8_t image_code(int wx, int wy, int wz) {
    return static_cast<std::uint8_t>((-wx + 1) + 3 * (-wy + 1) + 9 * (-wz + 1));
}

// x_i - x_j for a candidate whose stencil entry may leave the image open (wrap 2: minimum image)
// or cross the Lees-Edwards boundary, with w[] resolved to the image used.
Vec3 stencil_separation(const Vec3& xi, const Vec3& xj, int w[3], const Vec3& len, bool sliding, double shear_offset) {
    Vec3 d = xi - xj;
    if (sliding) {
        // z first: the z image decides the x shift of the partner.
        if (w[2] == 2) w[2] = static_cast<int>(std::nearbyint(d.z / len.z));
        d.z -= w[2] * len.z;
        d.x -= w[2] * shear_offset;
        for (int k = 0; k < 2; ++k) {
            if (w[k] == 2) w[k] = static_cast<int>(std::nearbyint(d[k] / len[k]));
            d[k] -= w[k] * len[k];
        }
        return d;
    }
    for (int k = 0; k < 3; ++k) {
        if (w[k] == 2) w[k] = static_cast<int>(std::nearbyint(d[k] / len[k]));
        d[k] -= w[k] * len[k];  // x_i - (x_j + w L): the partner image sits w periods away
    }
    return d;
}

// The candidates of one cell that grain i owns and that lie within their cutoff, when the whole
// cell sits at one periodic image (`shifted_xi` = x_i with that image's shift). Appends their
// slots in `order` to `accepted`. Branch-free: the owner and range tests
// each fail about half the time, unpredictably, and a mispredicted branch per candidate was
// most of a build's time.
template <class Cutoff>
void accept_in_cell(const CellGrid& grid, std::uint32_t cell, std::uint32_t i, const Vec3& shifted_xi, double ri,
                    Cutoff cutoff, std::vector<std::uint32_t>& accepted) {
    const std::uint32_t s0 = grid.start[cell], s1 = grid.start[cell + 1];
    const std::size_t base = accepted.size();
    accepted.resize(base + (s1 - s0));
    std::uint32_t* __restrict out = accepted.data() + base;
    std::uint32_t count = 0;
    for (std::uint32_t s = s0; s < s1; ++s) {
        const CellGrid::Binned& b = grid.binned[s];
        const double cut = cutoff(ri, b.r);
        out[count] = s;
        count += static_cast<std::uint32_t>(owns(ri, i, b.r, grid.order[s]) & (norm2(shifted_xi - b.x) < cut * cut));
    }
    accepted.resize(base + count);
}

}  // namespace

void NeighborList::build(Particles& p, const Domain& domain, int threads) {
    const std::size_t n = p.size();
    const Vec3 len = domain.length();
    // y may be closed (a monolayer, or walls along y): the sliding only couples x and z.
    if (domain.lees_edwards && !(domain.periodic[0] && domain.periodic[2]))
        throw std::runtime_error("Lees-Edwards boundaries need a box periodic along x (flow) and z (gradient)");
    for (std::size_t i = 0; i < n; ++i) domain.wrap(p.position[i], p.velocity[i]);

    double r_max = 0, r_sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
        r_max = std::max(r_max, p.radius[i]);
        r_sum += p.radius[i];
    }
    const double r_mean = n ? r_sum / n : 0;
    for (int k = 0; k < 3; ++k) {
        if (domain.periodic[k] && pair_cutoff(r_max, r_max) > 0.5 * len[k]) {
            std::ostringstream s;
            s << "the periodic box is " << len[k] << " m long on axis " << char('x' + k)
              << " but the neighbour cutoff of the largest grains is " << pair_cutoff(r_max, r_max)
              << " m; the box must be at least twice the cutoff (make the box larger or the cutoff shorter)";
            throw std::runtime_error(s.str());
        }
    }
    set_images(domain);
    const bool sliding = domain.lees_edwards;

    const CellGrid grid = bin(p, domain, std::max(pair_cutoff(r_mean, r_mean), 1e-300));

    const int nthreads = std::max(1, threads);
    const bool carry = begin_build(n, nthreads);

    fill_chunks(chunks_, n, nthreads, [&](Chunk& ch, std::size_t begin, std::size_t end) {
        AxisRange rx, ry, rz, rx_sliding;
        std::vector<std::uint32_t> accepted;
        const auto cutoff = [this](double a, double b) { return pair_cutoff(a, b); };
        for (std::size_t ii = begin; ii < end; ++ii) {
            const auto i = static_cast<std::uint32_t>(ii);
            const Vec3 xi = p.position[i];
            const double ri = p.radius[i];
            const double reach_len = pair_cutoff(ri, ri);
            int c[3];
            for (int k = 0; k < 3; ++k) c[k] = grid.axis_cell(xi[k], k);
            axis_range(c[0], static_cast<int>(std::ceil(reach_len / grid.size[0])), grid.count[0], domain.periodic[0],
                       rx);
            axis_range(c[1], static_cast<int>(std::ceil(reach_len / grid.size[1])), grid.count[1], domain.periodic[1],
                       ry);
            axis_range(c[2], static_cast<int>(std::ceil(reach_len / grid.size[2])), grid.count[2], domain.periodic[2],
                       rz);
            const int reach_x = static_cast<int>(std::ceil(reach_len / grid.size[0]));
            // No partner of i (none larger than i) is farther than reach_len.
            const double reach2 = reach_len * reach_len;
            axis_gaps(grid, 0, xi.x, len.x, domain.periodic[0], rx);
            axis_gaps(grid, 1, xi.y, len.y, domain.periodic[1], ry);
            axis_gaps(grid, 2, xi.z, len.z, domain.periodic[2], rz);
            for (int az = 0; az < rz.n; ++az) {
                // Lees-Edwards: across the z boundary the partners' images sit shifted along x by
                // the offset, so the x stencil is centred on x_i - offset (one cell wider: the
                // shift is not a whole number of cells) and the x image is chosen per pair.
                AxisRange* xs = &rx;
                if (sliding && rz.wrap[az] != 0) {
                    if (rz.wrap[az] == 2) {
                        axis_range(0, grid.count[0], grid.count[0], true, rx_sliding);
                    } else {
                        const double centre = xi.x - rz.wrap[az] * domain.shear_offset;
                        const double wrapped = centre - len.x * std::floor((centre - domain.lo.x) / len.x);
                        axis_range(grid.axis_cell(wrapped, 0), reach_x + 1, grid.count[0], true, rx_sliding);
                        for (int a = 0; a < rx_sliding.n; ++a) rx_sliding.wrap[a] = 2;
                    }
                    xs = &rx_sliding;
                }
                for (int ay = 0; ay < ry.n; ++ay)
                    for (int ax = 0; ax < xs->n; ++ax) {
                        if (rz.gap2[az] + ry.gap2[ay] + xs->gap2[ax] >= reach2) continue;  // wholly out of reach
                        const std::uint32_t cell = grid.cell_index(xs->cell[ax], ry.cell[ay], rz.cell[az]);
                        const int wx = xs->wrap[ax], wy = ry.wrap[ay], wz = rz.wrap[az];
                        if (!sliding && wx != 2 && wy != 2 && wz != 2) {
                            // One image for the whole cell: x_i - (x_j + w L).
                            const Vec3 shifted_xi = xi - Vec3{wx * len.x, wy * len.y, wz * len.z};
                            accepted.clear();
                            accept_in_cell(grid, cell, i, shifted_xi, ri, cutoff, accepted);
                            const std::uint8_t code = image_code(wx, wy, wz);
                            for (std::uint32_t s : accepted) {
                                push_pair(ch, carry, i, grid.order[s], code, interaction_range(ri, grid.binned[s].r));
                                ++ch.count[ii - begin];
                            }
                            continue;
                        }
                        for (std::uint32_t s = grid.start[cell]; s < grid.start[cell + 1]; ++s) {
                            const CellGrid::Binned& bj = grid.binned[s];
                            const std::uint32_t j = grid.order[s];
                            if (!owns(ri, i, bj.r, j)) continue;
                            int w[3] = {wx, wy, wz};
                            const Vec3 d = stencil_separation(xi, bj.x, w, len, sliding, domain.shear_offset);
                            const double cut = pair_cutoff(ri, bj.r);
                            if (norm2(d) >= cut * cut) continue;
                            push_pair(ch, carry, i, j, image_code(w[0], w[1], w[2]), interaction_range(ri, bj.r));
                            ++ch.count[ii - begin];
                        }
                    }
            }
        }
    });
    finish_build(p, nthreads);
}

void NeighborList::build_within(const NeighborList& wider, Particles& p, const Domain& domain, int threads) {
    const std::size_t n = p.size();
    if (!fits_within(wider) || wider.offsets.size() != n + 1 ||
        !std::equal(p.position.begin(), p.position.end(), wider.position_at_build_.begin(),
                    wider.position_at_build_.end(),
                    [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }))
        throw std::logic_error(
            "build_within: the wider list must share the skin, reach at least as far and have "
            "been built at these positions");
    set_images(domain);
    const int nthreads = std::max(1, threads);
    const bool carry = begin_build(n, nthreads);
    fill_chunks(chunks_, n, nthreads, [&](Chunk& ch, std::size_t begin, std::size_t end) {
        for (std::size_t ii = begin; ii < end; ++ii) {
            const auto i = static_cast<std::uint32_t>(ii);
            const Vec3 xi = p.position[i];
            const double ri = p.radius[i];
            for (std::uint32_t k = wider.offsets[i]; k < wider.offsets[i + 1]; ++k) {
                const std::uint32_t j = wider.partners[k];
                const std::uint8_t code = wider.image[k];
                const double cut = pair_cutoff(ri, p.radius[j]);
                if (norm2(xi - p.position[j] + shifts_[code]) >= cut * cut) continue;
                push_pair(ch, carry, i, j, code, interaction_range(ri, p.radius[j]));
                ++ch.count[ii - begin];
            }
        }
    });
    finish_build(p, nthreads);
}

void NeighborList::set_images(const Domain& domain) {
    const Vec3 len = domain.length();
    for (int a = 0; a < 27; ++a) {
        const int w[3] = {a % 3 - 1, (a / 3) % 3 - 1, a / 9 - 1};
        shifts_[a] = {w[0] * len.x, w[1] * len.y, w[2] * len.z};
        base_shift_x_[a] = shifts_[a].x;
        velocity_shifts_[a] = Vec3{};
    }
    offset_at_build_ = domain.shear_offset;
    set_shear_offset(domain);
}

// The last list is kept to carry contact history over: swapped, not copied, into buffers that
// persist between builds, as do the per-thread chunks, so a build reuses the memory of the builds
// before it instead of faulting in fresh pages for every pair (a tenth of a build's time in a
// 100,000-grain valve).
bool NeighborList::begin_build(std::size_t n, int nthreads) {
    old_offsets_.swap(offsets);
    old_partners_.swap(partners);
    old_history_.swap(history);
    old_touching_.swap(touching);
    chunks_.resize(nthreads);
    for (Chunk& ch : chunks_) {
        ch.partner.clear();
        ch.image.clear();
        ch.history.clear();
        ch.touching.clear();
        ch.range_sq.clear();
    }
    return settings_.keep_history && old_offsets_.size() == n + 1;
}

void NeighborList::push_pair(Chunk& ch, bool carry, std::uint32_t i, std::uint32_t j, std::uint8_t code,
                             double range) const {
    if (settings_.keep_history) {  // a list without history (the magnetic range) stores none
        ContactHistory h{};
        std::uint8_t touch = 0;
        if (carry) {
            for (std::uint32_t k = old_offsets_[i]; k < old_offsets_[i + 1]; ++k)
                if (old_partners_[k] == j) {
                    h = old_history_[k];
                    touch = old_touching_[k];
                    break;
                }
        }
        ch.history.push_back(h);
        ch.touching.push_back(touch);
    }
    ch.partner.push_back(j);
    ch.image.push_back(code);
    ch.range_sq.push_back(range * range);
}

void NeighborList::finish_build(const Particles& p, int nthreads) {
    const std::size_t n = p.size();
    offsets.assign(n + 1, 0);
    std::size_t i = 0;
    for (const auto& ch : chunks_)
        for (auto c : ch.count) {
            offsets[i + 1] = offsets[i] + c;
            ++i;
        }
    if (nthreads == 1) {
        // One chunk is the whole list: hand its arrays over (the list's old ones become the
        // chunk's buffers for the next build).
        Chunk& ch = chunks_[0];
        partners.swap(ch.partner);
        image.swap(ch.image);
        history.swap(ch.history);
        touching.swap(ch.touching);
        range_sq.swap(ch.range_sq);
    } else {
        partners.clear();
        image.clear();
        history.clear();
        touching.clear();
        range_sq.clear();
        for (const auto& ch : chunks_) {
            partners.insert(partners.end(), ch.partner.begin(), ch.partner.end());
            image.insert(image.end(), ch.image.begin(), ch.image.end());
            history.insert(history.end(), ch.history.begin(), ch.history.end());
            touching.insert(touching.end(), ch.touching.begin(), ch.touching.end());
            range_sq.insert(range_sq.end(), ch.range_sq.begin(), ch.range_sq.end());
        }
    }
    position_at_build_ = p.position;
    ++builds_;
}

void NeighborList::remove_grains(const std::vector<std::int64_t>& new_index, std::size_t kept) {
    const std::size_t n = new_index.size();
    if (offsets.size() != n + 1) {  // never built, or built for another count: the next step rebuilds
        position_at_build_.clear();
        return;
    }
    std::vector<std::uint32_t> new_offsets(kept + 1, 0);
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (new_index[i] < 0) continue;
        for (std::uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
            const std::int64_t j = new_index[partners[k]];
            if (j < 0) continue;
            partners[out] = static_cast<std::uint32_t>(j);
            image[out] = image[k];
            if (!history.empty()) {
                history[out] = history[k];
                touching[out] = touching[k];
            }
            range_sq[out] = range_sq[k];
            ++out;
        }
        new_offsets[static_cast<std::size_t>(new_index[i]) + 1] = static_cast<std::uint32_t>(out);
    }
    offsets.swap(new_offsets);
    partners.resize(out);
    image.resize(out);
    if (!history.empty()) {
        history.resize(out);
        touching.resize(out);
    }
    range_sq.resize(out);
    if (position_at_build_.size() == n) {
        for (std::size_t i = 0; i < n; ++i)
            if (new_index[i] >= 0) position_at_build_[static_cast<std::size_t>(new_index[i])] = position_at_build_[i];
        position_at_build_.resize(kept);
    }
}

bool NeighborList::needs_rebuild(const Particles& p, const Domain& domain, int threads) const {
    if (position_at_build_.size() != p.size()) return true;
    const double limit2 = rebuild_displacement_sq(domain);
    if (limit2 < 0) return true;
    const std::size_t n = p.size();
    int moved = 0;
#pragma omp parallel for reduction(| : moved) schedule(static) num_threads(threads)
    for (std::size_t i = 0; i < n; ++i)
        if (norm2(p.position[i] - position_at_build_[i]) > limit2) moved = 1;
    return moved != 0;
}

}  // namespace mrjam

namespace mrjam {

void NeighborList::save(std::ostream& out) const {
    binary::put(out, settings_);
    binary::put_vector(out, offsets);
    binary::put_vector(out, partners);
    binary::put_vector(out, image);
    binary::put_vector(out, history);
    binary::put_vector(out, touching);
    binary::put_vector(out, range_sq);
    binary::put_vector(out, position_at_build_);
    for (const Vec3& s : shifts_) binary::put(out, s);
    for (const Vec3& s : velocity_shifts_) binary::put(out, s);
    for (double s : base_shift_x_) binary::put(out, s);
    binary::put(out, offset_at_build_);
    binary::put(out, builds_);
}

void NeighborList::load(std::istream& in) {
    settings_ = binary::get<Settings>(in);
    binary::get_vector(in, offsets);
    binary::get_vector(in, partners);
    binary::get_vector(in, image);
    binary::get_vector(in, history);
    binary::get_vector(in, touching);
    binary::get_vector(in, range_sq);
    binary::get_vector(in, position_at_build_);
    for (Vec3& s : shifts_) s = binary::get<Vec3>(in);
    for (Vec3& s : velocity_shifts_) s = binary::get<Vec3>(in);
    for (double& s : base_shift_x_) s = binary::get<double>(in);
    offset_at_build_ = binary::get<double>(in);
    builds_ = binary::get<long>(in);
}

}  // namespace mrjam
