// `mrjam-bench magnetic`: the cost of a chain-forming magnetorheological scene (the issue's
// scene: 1,905 monodisperse 6.7 um iron grains at volume fraction 0.3 in a 100 um box, 600 mT
// along z, lagged mutual dipoles, magnetic range 8 um beyond contact). Chains form first
// (untimed), then a fixed number of steps is timed; prints core-microseconds per grain-step.
//
// `mrjam-bench magnetic-accuracy`: the speed/accuracy trade of the mutual-dipole policy and the
// magnetic cutoff. Chains form once in a polydisperse scene; from that saved state each setting
// is (a) evaluated once at the same configuration and (b) stepped on for K steps, and its mean
// magnetic force per grain and magnetic virial stress are compared against the converged policy
// at the longest cutoff. docs/magnetic_forces.md shows and explains the tables.
//
// The magnetic observers here (per-grain pair-force sum, virial stress) are computed from the
// public state (positions, dipole moments, the magnetic pair list) with eq. 4.8, rhat from j to
// i for the force on i, independently of lib/magnetic; the same-configuration pass checks them
// against the forces add_magnetic_forces() applies.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_commands.hpp"
#include "cli_common.hpp"
#include "geometry/size_distribution.hpp"
#include "integrator.hpp"
#include "magnetic/magnetic_model.hpp"
#include "observers.hpp"
#include "run/runner.hpp"
#include "scene/scene.hpp"
#include "scene/scene_parts.hpp"
#include "timestep.hpp"

namespace mrjam::cli {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// ---- scenes -----------------------------------------------------------------------------------

constexpr double kDiameter = 6.7e-6;  // m, the source's monodisperse grains
constexpr double kVolumeFraction = 0.3;

// Chapter 2 iron in silicone oil (examples/chains_600mT.json). The relative permeability (1000)
// and saturation magnetisation (1.7e6 A/m) are the scene defaults, written out for the record.
nlohmann::json iron_material() {
    return {{"name", "iron"},
            {"density", "7800 kg/m3"},
            {"youngs_modulus", "1 GPa"},
            {"poisson_ratio", 0.278},
            {"restitution", 0.1},
            {"friction", 0.1},
            {"rolling_friction", 0.1},
            {"rolling_damping", 0.1},
            {"cohesion_energy_density", "60 kJ/m3"},
            {"relative_permeability", 1000},
            {"saturation_magnetisation", "1.7e6 A/m"}};
}

nlohmann::json mr_scene(const std::string& description, double lx, double ly, double lz, const nlohmann::json& size,
                        const nlohmann::json& cutoff) {
    return {
        {"description", description},
        {"seed", 11},
        {"domain", {{"lo", {0, 0, 0}}, {"hi", {lx, ly, lz}}, {"periodic", "xy"}}},
        {"materials", {iron_material()}},
        {"contact", {{"model", "hertz_mindlin"}, {"rolling", "epsd"}, {"cohesion", "sjkr"}}},
        {"fluid", {{"viscosity", "10 mPa s"}}},
        {"magnetic",
         {{"field", {{"type", "uniform"}, {"flux_density", {0, 0, "600 mT"}}}},
          {"mutual", "lagged"},
          {"cutoff", cutoff}}},
        {"walls",
         {{{"name", "bottom"}, {"type", "plane"}, {"point", {0, 0, 0}}, {"normal", {0, 0, 1}}},
          {{"name", "top"}, {"type", "plane"}, {"point", {0, 0, lz}}, {"normal", {0, 0, -1}}}}},
        {"grains",
         {{{"material", "iron"},
           {"size", size},
           {"placement", {{"method", "random"}, {"volume_fraction", kVolumeFraction}}}}}},
        {"run", {{"timestep", "0.2 ns"}, {"steps", 1}}},
    };
}

// The scene (chapter 2's monodisperse 6.7 um runs, 8 um magnetic neighbour length).
nlohmann::json magnetic_bench_scene() {
    const double side = 100e-6;
    return mr_scene(
        "magnetic benchmark: 6.7 um iron grains, phi 0.3, 600 mT along z, lagged mutual dipoles, "
        "magnetic range 8 um beyond contact",
        side, side, side, {{"distribution", "single"}, {"diameter", "6.7 um"}}, {{"beyond_contact", "8 um"}});
}

// ---- observers (read-only) --------------------------------------------------------------------

// Mean |cos| of the grain-grain contact normals to z; optionally the number of such contacts
// and the fraction within 30 degrees of z.
double contact_alignment(const System& s, std::size_t* contacts_out = nullptr, double* aligned_out = nullptr) {
    const Particles& p = s.particles;
    const NeighborList& list = s.contacts;
    double sum = 0;
    std::size_t contacts = 0, aligned = 0;
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const std::uint32_t j = list.partners[k];
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[k]);
            const double r2 = norm2(d);
            if (r2 >= list.range_sq[k]) continue;
            const double c = std::fabs(d.z) / std::sqrt(r2);
            sum += c;
            aligned += c > 0.8660254037844386;
            ++contacts;
        }
    if (contacts_out) *contacts_out = contacts;
    if (aligned_out) *aligned_out = contacts ? static_cast<double>(aligned) / static_cast<double>(contacts) : 0.0;
    return contacts ? sum / static_cast<double>(contacts) : 0.0;
}

// Magnetic pairs closer than their interaction range (the pairs that contribute).
std::size_t magnetic_pairs_in_range(const Particles& p, const NeighborList& list) {
    std::size_t count = 0;
    for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i)
        for (std::uint32_t k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
            const Vec3 d = p.position[i] - p.position[list.partners[k]] + list.image_shift(list.image[k]);
            count += norm2(d) < list.range_sq[k];
        }
    return count;
}

struct MagneticObservation {
    std::vector<Vec3> force;                          // sum of the dipole-dipole pair forces on each grain, N
    double mean_force = 0;                            // mean over grains of |force|, N
    double sigma_xx = 0, sigma_yy = 0, sigma_zz = 0;  // (1/V) sum over pairs of r_k F_k, Pa
    std::size_t pairs_in_range = 0;
};

// Eq. 4.8 for every listed pair within range, with the moments m: F on i, rhat from j to i,
// F_i = 3 mu0 / (4 pi r^4) [m_j (m_i.rhat) + m_i (m_j.rhat) + rhat (m_i.m_j) - 5 rhat (m_i.rhat)(m_j.rhat)].
// r = x_i - x_j, so (1/V) sum r F is the virial of the pair forces: negative along z for the
// attraction of head-to-tail dipoles (a tensile contribution in the convention where
// compression is positive, i.e. sigma_cauchy = -(1/V) sum r F).
MagneticObservation observe_magnetic(const Particles& p, const NeighborList& list, const std::vector<Vec3>& m,
                                     double volume) {
    MagneticObservation out;
    const std::size_t n = p.size();
    out.force.assign(n, Vec3{});
    constexpr double k = 3.0 * kMu0 / (4.0 * M_PI);
    double sxx = 0, syy = 0, szz = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t q = list.offsets[i]; q < list.offsets[i + 1]; ++q) {
            const std::uint32_t j = list.partners[q];
            const Vec3 d = p.position[i] - p.position[j] + list.image_shift(list.image[q]);
            const double r2 = norm2(d);
            if (r2 >= list.range_sq[q]) continue;
            const double r = std::sqrt(r2);
            const Vec3 e = d / r;
            const Vec3& mi = m[i];
            const Vec3& mj = m[j];
            const double mie = dot(mi, e), mje = dot(mj, e);
            const Vec3 f = (mj * mie + mi * mje + e * dot(mi, mj) - e * (5.0 * mie * mje)) * (k / (r2 * r2));
            out.force[i] += f;
            out.force[j] -= f;
            sxx += d.x * f.x;
            syy += d.y * f.y;
            szz += d.z * f.z;
            ++out.pairs_in_range;
        }
    double sum = 0;
    for (const Vec3& f : out.force) sum += norm(f);
    out.mean_force = n ? sum / static_cast<double>(n) : 0.0;
    out.sigma_xx = sxx / volume;
    out.sigma_yy = syy / volume;
    out.sigma_zz = szz / volume;
    return out;
}

// Pairs closer than scale (R_i + R_j), by brute force with the minimum image on periodic axes:
// checks the magnetic pair list the comparisons rest on.
std::size_t brute_force_pairs_in_range(const Particles& p, const Domain& dom, double scale) {
    const Vec3 len = dom.length();
    std::size_t count = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            Vec3 d = p.position[i] - p.position[j];
            for (int a = 0; a < 3; ++a)
                if (dom.periodic[a]) d[a] -= len[a] * std::nearbyint(d[a] / len[a]);
            const double range = scale * (p.radius[i] + p.radius[j]);
            count += norm2(d) < range * range;
        }
    return count;
}

double domain_volume(const Domain& d) {
    const Vec3 l = d.length();
    return l.x * l.y * l.z;
}

// Steps with a progress line on stderr every ~5 s (untimed phases). `extra` adds to the line.
void run_with_progress(System& s, long steps, const char* label,
                       const std::function<std::string(const System&)>& extra) {
    const auto t0 = Clock::now();
    auto last = t0;
    long done = 0, chunk = 50;
    while (done < steps) {
        const long c = std::min(chunk, steps - done);
        const auto a = Clock::now();
        advance_steps(s, c);
        done += c;
        const double took = seconds_since(a);
        if (took < 0.2)
            chunk = std::min<long>(chunk * 2, 1000000);
        else if (took > 1.0 && chunk > 1)
            chunk /= 2;
        if (seconds_since(last) > 5.0 && done < steps) {
            const double el = seconds_since(t0);
            std::fprintf(stderr, "  %s: step %ld of %ld (%.0f%%), %.0f s elapsed, ~%.0f s left%s\n", label, done, steps,
                         100.0 * done / steps, el, el * (steps - done) / done, extra ? extra(s).c_str() : "");
            last = Clock::now();
        }
    }
}

std::string alignment_note(const System& s) {
    char buf[160];
    double aligned = 0;
    const double c = contact_alignment(s, nullptr, &aligned);
    std::snprintf(buf, sizeof buf,
                  ", mean |cos| of contact normals to z %.3f (%.0f%% within 30 deg), %.2f contacts per grain", c,
                  100 * aligned, mean_coordination(s));
    return buf;
}

// ---- bench magnetic ----------------------------------------------------------------------------

struct MagneticBenchArgs {
    long steps = 2000;
    long settle_steps = 30000;
    int threads = 1;
    std::string json_out;
};

void run_magnetic_bench(const MagneticBenchArgs& args) {
    BuildOptions build;
    build.threads = args.threads;
    const auto setup0 = Clock::now();
    Scene scene = build_scene(magnetic_bench_scene(), build);
    choose_timestep(scene);
    System& s = scene.system;
    prepare(s);
    const double setup = seconds_since(setup0);
    const std::size_t n = s.particles.size();
    std::printf(
        "bench magnetic: %zu grains of %.1f um, volume fraction %.2f, 100 um box periodic in x and y, "
        "600 mT along z, lagged mutual dipoles, magnetic range 8 um beyond contact, dt %.3g s, %d thread(s)\n",
        n, kDiameter * 1e6, kVolumeFraction, s.dt, args.threads);
    std::fflush(stdout);

    const auto settle0 = Clock::now();
    run_with_progress(s, args.settle_steps, "settling (chains forming)", alignment_note);
    const double settle = seconds_since(settle0);
    double aligned_settled = 0;
    const double cos_settled = contact_alignment(s, nullptr, &aligned_settled);
    std::printf(
        "settled %ld steps (%.3g s simulated) in %.1f s: mean |cos| of contact normals to z %.3f (%.0f%% within "
        "30 deg), %.2f contacts per grain\n",
        args.settle_steps, s.time, settle, cos_settled, 100 * aligned_settled, mean_coordination(s));

    const long builds0 = s.contacts.builds();
    const long field0 = s.magnetic.field_passes, force0 = s.magnetic.force_passes;
    const auto t0 = Clock::now();
    advance_steps(s, args.steps);
    const double wall = seconds_since(t0);
    const double grain_steps = static_cast<double>(n) * static_cast<double>(args.steps);
    const double core_us = wall * args.threads * 1e6 / grain_steps;

    // The magnetic part alone: the same pass the step makes (lagged: one pair pass with forces,
    // one moment update), repeated on a copy of the grains at the final state.
    double magnetic_core_us = 0;
    {
        Particles q = s.particles;
        MagneticModel model = s.magnetic;
        const int reps = 200;
        add_magnetic_forces(model, q, s.time, args.threads);  // warm the buffers
        const auto m0 = Clock::now();
        for (int r = 0; r < reps; ++r) add_magnetic_forces(model, q, s.time, args.threads);
        magnetic_core_us = seconds_since(m0) * args.threads * 1e6 / (static_cast<double>(n) * reps);
    }

    const double listed = 2.0 * static_cast<double>(s.magnetic.pairs.pair_count()) / n;
    const double within = 2.0 * static_cast<double>(magnetic_pairs_in_range(s.particles, s.magnetic.pairs)) / n;
    const double contacts = mean_coordination(s);
    const double cos_final = contact_alignment(s);
    const double range = s.magnetic.pairs.interaction_range(0.5 * kDiameter, 0.5 * kDiameter);
    double mean_moment = 0;
    for (const Vec3& m : s.particles.dipole_moment) mean_moment += norm(m);
    mean_moment /= n;
    const double sat = s.particles.saturation_moment[0];

    std::printf(
        "timed %ld steps: %.3f core-us per grain-step, %.3g grain-steps/s (%.1f s wall); magnetic part alone "
        "%.3f core-us per grain-step\n",
        args.steps, core_us, grain_steps / wall, wall, magnetic_core_us);
    std::printf(
        "magnetic range %.2f um: %.2f listed magnetic neighbours per grain, %.2f within the range; %.2f "
        "contacts per grain (walls counted once); mean |cos| of contact normals to z %.3f; mean |m| %.3f of "
        "saturation; %ld list builds in the timed steps\n",
        range * 1e6, listed, within, contacts, cos_final, mean_moment / sat, s.contacts.builds() - builds0);
    std::printf(
        "target <= 0.3 core-us per grain-step; the source's LIGGGHTS runs: 3.90 ms per step for ~30,000 "
        "monodisperse 6.7 um grains on 18 cores = 2.3 core-us, 4.64 ms for ~12,000 polydisperse grains on 18 "
        "cores = 7.0 core-us (section 2.4.3)\n");

    if (!args.json_out.empty()) {
        const nlohmann::json out = {
            {"benchmark", "magnetic"},
            {"grains", n},
            {"diameter_m", kDiameter},
            {"volume_fraction", kVolumeFraction},
            {"threads", args.threads},
            {"timestep_s", s.dt},
            {"settle_steps", args.settle_steps},
            {"settle_wall_s", settle},
            {"steps", args.steps},
            {"setup_s", setup},
            {"wall_s", wall},
            {"grain_steps_per_s", grain_steps / wall},
            {"core_us_per_particle_step", core_us},
            {"magnetic_only_core_us_per_particle_step", magnetic_core_us},
            {"magnetic_range_m", range},
            {"magnetic_listed_neighbours_per_grain", listed},
            {"magnetic_neighbours_within_range_per_grain", within},
            {"contacts_per_grain", contacts},
            {"mean_abs_cos_contact_normal_z_after_settle", cos_settled},
            {"fraction_contacts_within_30deg_of_z_after_settle", aligned_settled},
            {"mean_abs_cos_contact_normal_z_final", cos_final},
            {"mean_moment_over_saturation", mean_moment / sat},
            {"mutual_dipole_field_passes_per_step",
             s.magnetic.force_passes > force0
                 ? static_cast<double>(s.magnetic.field_passes - field0) / (s.magnetic.force_passes - force0)
                 : 0.0},
            {"neighbour_builds_timed", s.contacts.builds() - builds0},
            {"simulated_time_s", s.time},
            {"scene", scene.resolved},
        };
        write_json_file(args.json_out, out);
    }
}

// ---- bench magnetic-accuracy -------------------------------------------------------------------

struct AccuracyArgs {
    std::string geometry = "slab";
    long form_steps = 15000;
    long early_step = 1500;  // where the while-forming policy comparison starts
    long steps = 300;        // K: steps each setting runs from the saved state
    long replay_steps = 20;  // trajectory steps replayed for the same-configuration moments
    int threads = 1;
    long grains = 0;  // 0: 2,000 (slab) or the smallest cube the cutoff admits (bulk)
    std::string json_out;
};

struct Setting {
    std::string label;
    MutualPolicy policy;
    int iterations = 1;
    double tolerance = 1e-6;
    double diameters = 5;
};

Setting make_setting(MutualPolicy p, int iterations, double tolerance, double diameters, const std::string& name) {
    char label[64];
    std::snprintf(label, sizeof label, "%s, %g d", name.c_str(), diameters);
    return {label, p, iterations, tolerance, diameters};
}

void apply_setting(MagneticModel& model, const Setting& st, double skin) {
    MagneticSettings& ms = model.settings;
    ms.policy = st.policy;
    ms.iterations = st.iterations;
    ms.tolerance = st.tolerance;
    ms.max_iterations = 500;
    ms.cutoff_scale = st.diameters;
    ms.cutoff_extra = 0;
    model.pairs = NeighborList(NeighborList::Settings{skin, st.diameters, false, 0.0});
    model.field_passes = 0;
    model.force_passes = 0;
}

struct Measure {
    MagneticObservation obs;
    double core_us = std::numeric_limits<double>::quiet_NaN();
    double field_passes_per_step = 0;
    double neighbours_in_range = 0;  // per grain
    double engine_mismatch = 0;      // max |F_engine - F_observer| / mean |F| (same-configuration pass)
};

// A state to compare the settings at, with the formation run's last M positions before it.
struct SavedState {
    System system;
    std::vector<std::vector<Vec3>> positions;  // x_{N-M} .. x_{N-1}
    std::vector<double> times;
    std::vector<Vec3> moments_at_start;  // the run's moments before the first replayed step
};

// Advances `s` to `target` steps (progress on stderr), recording the last M steps' positions.
SavedState advance_and_save(System& s, long target, long M, const char* label) {
    const long first = std::max(s.step, target - M);
    run_with_progress(s, first - s.step, label, alignment_note);
    SavedState out;
    out.moments_at_start = s.particles.dipole_moment;
    while (s.step < target) {
        out.positions.push_back(s.particles.position);
        out.times.push_back(s.time);
        advance_steps(s, 1);
    }
    out.system = s;
    return out;
}

// Same configuration: the setting's moments are built along the recorded trajectory of the
// formation run (the last M steps; each step calls add_magnetic_forces at that step's positions,
// so lagged and k-iteration moments carry the history they would have had), then the forces are
// evaluated once at the saved state's positions. Only the moments and the cutoff differ.
Measure same_configuration(const SavedState& state, const Setting& st, double skin, int threads) {
    const System& saved = state.system;
    const Domain& dom = saved.domain;
    const Vec3 len = dom.length();
    const std::size_t n = saved.particles.size();
    // The recorded positions, made continuous with the final ones across periodic wraps; one
    // list built with a skin covering the largest displacement then serves every replayed step.
    const std::vector<Vec3>& last = saved.particles.position;
    std::vector<std::vector<Vec3>> path = state.positions;
    double max_disp = 0;
    for (auto& xs : path)
        for (std::size_t i = 0; i < n; ++i) {
            Vec3 d = xs[i] - last[i];
            for (int a = 0; a < 3; ++a)
                if (dom.periodic[a]) d[a] -= len[a] * std::nearbyint(d[a] / len[a]);
            xs[i] = last[i] + d;
            max_disp = std::max(max_disp, norm(d));
        }
    Particles q = saved.particles;
    MagneticModel model = saved.magnetic;
    apply_setting(model, st, skin);
    model.pairs = NeighborList(NeighborList::Settings{2.02 * max_disp + 1e-3 * skin, st.diameters, false, 0.0});
    model.pairs.build(q, dom, threads);  // wraps q's positions; keep each grain's offset
    std::vector<Vec3> offset(n);
    for (std::size_t i = 0; i < n; ++i) offset[i] = q.position[i] - last[i];
    const std::vector<Vec3> final_position = q.position;
    q.dipole_moment = state.moments_at_start;
    for (std::size_t k = 0; k < path.size(); ++k) {
        for (std::size_t i = 0; i < n; ++i) q.position[i] = path[k][i] + offset[i];
        std::fill(q.force.begin(), q.force.end(), Vec3{});
        std::fill(q.torque.begin(), q.torque.end(), Vec3{});
        add_magnetic_forces(model, q, state.times[k], threads);
    }
    q.position = final_position;
    std::fill(q.force.begin(), q.force.end(), Vec3{});
    std::fill(q.torque.begin(), q.torque.end(), Vec3{});
    const std::vector<Vec3> before = q.dipole_moment;
    add_magnetic_forces(model, q, saved.time, threads);
    // Lagged forces use the moments held before the call (it updates them afterwards).
    const std::vector<Vec3>& used = st.policy == MutualPolicy::lagged ? before : q.dipole_moment;
    Measure m;
    m.obs = observe_magnetic(q, model.pairs, used, domain_volume(dom));
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, norm(q.force[i] - m.obs.force[i]));
    m.engine_mismatch = m.obs.mean_force > 0 ? worst / m.obs.mean_force : 0.0;
    m.field_passes_per_step = mean_iterations(model);
    m.neighbours_in_range = 2.0 * static_cast<double>(m.obs.pairs_in_range) / n;
    return m;
}

// Stepped: a copy of the saved state switched to the setting runs K steps (timed, all forces);
// the forces of the last step are measured.
Measure stepped(const System& saved, const Setting& st, double skin, long steps, int threads) {
    System s = saved;
    s.threads = threads;
    apply_setting(s.magnetic, st, skin);
    prepare(s);
    s.magnetic.field_passes = s.magnetic.force_passes = 0;
    const auto t0 = Clock::now();
    advance_steps(s, steps - 1);
    const std::vector<Vec3> before = s.particles.dipole_moment;  // the lagged moments of the last step
    advance_steps(s, 1);
    const double wall = seconds_since(t0);
    const std::vector<Vec3>& used = st.policy == MutualPolicy::lagged ? before : s.particles.dipole_moment;
    Measure m;
    m.obs = observe_magnetic(s.particles, s.magnetic.pairs, used, domain_volume(s.domain));
    m.core_us = wall * threads * 1e6 / (static_cast<double>(s.particles.size()) * steps);
    m.field_passes_per_step = mean_iterations(s.magnetic);
    m.neighbours_in_range = 2.0 * static_cast<double>(m.obs.pairs_in_range) / s.particles.size();
    return m;
}

double percent(double x, double ref) { return 100.0 * (x - ref) / ref; }

nlohmann::json measure_json(const Measure& m, const Measure& ref) {
    nlohmann::json j = {{"mean_force_N", m.obs.mean_force},
                        {"sigma_xx_Pa", m.obs.sigma_xx},
                        {"sigma_yy_Pa", m.obs.sigma_yy},
                        {"sigma_zz_Pa", m.obs.sigma_zz},
                        {"mean_force_error_percent", percent(m.obs.mean_force, ref.obs.mean_force)},
                        {"sigma_zz_error_percent", percent(m.obs.sigma_zz, ref.obs.sigma_zz)},
                        {"sigma_xx_error_percent", percent(m.obs.sigma_xx, ref.obs.sigma_xx)},
                        {"field_passes_per_step", m.field_passes_per_step},
                        {"magnetic_neighbours_within_range_per_grain", m.neighbours_in_range}};
    if (std::isfinite(m.core_us)) j["core_us_per_particle_step"] = m.core_us;
    return j;
}

struct Comparison {
    std::vector<Setting> settings;
    std::vector<Measure> same, step;  // step empty when not stepped
    std::size_t reference = 0, cost_unit = 0;
    double worst_mismatch = 0;
};

Comparison compare(const SavedState& state, const std::vector<Setting>& settings, std::size_t reference,
                   std::size_t cost_unit, double skin, const AccuracyArgs& args, bool with_steps, const char* label) {
    Comparison c;
    c.settings = settings;
    c.reference = reference;
    c.cost_unit = cost_unit;
    const auto t0 = Clock::now();
    for (const Setting& st : settings) {
        c.same.push_back(same_configuration(state, st, skin, args.threads));
        c.worst_mismatch = std::max(c.worst_mismatch, c.same.back().engine_mismatch);
        std::fprintf(stderr, "  %s, same configuration: %s done (%.0f s)\n", label, st.label.c_str(),
                     seconds_since(t0));
    }
    if (with_steps)
        for (const Setting& st : settings) {
            c.step.push_back(stepped(state.system, st, skin, args.steps, args.threads));
            std::fprintf(stderr, "  %s, %ld steps: %s done (%.0f s)\n", label, args.steps, st.label.c_str(),
                         seconds_since(t0));
        }
    return c;
}

// Stress errors: per cent of the same component of the reference, or (`scaled`) of the
// reference's larger diagonal magnitude max(|sigma_xx|, |sigma_zz|), for states where a
// component is near zero (while chains form, attraction along z and the slab's far field nearly
// cancel in sigma_zz).
nlohmann::json print_comparison(const Comparison& c, const AccuracyArgs& args, bool scaled = false) {
    const Measure& rs = c.same[c.reference];
    const auto stress_err = [&](double x, double ref, const Measure& r) {
        if (!scaled) return percent(x, ref);
        return 100.0 * (x - ref) / std::max(std::fabs(r.obs.sigma_xx), std::fabs(r.obs.sigma_zz));
    };
    const bool stepped_too = !c.step.empty();
    std::printf(
        "Reference: %s (tolerance %g). Same configuration: mean |F_mag| %.4g N, sigma_zz %.4g Pa, "
        "sigma_xx %.4g Pa",
        c.settings[c.reference].label.c_str(), c.settings[c.reference].tolerance, rs.obs.mean_force, rs.obs.sigma_zz,
        rs.obs.sigma_xx);
    if (stepped_too) {
        const Measure& rk = c.step[c.reference];
        std::printf("; after %ld steps: %.4g N, %.4g Pa, %.4g Pa", args.steps, rk.obs.mean_force, rk.obs.sigma_zz,
                    rk.obs.sigma_xx);
    }
    std::printf(".\n\n");
    if (stepped_too) {
        std::printf(
            "| setting | neighbours in range | field passes per step | same config: mean abs F err (%%) | "
            "sigma_zz err (%%) | sigma_xx err (%%) | after %ld steps: mean abs F err (%%) | sigma_zz err (%%) | "
            "core-us per grain-step | cost vs %s |\n",
            args.steps, c.settings[c.cost_unit].label.c_str());
        std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    } else {
        std::printf(
            "| setting | neighbours in range | field passes per step | same config: mean abs F err (%%) | "
            "sigma_zz err (%%) | sigma_xx err (%%) |\n");
        std::printf("|---|---:|---:|---:|---:|---:|\n");
    }
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t k = 0; k < c.settings.size(); ++k) {
        const Measure& a = c.same[k];
        std::printf("| %s%s | %.1f | %.2f | %+.2f | %+.2f | %+.2f |", c.settings[k].label.c_str(),
                    k == c.reference ? " (reference)" : "", a.neighbours_in_range,
                    stepped_too ? c.step[k].field_passes_per_step : a.field_passes_per_step,
                    percent(a.obs.mean_force, rs.obs.mean_force), stress_err(a.obs.sigma_zz, rs.obs.sigma_zz, rs),
                    stress_err(a.obs.sigma_xx, rs.obs.sigma_xx, rs));
        nlohmann::json row = {{"setting", c.settings[k].label},
                              {"policy", policy_name(c.settings[k].policy)},
                              {"iterations", c.settings[k].iterations},
                              {"tolerance", c.settings[k].tolerance},
                              {"cutoff_diameters", c.settings[k].diameters},
                              {"same_configuration", measure_json(a, rs)}};
        if (stepped_too) {
            const Measure& b = c.step[k];
            const Measure& rk = c.step[c.reference];
            std::printf(" %+.2f | %+.2f | %.3f | %.2f |", percent(b.obs.mean_force, rk.obs.mean_force),
                        stress_err(b.obs.sigma_zz, rk.obs.sigma_zz, rk), b.core_us,
                        b.core_us / c.step[c.cost_unit].core_us);
            row["stepped"] = measure_json(b, rk);
            row["cost_relative_to_" + c.settings[c.cost_unit].label] = b.core_us / c.step[c.cost_unit].core_us;
        }
        std::printf("\n");
        rows.push_back(row);
    }
    return {{"reference", c.settings[c.reference].label},
            {"settings", rows},
            {"observer_vs_engine_max_relative_mismatch", c.worst_mismatch}};
}

void run_accuracy_bench(const AccuracyArgs& args) {
    if (args.geometry != "slab" && args.geometry != "bulk")
        throw std::invalid_argument("--geometry must be slab or bulk");
    const bool bulk = args.geometry == "bulk";
    // Bulk by default fills the smallest cube the 8-diameter cutoff admits (~8,100 grains).
    const long grains = args.grains > 0 ? args.grains : (bulk ? 0 : 2000);
    // Polydisperse grains: number-weighted lognormal, median 6.7 um, sigma_ln 0.3, truncated at
    // +-1.5 sigma (4.3 to 10.5 um). A periodic side must be more than twice the 8-diameter cutoff
    // of the largest pair (plus the skin). Slab: periodic in x and y with that side, walls in z at
    // the height that holds the grains. Bulk: periodic cube (no walls, no sample surface).
    const double sigma = 0.3, trunc = 1.5;
    const double dmin = kDiameter * std::exp(-trunc * sigma), dmax = kDiameter * std::exp(trunc * sigma);
    const SizeDistribution sizes = SizeDistribution::lognormal(kDiameter, sigma, dmin, dmax);
    const double solid = static_cast<double>(grains) * sizes.mean_particle_volume() / kVolumeFraction;
    const double skin_estimate = 0.1 * sizes.mean_diameter_number();
    const double side_min = 2.0 * (8.0 * dmax + skin_estimate) * 1.03;
    const double lxy = bulk ? std::max(side_min, std::cbrt(solid)) : side_min;
    const double lz = bulk ? lxy : solid / (lxy * lxy);
    // The slab's side is fixed by the cutoff, so its height comes from the count: at least two
    // of the largest grains.
    if (!bulk && lz < 2.0 * dmax) {
        const double fewest = std::ceil(2.0 * dmax * lxy * lxy * kVolumeFraction / sizes.mean_particle_volume());
        throw SceneError("--grains", "is too few for the slab (its side is fixed by the cutoff at " +
                                         format_number(lxy * 1e6) + " um): give at least " + format_number(fewest) +
                                         ", or 0 for the default");
    }
    const nlohmann::json size = {{"distribution", "lognormal"},
                                 {"median_diameter", kDiameter},
                                 {"sigma_ln", sigma},
                                 {"min_diameter", dmin},
                                 {"max_diameter", dmax}};
    nlohmann::json input = mr_scene("magnetic accuracy: polydisperse iron grains forming chains at 600 mT", lxy, lxy,
                                    lz, size, {{"diameters", 5.0}});
    if (bulk) {
        input["domain"]["periodic"] = "xyz";
        input.erase("walls");
    }
    // Chains pull small grains hard into their big neighbours (1 GPa grains, as the source):
    // overlaps pass the default guard of 0.1 small radii in the bulk scene. The guard only stops
    // a run; raising it changes no force.
    input["run"]["max_overlap_fraction"] = 0.3;
    BuildOptions build;
    build.threads = args.threads;
    Scene scene = build_scene(input, build);
    choose_timestep(scene);
    System& s = scene.system;
    const double skin = s.contacts.settings().skin;
    const std::size_t n = s.particles.size();
    std::printf(
        "bench magnetic-accuracy (%s): %zu grains, lognormal median %.1f um, sigma_ln %.1f, truncated to "
        "%.2f-%.2f um; box %.1f x %.1f x %.1f um (%s); phi %.2f; 600 mT along z; dt %.3g s; %d thread(s)\n",
        args.geometry.c_str(), n, kDiameter * 1e6, sigma, dmin * 1e6, dmax * 1e6, lxy * 1e6, lxy * 1e6, lz * 1e6,
        bulk ? "periodic in x, y and z" : "periodic in x and y, walls in z", kVolumeFraction, s.dt, args.threads);
    std::fflush(stdout);

    // Chains form under the reference-quality formation setting (lagged, 5 diameters). Two
    // states are kept: one while the chains are still forming (fast motion: the policies' lag
    // shows) and the formed one.
    prepare(s);
    const long M = std::min(args.replay_steps, args.early_step - 1);
    const auto form0 = Clock::now();
    const SavedState early = advance_and_save(s, args.early_step, M, "forming chains (lagged, 5 d)");
    double aligned_early = 0;
    const double cos_early = contact_alignment(early.system, nullptr, &aligned_early);
    double vmax_early = 0;
    for (const Vec3& v : early.system.particles.velocity) vmax_early = std::max(vmax_early, norm(v));
    const SavedState formed = advance_and_save(s, args.form_steps, M, "forming chains (lagged, 5 d)");
    const double form_wall = seconds_since(form0);
    const System& saved = formed.system;
    double aligned_formed = 0;
    const double cos_formed = contact_alignment(saved, nullptr, &aligned_formed);
    double vmax_formed = 0;
    for (const Vec3& v : saved.particles.velocity) vmax_formed = std::max(vmax_formed, norm(v));
    std::printf(
        "while forming, step %ld (%.3g s): mean |cos| of contact normals to z %.3f, %.0f%% within 30 deg, %.2f "
        "contacts per grain, fastest grain %.3g m/s\n",
        args.early_step, early.system.time, cos_early, 100 * aligned_early, mean_coordination(early.system),
        vmax_early);
    std::printf(
        "formed, step %ld (%.3g s, %.0f s wall): mean |cos| of contact normals to z %.3f (random contacts: "
        "0.5), %.0f%% within 30 deg, %.2f contacts per grain, fastest grain %.3g m/s\n\n",
        args.form_steps, saved.time, form_wall, cos_formed, 100 * aligned_formed, mean_coordination(saved),
        vmax_formed);
    std::fflush(stdout);

    // (1) Policies and cutoffs at the formed state, against converged dipoles at 8 diameters.
    std::vector<Setting> main_settings = {
        make_setting(MutualPolicy::converged, 1, 1e-8, 8, "converged"),  // the reference, first
        make_setting(MutualPolicy::fixed, 1, 1e-6, 5, "fixed"),
        make_setting(MutualPolicy::lagged, 1, 1e-6, 5, "lagged"),
        make_setting(MutualPolicy::iterations, 1, 1e-6, 5, "iterations 1"),
        make_setting(MutualPolicy::iterations, 3, 1e-6, 5, "iterations 3"),
        make_setting(MutualPolicy::converged, 1, 1e-8, 5, "converged"),
        make_setting(MutualPolicy::converged, 1, 1e-8, 3, "converged"),
        make_setting(MutualPolicy::converged, 1, 1e-8, 2, "converged"),
        make_setting(MutualPolicy::lagged, 1, 1e-6, 8, "lagged"),
        make_setting(MutualPolicy::lagged, 1, 1e-6, 3, "lagged"),
        make_setting(MutualPolicy::lagged, 1, 1e-6, 2, "lagged"),
    };
    const std::size_t lagged8 = 8, lagged3 = 9;
    const bool with_steps = !bulk;  // bulk: same configuration only (the 8 d stepping would take ~10 min)
    const Comparison main_cmp = compare(formed, main_settings, 0, lagged3, skin, args, with_steps, "formed");

    // (2) The policies while chains form, at 3 diameters, against converged dipoles at 3 d:
    // the cutoff is the same for all, so the differences are the policies' alone.
    std::vector<Setting> policy_settings = {
        make_setting(MutualPolicy::converged, 1, 1e-8, 3, "converged"),
        make_setting(MutualPolicy::fixed, 1, 1e-6, 3, "fixed"),
        make_setting(MutualPolicy::lagged, 1, 1e-6, 3, "lagged"),
        make_setting(MutualPolicy::iterations, 1, 1e-6, 3, "iterations 1"),
        make_setting(MutualPolicy::iterations, 3, 1e-6, 3, "iterations 3"),
        make_setting(MutualPolicy::converged, 1, 1e-4, 3, "converged 1e-4"),
    };
    const Comparison early_cmp = compare(early, policy_settings, 0, 2, skin, args, with_steps, "forming");

    // Noise floor of the stepped comparison: lagged at 8 d (cheap) re-run with another thread
    // count (same physics, another summation order) against its own run.
    Measure floor_run;
    const int other_threads = args.threads > 1 ? 1 : 2;
    if (with_steps) floor_run = stepped(saved, main_settings[lagged8], skin, args.steps, other_threads);

    std::printf("## Formed chains (step %ld): policy and cutoff against converged dipoles at 8 diameters\n\n",
                args.form_steps);
    std::printf(
        "Errors are signed, 100 (X - X_ref) / X_ref. mean abs F: mean over grains of |sum of the magnetic pair "
        "forces on the grain|. sigma = (1/V) sum over pairs r F (V the box; negative sigma_zz: net magnetic "
        "attraction along z). Same config: the settings' moments built along the same last %ld steps of the "
        "formation trajectory, forces evaluated at the same positions.",
        M);
    if (with_steps)
        std::printf(
            " After %ld steps: each setting run on from the formed state; cost: all forces, %d thread(s), timed "
            "over those steps.",
            args.steps, args.threads);
    else
        std::printf(" (Bulk: same configuration only; stepping the 8-diameter reference here would take ~10 minutes.)");
    std::printf("\n\n");
    const nlohmann::json main_json = print_comparison(main_cmp, args);
    if (with_steps)
        std::printf(
            "\nNoise floor of the stepped columns: %s re-run with %d thread(s) (same physics, another summation "
            "order) differs from its %d-thread run by %+.3f %% in mean |F| and %+.3f %% in sigma_zz after %ld "
            "steps.\n",
            main_settings[lagged8].label.c_str(), other_threads, args.threads,
            percent(floor_run.obs.mean_force, main_cmp.step[lagged8].obs.mean_force),
            percent(floor_run.obs.sigma_zz, main_cmp.step[lagged8].obs.sigma_zz), args.steps);

    std::printf(
        "\n## While chains form (step %ld): policies at 3 diameters against converged dipoles at 3 diameters\n\n",
        args.early_step);
    std::printf(
        "Stress errors here in per cent of the reference's larger diagonal magnitude, max(|sigma_xx|, "
        "|sigma_zz|): sigma_zz itself is near zero while chains form.\n\n");
    const nlohmann::json early_json = print_comparison(early_cmp, args, true);
    const double worst_mismatch = std::max(main_cmp.worst_mismatch, early_cmp.worst_mismatch);
    const std::size_t brute = brute_force_pairs_in_range(saved.particles, saved.domain, main_settings[0].diameters);
    const std::size_t listed_in_range = main_cmp.same[0].obs.pairs_in_range;
    std::printf(
        "\nObserver check: the pair forces summed here from eq. 4.8 match the forces add_magnetic_forces applied "
        "to within %.2g of the mean |F| (worst grain, all settings, same configuration). Pairs within 8 "
        "diameters at the formed state: %zu by the list, %zu by brute force.\n",
        worst_mismatch, listed_in_range, brute);

    if (!args.json_out.empty()) {
        nlohmann::json out = {
            {"benchmark", "magnetic-accuracy"},
            {"geometry", args.geometry},
            {"grains", n},
            {"threads", args.threads},
            {"timestep_s", saved.dt},
            {"box_m", {lxy, lxy, lz}},
            {"volume_m3", domain_volume(saved.domain)},
            {"size", size},
            {"form_steps", args.form_steps},
            {"form_wall_s", form_wall},
            {"formed",
             {{"mean_abs_cos_contact_normal_z", cos_formed},
              {"fraction_contacts_within_30deg_of_z", aligned_formed},
              {"contacts_per_grain", mean_coordination(saved)},
              {"fastest_grain_m_per_s", vmax_formed}}},
            {"forming",
             {{"step", args.early_step},
              {"mean_abs_cos_contact_normal_z", cos_early},
              {"fraction_contacts_within_30deg_of_z", aligned_early},
              {"contacts_per_grain", mean_coordination(early.system)},
              {"fastest_grain_m_per_s", vmax_early}}},
            {"steps_per_setting", with_steps ? args.steps : 0},
            {"replayed_steps_same_configuration", M},
            {"formed_comparison", main_json},
            {"forming_policy_comparison", early_json},
            {"observer_vs_engine_max_relative_mismatch", worst_mismatch},
            {"pairs_within_8d_list", listed_in_range},
            {"pairs_within_8d_brute_force", brute},
            {"scene", scene.resolved},
        };
        if (with_steps)
            out["noise_floor"] = {{"setting", main_settings[lagged8].label},
                                  {"threads", other_threads},
                                  {"stepped", measure_json(floor_run, main_cmp.step[lagged8])}};
        write_json_file(args.json_out, out);
    }
}

}  // namespace

void add_magnetic_bench_commands(CLI::App& bench, int& exit_status) {
    auto margs = std::make_shared<MagneticBenchArgs>();
    CLI::App* magnetic = bench.add_subcommand(
        "magnetic",
        "Chain-forming MR scene (1,905 iron grains, 600 mT, lagged mutual dipoles): core-us per grain-step");
    magnetic->add_option("--steps", margs->steps, "Timed steps")
        ->check(CLI::Range(1L, 100000000L))
        ->capture_default_str();
    magnetic->add_option("--settle-steps", margs->settle_steps, "Untimed steps for chains to form first")
        ->check(CLI::Range(0L, 100000000L))
        ->capture_default_str();
    magnetic->add_option("--threads", margs->threads, "OpenMP threads")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    magnetic->add_option("--json", margs->json_out, "Write the figures as JSON here");
    magnetic->callback([margs, &exit_status] {
        if (!margs->json_out.empty()) prepare_output_file(margs->json_out, "--json");
        run_magnetic_bench(*margs);
        exit_status = 0;
    });

    auto aargs = std::make_shared<AccuracyArgs>();
    CLI::App* accuracy = bench.add_subcommand(
        "magnetic-accuracy",
        "Speed/accuracy of the mutual-dipole policy and magnetic cutoff against converged dipoles at 8 diameters");
    accuracy
        ->add_option("--geometry", aargs->geometry,
                     "slab: periodic in x and y, walls in z (stepped and same-configuration comparisons); bulk: "
                     "periodic cube (same configuration only)")
        ->check(CLI::IsMember({"slab", "bulk"}))
        ->capture_default_str();
    accuracy->add_option("--form-steps", aargs->form_steps, "Steps forming the chains (lagged, 5 diameters)")
        ->check(CLI::Range(3L, 100000000L))
        ->capture_default_str();
    accuracy
        ->add_option("--early-step", aargs->early_step,
                     "Formation step at which the policies are compared while chains form")
        ->check(CLI::Range(2L, 100000000L))
        ->capture_default_str();
    accuracy->add_option("--steps", aargs->steps, "Steps each setting runs from the formed state (K)")
        ->check(CLI::Range(2L, 100000000L))
        ->capture_default_str();
    accuracy
        ->add_option("--replay-steps", aargs->replay_steps,
                     "Formation steps replayed to give each setting its moment history (same configuration)")
        ->check(CLI::Range(1L, 100000L))
        ->capture_default_str();
    accuracy
        ->add_option("--grains", aargs->grains,
                     "Approximate number of grains (0: 2000 in the slab; the bulk cube is at least the smallest the "
                     "8-diameter cutoff admits, ~8100 grains)")
        ->check(CLI::Range(0L, 1000000L))
        ->capture_default_str();
    accuracy->add_option("--threads", aargs->threads, "OpenMP threads")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
    accuracy->add_option("--json", aargs->json_out, "Write the figures as JSON here");
    accuracy->callback([aargs, &exit_status] {
        if (aargs->early_step >= aargs->form_steps)
            throw CLI::ValidationError("--early-step", "must be below --form-steps");
        if (!aargs->json_out.empty()) prepare_output_file(aargs->json_out, "--json");
        run_accuracy_bench(*aargs);
        exit_status = 0;
    });
}

}  // namespace mrjam::cli
