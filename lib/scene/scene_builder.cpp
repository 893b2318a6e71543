// Scene file -> System and protocol. Every check that can be made before work is made here.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/exit_status.hpp"
#include "core/machine_threads.hpp"
#include "geometry/disc_packing.hpp"
#include "geometry/packing.hpp"
#include "run/interrupt.hpp"
#include "scene/fidelity.hpp"
#include "scene/memory_estimate.hpp"
#include "scene/output_block.hpp"
#include "scene/plausibility.hpp"
#include "scene/scene.hpp"
#include "scene/scene_parts.hpp"
#include "scene/scene_physics.hpp"
#include "spatial_sort.hpp"
#include "terms/drag_term.hpp"
#include "terms/gravity_term.hpp"
#include "terms/magnetic_term.hpp"
#include "terms/pair_damping_term.hpp"

namespace mrjam {
namespace {

constexpr double kRandomClosePacking = 0.64;

// A placement's region (the whole box by default). On an axis that is not periodic it must lie
// inside the box: grains placed outside it leave at the first step, which read as a blow-up.
Region placement_region(SceneNode& place, const Domain& domain) {
    if (!place.has("region")) return Region::box(domain.lo, domain.hi);
    const Region region = read_region(place.object("region"), domain);
    const Vec3 lo = region.bbox_lo(), hi = region.bbox_hi();
    for (int k = 0; k < 3; ++k)
        if (!domain.periodic[k] && (lo[k] < domain.lo[k] || hi[k] > domain.hi[k]))
            place.fail("region", std::string("reaches outside the domain along ") + char('x' + k) + " (" +
                                     format_number(lo[k]) + " to " + format_number(hi[k]) + " m against " +
                                     format_number(domain.lo[k]) + " to " + format_number(domain.hi[k]) +
                                     " m), which is not periodic: keep it inside /domain");
    return region;
}

Domain read_domain(SceneNode node) {
    Domain d;
    d.lo = node.vector("lo", units::length, std::nullopt);
    d.hi = node.vector("hi", units::length, std::nullopt);
    for (int k = 0; k < 3; ++k)
        if (!(d.hi[k] > d.lo[k])) node.fail("hi", "each component must exceed the matching component of lo");
    const auto flags = node.axis_flags("periodic", std::vector<bool>{false, false, false});
    for (int k = 0; k < 3; ++k) d.periodic[k] = flags[k];
    const std::string mono = node.choice("monolayer", {"none", "x", "y", "z"}, "none");
    if (mono != "none") {
        d.monolayer_normal = mono[0] - 'x';
        if (d.periodic[d.monolayer_normal])
            node.fail("monolayer", "a monolayer's normal axis (" + mono +
                                       ") must not be periodic: the layer is one grain thick "
                                       "and needs no images; drop " +
                                       mono + " from /domain/periodic");
    }
    node.finish();
    return d;
}

// Runs a packing that returns its spheres and the fraction it reached: an interrupt passes
// through (exit 130 at once), a packing that cannot be done is refused at `key`, and a fraction
// more than 2 % from the requested one is a warning.
template <class Packing>
std::vector<Sphere> run_packing(const SceneNode& node, SceneNode& place, Scene& scene, const std::string& key,
                                const std::string& what, double requested, Packing packing) {
    try {
        auto [spheres, achieved] = packing();
        if (std::fabs(achieved - requested) > 0.02 * requested)
            scene.warnings.push_back(node.path() + ": packed " + what + " " + format_number(achieved) +
                                     " differs from the requested " + format_number(requested));
        return spheres;
    } catch (const SetupInterrupted&) {
        throw;
    } catch (const std::exception& e) {
        place.fail(key, e.what());
    }
}

// The packing's own keys, and Ctrl-C's flag: a long packing stops at once.
PackingOptions packing_options(SceneNode& place) {
    PackingOptions opt;
    opt.overlap_tolerance = place.number("overlap_tolerance", 1e-3, Bounds::open(0.0, 0.5));
    opt.cancelled = interrupt_requested;
    return opt;
}

// One batch of grains: a material, a size distribution, a placement and initial motion.
// The placement methods of a /grains batch, each reading its keys and returning the spheres
// (none when `insert` is false: a resumed scene takes its grains from the checkpoint).
std::vector<Sphere> place_random(SceneNode& node, SceneNode& place, Scene& scene, const SizeDistribution& sizes,
                                 Rng& rng, bool insert) {
    System& s = scene.system;
    const double phi = place.number("volume_fraction", std::nullopt, Bounds::open_closed(0.0, 1.0));
    if (phi > kRandomClosePacking)
        place.fail("volume_fraction",
                   "cannot exceed random close packing of spheres, " + format_number(kRandomClosePacking));
    const Region region = placement_region(place, s.domain);
    const PackingOptions opt = packing_options(place);
    if (!region.fits(0.5 * sizes.max_diameter(), s.domain))
        place.fail("region", "the largest grain does not fit inside the insertion region");
    place.finish();
    if (!insert) return {};
    return run_packing(node, place, scene, "volume_fraction", "volume fraction", phi, [&] {
        PackingResult r = random_packing(region, s.domain, sizes, phi, rng, opt);
        return std::pair{std::move(r.spheres), r.achieved_volume_fraction};
    });
}

std::vector<Sphere> place_monolayer(SceneNode& node, SceneNode& place, Scene& scene, const SizeDistribution& sizes,
                                    Rng& rng, bool insert) {
    System& s = scene.system;
    const int mono = s.domain.monolayer_normal;
    const double phi = place.number("area_fraction", std::nullopt, Bounds::open_closed(0.0, 1.0));
    if (phi > kRandomClosePackingDiscs)
        place.fail("area_fraction", "cannot exceed random close packing of discs, " +
                                        format_number(kRandomClosePackingDiscs) +
                                        "; lower it (0.5 is a loose monolayer)");
    const PackingOptions opt = packing_options(place);
    place.finish();
    if (!insert) return {};
    return run_packing(node, place, scene, "area_fraction", "area fraction", phi, [&] {
        DiscPackingResult r = random_disc_packing(s.domain, mono, sizes, phi, rng, opt);
        return std::pair{std::move(r.discs), r.achieved_area_fraction};
    });
}

std::vector<Sphere> place_lattice(SceneNode& node, SceneNode& place, const System& s, const SizeDistribution& sizes,
                                  bool insert) {
    std::vector<Sphere> spheres;
    if (!sizes.is_discrete() || sizes.discrete_classes().size() != 1)
        node.fail("size", "lattice placement needs a single grain size");
    const double diameter = sizes.max_diameter();
    const double spacing = place.quantity("spacing", units::length, diameter, Bounds::positive());
    if (spacing < diameter) place.fail("spacing", "must be at least the grain diameter " + format_number(diameter));
    const std::string lattice = place.choice("lattice", {"cubic", "fcc"}, "cubic");
    const Region region = placement_region(place, s.domain);
    place.finish();
    if (insert) try {
            spheres = lattice_packing(region, s.domain, diameter, spacing, lattice);
        } catch (const std::invalid_argument& e) {  // a period shorter than one lattice period
            place.fail("spacing", e.what());
        }
    return spheres;
}

std::vector<Sphere> place_list(SceneNode& node, SceneNode& place, const System& s, const SizeDistribution& sizes,
                               bool insert) {
    const int mono = s.domain.monolayer_normal;
    std::vector<Sphere> spheres;
    const json& list = place.raw("positions");
    if (!list.is_array() || list.empty()) place.fail("positions", "expected a non-empty array of [x, y, z]");
    if (!sizes.is_discrete() || sizes.discrete_classes().size() != 1)
        node.fail("size", "list placement needs a single grain size");
    for (std::size_t i = 0; i < list.size(); ++i) {
        // Read through a node whose key is the index, so errors name .../positions/<i>/<axis>.
        const std::string index = std::to_string(i);
        json out = json::object();
        json in = {{index, list[i]}};
        SceneNode item(in, out, place.path_of("positions"));
        const Vec3 centre = item.vector(index, units::length, std::nullopt);
        // On a closed axis a centre outside the box is a grain the first step would stop on
        // as "left the box"; say so here, with the position's path.
        if (mono >= 0 &&
            std::fabs(centre[mono] - 0.5 * (s.domain.lo[mono] + s.domain.hi[mono])) > 1e-9 * s.domain.length()[mono])
            item.fail(index, std::string("a monolayer's grains lie in its mid-plane: set the ") + char('x' + mono) +
                                 " coordinate to " + format_number(0.5 * (s.domain.lo[mono] + s.domain.hi[mono])) +
                                 " m");
        for (int k = 0; k < 3; ++k)
            if (!s.domain.periodic[k] && (centre[k] < s.domain.lo[k] || centre[k] > s.domain.hi[k]))
                item.fail(index, std::string("the centre lies outside the box along ") + char('x' + k) + " (" +
                                     format_number(centre[k]) + " m, box " + format_number(s.domain.lo[k]) + " to " +
                                     format_number(s.domain.hi[k]) + " m), which is not periodic");
        spheres.push_back({centre, 0.5 * sizes.max_diameter()});
    }
    place.finish();
    if (!insert) spheres.clear();
    return spheres;
}

// Heavier fine grains (mass scaling): every grain of a batch finer than `below_diameter` D
// carries (D / d)^2 times the mass and moment of inertia its material's density gives it, so its
// Stokes time m / (6 pi mu R) and its Rayleigh time R sqrt(rho / G) are those of a grain of
// diameter D. A run whose contacts had to be stiffened (to hold a magnetic pull) keeps its step
// that way, and fine grains stop setting a step far shorter than the rest need. Valid where the
// grains' inertia does not matter: a D grain's Stokes number in the flow far below 1 (the
// caller's to check; docs/scene.md).
double read_mass_scaling(SceneNode& node) {
    std::optional<SceneNode> ms = node.optional_object("mass_scaling");
    if (!ms) return 0;
    const double below = ms->quantity("below_diameter", units::length, std::nullopt, Bounds::positive());
    ms->finish();
    return below;
}

void read_grains(SceneNode node, Scene& scene, const std::vector<std::string>& names, Rng& rng, bool insert) {
    System& s = scene.system;
    const std::uint16_t mat = material_index(node, "material", names, names.front());
    SizeDistribution sizes = read_size_distribution(node.object("size"));
    SceneNode place = node.object("placement");
    const int mono = s.domain.monolayer_normal;
    const std::string method =
        place.choice("method", {"random", "lattice", "list", "monolayer"}, mono >= 0 ? "monolayer" : "random");
    if (mono >= 0 && (method == "random" || method == "lattice"))
        place.fail("method",
                   "the domain is a monolayer (/domain/monolayer): place grains with \"monolayer\" (a random packing "
                   "of discs in its plane) or \"list\"");
    if (mono < 0 && method == "monolayer")
        place.fail(
            "method",
            "\"monolayer\" placement needs a monolayer domain: set /domain/monolayer to the normal axis, e.g. \"y\"");
    // A grain must fit in the box on every axis; on a periodic axis it must also leave room for
    // the minimum image (checked with the neighbour cutoff in build_scene). A monolayer's
    // thickness may equal the largest diameter.
    for (int k = 0; k < 3; ++k)
        if (k == mono ? sizes.max_diameter() > s.domain.length()[k] : sizes.max_diameter() >= s.domain.length()[k])
            node.fail("size", "the largest grain (" + format_number(sizes.max_diameter()) +
                                  " m) does not fit in the box (" + format_number(s.domain.length()[k]) + " m along " +
                                  char('x' + k) + "); enlarge /domain");
    const Vec3 spin = node.vector("angular_velocity", units::frequency, Vec3{});
    const Vec3 v0 = node.vector("velocity", units::velocity, Vec3{});
    const double random_speed = node.quantity("random_velocity", units::velocity, 0.0, Bounds::non_negative());
    const double heavier_below = read_mass_scaling(node);

    std::vector<Sphere> spheres = method == "random"      ? place_random(node, place, scene, sizes, rng, insert)
                                  : method == "monolayer" ? place_monolayer(node, place, scene, sizes, rng, insert)
                                  : method == "lattice"   ? place_lattice(node, place, s, sizes, insert)
                                                          : place_list(node, place, s, sizes, insert);
    node.finish();

    Particles& p = s.particles;
    const Material& material = s.materials[mat];
    for (const Sphere& sp : spheres) {
        const std::size_t i = p.add(sp.centre, sp.radius, material.density, mat);
        p.id[i] = i;
        if (2 * sp.radius < heavier_below) {
            const double factor = heavier_below * heavier_below / (4 * sp.radius * sp.radius);
            p.mass[i] *= factor;
            p.inertia[i] *= factor;
        }
        set_magnetic_constants(material, p, i, rng);
        Vec3 v = v0;
        if (random_speed > 0)
            for (int k = 0; k < 3; ++k) v[k] += rng.uniform(-random_speed, random_speed);
        p.velocity[i] = v;
        p.angular_velocity[i] = spin;
    }
}

// Each batch is placed on its own: random packings do not see the grains of earlier batches, and
// list positions are taken as given. Overlaps above run.max_overlap_fraction would stop the run
// at step 0 with a blow-up blaming the time step; refuse them here instead, naming the batches.
void check_initial_overlaps(const System& s, const std::vector<std::size_t>& batch_end) {
    const std::size_t n = s.particles.size();
    auto batch_of = [&](std::size_t i) {
        return static_cast<std::size_t>(std::upper_bound(batch_end.begin(), batch_end.end(), i) - batch_end.begin());
    };
    // A wall through the grains placed (a plane inside the insertion region, a listed grain
    // against it) would throw them out at the first step, which read as a blow-up.
    for (std::size_t w = 0; w < s.walls.size(); ++w)
        for (std::size_t i = 0; i < n; ++i) {
            double overlap = 0;
            Vec3 normal;
            if (!s.walls[w].touch(s.particles.position[i], s.particles.radius[i], overlap, normal)) continue;
            if (!(overlap / s.particles.radius[i] > s.max_overlap_fraction)) continue;
            const std::size_t b = batch_of(i);
            throw SceneError("/walls/" + std::to_string(w),
                             "wall '" + s.walls[w].name + "' cuts through grain " +
                                 std::to_string(i - (b == 0 ? 0 : batch_end[b - 1])) + " of /grains/" +
                                 std::to_string(b) + " (overlap " + format_number(overlap / s.particles.radius[i]) +
                                 " of its radius): keep the grains' region or positions clear of the wall");
        }
    if (n < 2) return;
    Particles p = s.particles;  // the list build wraps positions; keep the scene's as they are
    NeighborList list(NeighborList::Settings{0.0, 1.0, false});  // cutoff R_i + R_j: the overlaps
    try {
        list.build(p, s.domain, 1);
    } catch (const std::runtime_error&) {
        return;  // a period too short for the grains: choose_timestep refuses it with its path
    }
    double worst = 0;
    std::size_t wi = 0, wj = 0;
    for (std::size_t i = 0; i < n; ++i) {
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::size_t j = list.partners[k];
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const double ratio = (p.radius[i] + p.radius[j] - norm(d)) / std::min(p.radius[i], p.radius[j]);
            if (ratio > worst) {
                worst = ratio;
                wi = i;
                wj = j;
            }
        }
    }
    if (!(worst > s.max_overlap_fraction)) return;
    std::size_t bi = batch_of(wi), bj = batch_of(wj);
    if (bi > bj) {
        std::swap(bi, bj);
        std::swap(wi, wj);
    }
    const std::string ratio = format_number(worst), limit = format_number(s.max_overlap_fraction);
    if (bi != bj)
        throw SceneError("/grains/" + std::to_string(bj) + "/placement",
                         "its grains overlap those of /grains/" + std::to_string(bi) + " by up to " + ratio +
                             " of the smaller radius (run.max_overlap_fraction is " + limit +
                             "): each batch is packed without regard to the others, so batches need "
                             "disjoint regions");
    const std::size_t first = bi == 0 ? 0 : batch_end[bi - 1];
    throw SceneError("/grains/" + std::to_string(bi) + "/placement",
                     "grains " + std::to_string(wi - first) + " and " + std::to_string(wj - first) +
                         " of this batch overlap by " + ratio +
                         " of the smaller radius, above run.max_overlap_fraction (" + limit +
                         "); move them apart, or for a random placement lower its overlap_tolerance");
}

// `formed`: the rafts formed by the stages before this one (a released raft keeps its name and may
// be formed again); a stage releases, then forms, then sets velocities (lib/run/runner.cpp).
Stage read_stage(SceneNode node, const Scene& scene, const std::vector<std::string>& wall_names,
                 std::set<std::string>& formed) {
    Stage st;
    st.name = node.text("name", "stage");
    if (node.has("steps") == node.has("duration")) node.fail("steps", "give exactly one of 'steps' or 'duration'");
    if (node.has("steps")) {
        st.steps = node.integer("steps", std::nullopt, 0);
    } else {
        st.duration = node.quantity("duration", units::time, std::nullopt, Bounds::non_negative());
    }
    if (node.has("release")) {
        const json& rel = node.raw("release");
        if (!rel.is_array()) node.fail("release", "expected an array of raft names");
        for (const auto& r : rel) {
            if (!r.is_string()) node.fail("release", "expected an array of raft names");
            st.release.push_back(r.get<std::string>());
            if (!formed.contains(st.release.back()))
                node.fail("release",
                          "no earlier stage forms a raft named '" + st.release.back() + "'; name one of form_rafts");
        }
    }
    std::set<std::string> formed_here;
    for (auto r : node.objects("form_rafts")) {
        Stage::RaftForm f;
        f.name = r.text("name", std::nullopt);
        if (f.name.empty()) r.fail("name", "give the raft a name (raft_velocities and release refer to it)");
        // Two entries of one name would make one raft moving at the second's velocity.
        if (!formed_here.insert(f.name).second)
            r.fail("name", "raft '" + f.name + "' is formed twice in this stage; give each raft its own name");
        f.region = read_region(r.object("region"), scene.system.domain);
        f.velocity = r.vector("velocity", units::velocity, Vec3{});
        r.finish();
        st.form_rafts.push_back(f);
    }
    formed.insert(formed_here.begin(), formed_here.end());
    for (auto r : node.objects("raft_velocities")) {
        st.raft_velocities.emplace_back(r.text("name", std::nullopt),
                                        r.vector("velocity", units::velocity, std::nullopt));
        if (!formed.contains(st.raft_velocities.back().first))
            r.fail("name", "no raft of this name is formed by this stage or an earlier one; name one of form_rafts");
        r.finish();
    }
    for (auto w : node.objects("wall_velocities")) {
        const std::string name =
            w.choice("name", wall_names.empty() ? std::vector<std::string>{"(no walls)"} : wall_names, std::nullopt);
        st.wall_velocities.emplace_back(name, w.vector("velocity", units::velocity, std::nullopt));
        w.finish();
    }
    if (node.has("remove_walls")) {
        const json& names = node.raw("remove_walls");
        if (!names.is_array()) node.fail("remove_walls", "must be a list of wall names");
        for (const json& n : names) {
            const auto it = n.is_string() ? std::find_if(scene.system.walls.begin(), scene.system.walls.end(),
                                                         [&](const Wall& w) { return w.name == n.get<std::string>(); })
                                          : scene.system.walls.end();
            if (it == scene.system.walls.end())
                node.fail("remove_walls", "names no wall of the scene (" + n.dump() + ")");
            if (it->kind != Wall::Kind::plane) node.fail("remove_walls", "only a plane wall can be taken away");
            st.remove_walls.push_back(it->name);
        }
    }
    if (node.has("flow")) st.flow = read_flow(node.object("flow"), scene.system.domain);
    node.finish();
    return st;
}

void read_output(SceneNode node, OutputPlan& out) { out = output_plan(read_output_block(node, ".")); }

}  // namespace

long Scene::total_steps() const {
    long n = 0;
    for (const auto& st : stages) n += st.steps;
    return n;
}

// The materials and their pairs' values; the names, in order, for the blocks that refer to them.
std::vector<std::string> read_materials(SceneNode& root, System& s) {
    std::vector<std::string> names;
    for (auto m : root.objects("materials", true)) {
        s.materials.push_back(read_material(m));
        if (std::find(names.begin(), names.end(), s.materials.back().name) != names.end())
            m.fail("name", "material names must be unique");
        names.push_back(s.materials.back().name);
    }
    if (names.empty()) root.fail("materials", "needs at least one material");
    s.pairs = PairTable(s.materials);
    for (auto pair : root.objects("material_pairs")) read_material_pair(pair, names, s.pairs);
    return names;
}

// The contact block, then the force terms whose blocks the scene has.
void add_force_terms(SceneNode& root, Scene& scene, const BuildOptions& options, const FidelityTier& tier) {
    System& s = scene.system;
    double pair_damping = 0;
    if (auto c = root.optional_object("contact"))
        read_contact(*c, s.physics, pair_damping);
    else {
        json in = json::object();
        read_contact(SceneNode(in, scene.resolved["contact"], "/contact"), s.physics, pair_damping);
    }

    // The force terms, in the order they add (per grain: drag, gravity; then magnetic, self-gravity,
    // pair damping).
    double fluid_density = 0;
    if (auto f = root.optional_object("fluid")) {
        const double viscosity = f->quantity("viscosity", units::viscosity, std::nullopt, Bounds::positive());
        fluid_density = f->quantity("density", units::density, 0.0, Bounds::non_negative());
        const int lookup_interval = static_cast<int>(f->integer("lookup_interval", 1, 1, 100));
        if (auto fl = f->optional_object("flow")) s.flow = read_flow(*fl, s.domain);
        f->finish();
        s.terms.add(std::make_unique<DragTerm>(viscosity, lookup_interval));
    }
    if (root.has("gravity"))
        s.terms.add(
            std::make_unique<GravityTerm>(root.vector("gravity", units::acceleration, std::nullopt), fluid_density));

    if (auto mag = root.optional_object("magnetic")) {
        read_magnetic(*mag, s, options, tier);
        s.terms.add(std::make_unique<MagneticTerm>());
    }
    if (auto sg = root.optional_object("self_gravity"))
        s.terms.add(std::make_unique<SelfGravityTerm>(read_self_gravity(*sg, s.domain)));
    if (pair_damping > 0) s.terms.add(std::make_unique<PairDampingTerm>(pair_damping));
}

std::vector<std::string> read_walls(SceneNode& root, System& s, const std::vector<std::string>& names) {
    std::vector<std::string> wall_names;
    for (auto w : root.objects("walls")) {
        s.walls.push_back(read_wall(w, names));
        // A stage's wall_velocities names the wall: two of one name would both move.
        if (std::find(wall_names.begin(), wall_names.end(), s.walls.back().name) != wall_names.end())
            w.fail("name", "wall names must be unique ('" + s.walls.back().name + "' is taken)");
        if (s.walls.back().name.empty()) w.fail("name", "give the wall a name (stages refer to it)");
        wall_names.push_back(s.walls.back().name);
    }
    return wall_names;
}

// Each /grains batch placed, then sorted in space; checked against each other and the field map.
void place_grains(SceneNode& root, Scene& scene, const std::vector<std::string>& names, const BuildOptions& options) {
    System& s = scene.system;
    Rng rng(scene.seed);
    std::size_t batches = 0;
    std::vector<std::size_t> batch_end;  // one past the last grain of each batch
    for (auto g : root.objects("grains", true)) {
        read_grains(g, scene, names, rng, options.insert_grains);
        double speed_over_radius = 0;
        for (std::size_t i = batch_end.empty() ? 0 : batch_end.back(); i < s.particles.size(); ++i)
            speed_over_radius = std::max(speed_over_radius, norm(s.particles.velocity[i]) / s.particles.radius[i]);
        scene.batch_speed_over_radius.push_back(speed_over_radius);
        batch_end.push_back(s.particles.size());
        ++batches;
    }
    if (batches == 0) root.fail("grains", "needs at least one batch of grains");
    if (options.insert_grains) {
        check_initial_overlaps(s, batch_end);
        check_field_map_coverage(s, scene.warnings);
    }
    sort_spatially(s.particles, s.domain);
}

// The stages, or the single stage of /run (steps or duration).
void read_stages(SceneNode& root, SceneNode& run, Scene& scene, const std::vector<std::string>& wall_names) {
    auto stage_nodes = root.objects("stages");
    if (stage_nodes.empty()) {
        Stage st;
        st.name = "run";
        st.path = "/run";
        if (run.has("steps") == run.has("duration"))
            run.fail("steps", "give exactly one of 'steps' or 'duration' (or a list of /stages)");
        if (run.has("steps"))
            st.steps = run.integer("steps", std::nullopt, 0);
        else
            st.duration = run.quantity("duration", units::time, std::nullopt, Bounds::non_negative());
        scene.stages.push_back(std::move(st));
    } else {
        std::set<std::string> formed;
        for (auto st : stage_nodes) {
            scene.stages.push_back(read_stage(st, scene, wall_names, formed));
            scene.stages.back().path = "/stages/" + std::to_string(scene.stages.size() - 1);
        }
    }
}

Scene build_scene(const json& input, const BuildOptions& options) {
    Scene scene;
    scene.resolved = json::object();
    SceneNode root(input, scene.resolved, "");
    root.text("mode", "run");
    root.text("description", "");
    scene.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0));
    System& s = scene.system;
    // Until the grains are known (choose_timestep), an automatic count runs on the machine's cores.
    scene.requested_threads = options.threads;
    s.threads = options.threads > 0 ? options.threads : machine_threads();
    s.domain = read_domain(root.object("domain"));

    const std::vector<std::string> names = read_materials(root, s);

    const FidelityTier* tier_ptr = nullptr;
    try {
        tier_ptr = &fidelity_tier(options.fidelity);
    } catch (const std::invalid_argument& e) {
        throw SceneError("--fidelity", e.what());
    }
    const FidelityTier& tier = *tier_ptr;
    scene.fidelity = describe(tier);
    add_force_terms(root, scene, options, tier);

    const std::vector<std::string> wall_names = read_walls(root, s, names);

    SceneNode run = root.object("run");
    scene.characteristic_speed = run.quantity("characteristic_speed", units::velocity, 1.0, Bounds::positive());
    scene.timestep_safety =
        run.number("timestep_safety", tier.timestep_safety, Bounds::open_closed(0.0, kMaxStepFraction));
    if (run.has("timestep") && run.raw("timestep").is_string() && run.raw("timestep").get<std::string>() == "auto") {
        scene.requested_timestep = 0;
    } else if (run.has("timestep")) {
        // A step of 0 meant "automatic" without a word; the automatic step is asked for by name.
        scene.requested_timestep = run.quantity("timestep", units::time, std::nullopt, Bounds::positive());
    } else {
        scene.requested_timestep = 0;
        scene.resolved["run"]["timestep"] = "auto";
    }
    // choose_timestep() records the step it chose as run.timestep_used in the resolved scene, and
    // a checkpoint (or a report's "inputs" fed back as a scene) carries that copy. It is an output,
    // recomputed from the grains by choose_timestep(): accept it here so such a scene reads back,
    // but ignore its value.
    run.has("timestep_used");
    // The count an automatic run chose (choose_timestep) rides along the same way; a resumed run
    // without --threads takes it again, so it goes on bit for bit even when its grains have
    // drained below the count's threshold since.
    const long long threads_used = run.integer("threads_used", 0, 0, 1024);
    if (options.threads == kAutoThreads && !options.insert_grains && threads_used > 0)
        scene.requested_threads = static_cast<int>(threads_used);
    s.max_overlap_fraction = run.number("max_overlap_fraction", 0.1, Bounds::open(0.0, 1.0));
    // Verlet skin, as a fraction of the mean grain diameter.
    const double skin_fraction = run.number("skin", kDefaultSkinFraction, Bounds::open_closed(0.0, 2.0));

    place_grains(root, scene, names, options);
    // The skin length needs the grain sizes, known once grains exist (choose_timestep).
    scene.skin_fraction = skin_fraction;

    read_stages(root, run, scene, wall_names);
    run.finish();
    if (auto out = root.optional_object("output"))
        read_output(*out, scene.output);
    else {
        json in = json::object();
        read_output(SceneNode(in, scene.resolved["output"], "/output"), scene.output);
    }
    root.finish();
    return scene;
}

void choose_timestep(Scene& scene) {
    System& s = scene.system;
    Particles& p = s.particles;
    if (p.size() == 0) throw SceneError("/grains", "no grains were placed; check the placement regions and sizes");
    s.threads = threads_for(p.size(), scene.requested_threads);
    double r_sum = 0, r_max = 0;
    for (double r : p.radius) {
        r_sum += r;
        r_max = std::max(r_max, r);
    }
    const double skin = scene.skin_fraction * 2.0 * r_sum / p.size();
    s.contacts = NeighborList(NeighborList::Settings{skin, 1.0, true});
    for (int k = 0; k < 3; ++k)
        if (s.domain.periodic[k] && s.contacts.pair_cutoff(r_max, r_max) > 0.5 * s.domain.length()[k])
            throw SceneError("/domain/hi",
                             "the box is too short along the periodic axis " + std::string(1, char('x' + k)) +
                                 ": it must be more than twice the neighbour cutoff of the largest grains (" +
                                 format_number(2 * s.contacts.pair_cutoff(r_max, r_max)) + " m)");

    if (s.magnetic.enabled) {
        const MagneticSettings& ms = s.magnetic.settings;
        s.magnetic.pairs =
            NeighborList(NeighborList::Settings{skin, ms.cutoff_scale, false, ms.cutoff_extra, ms.cutoff_max_scale});
        if (s.magnetic.pairs.interaction_range(r_max, r_max) < 2 * r_max)
            throw SceneError("/magnetic/cutoff", "the magnetic range (" +
                                                     format_number(s.magnetic.pairs.interaction_range(r_max, r_max)) +
                                                     " m for the largest grains) is shorter than contact; it must "
                                                     "reach at least the touching neighbours");
        for (int k = 0; k < 3; ++k)
            if (s.domain.periodic[k] && s.magnetic.pairs.pair_cutoff(r_max, r_max) > 0.5 * s.domain.length()[k])
                throw SceneError(
                    "/magnetic/cutoff",
                    "the magnetic cutoff of the largest grains drawn (diameter " + format_number(2 * r_max, 3) +
                        " m) is " + format_number(s.magnetic.pairs.pair_cutoff(r_max, r_max), 3) +
                        " m with the skin, more than half the periodic box along " + std::string(1, char('x' + k)) +
                        " (" + format_number(0.5 * s.domain.length()[k], 3) +
                        " m): a pair would meet through more than one image; shorten the cutoff or enlarge the box");
        s.magnetic.any_permanent = false;
        for (const Vec3& m : p.permanent_moment) s.magnetic.any_permanent |= norm2(m) > 0;
        if (ms.close_pairs.enabled) build_close_pair_table(s, r_max);
        initialise_moments(s.magnetic, s.particles, s.time);
    }

    scene.limits = timestep_limits(s, scene.characteristic_speed);
    if (scene.requested_timestep > 0) {
        if (scene.requested_timestep > scene.limits.stable_limit)
            throw SceneError("/run/timestep",
                             "the requested step " + format_number(scene.requested_timestep) +
                                 " s is above the stable limit " + format_number(scene.limits.stable_limit) + " s (" +
                                 format_number(kMaxStepFraction) + " of the " + scene.limits.limiting + ", " +
                                 format_number(scene.limits.critical) + " s); use a shorter step or \"auto\"");
        s.dt = scene.requested_timestep;
    } else {
        // Nothing that moves on its own time scale (no contact law, drag, damping or self-gravity).
        if (!std::isfinite(scene.limits.critical))
            throw SceneError("/run/timestep",
                             "nothing in this scene limits the time step (no contact model, drag, pair damping or "
                             "self-gravity): give an explicit step, e.g. \"1 us\"");
        s.dt = scene.timestep_safety * scene.limits.critical;
    }
    if (const std::string w = drag_limited_step_warning(scene.limits); !w.empty()) scene.warnings.push_back(w);
    check_pair_memory(s);
    check_plausible_motion(scene);
    scene.resolved["run"]["timestep_used"] = s.dt;
    scene.resolved["run"]["threads_used"] = s.threads;
    // A duration over the step: far more steps than any run could take (kMostSteps) is refused.
    for (Stage& st : scene.stages) {
        if (st.steps >= 0) continue;
        const double steps = std::ceil(st.duration / s.dt - 1e-9);
        if (!(steps <= kMostSteps))
            throw SceneError(st.path + "/duration",
                             "needs " + format_number(steps) + " steps of " + format_number(s.dt) + " s, more than " +
                                 format_number(kMostSteps) +
                                 ": check the duration's units, or the materials' that set the step (" +
                                 scene.limits.limiting + ")");
        st.steps = std::max(1L, static_cast<long>(steps));
    }
}

}  // namespace mrjam
