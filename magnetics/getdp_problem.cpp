#include "magnetics/getdp_problem.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>

#include "core/format.hpp"
#include "magnetics/child_process.hpp"

namespace mrjam::magnetics {

namespace fs = std::filesystem;

const RegionField& Solution::field(int region) const {
    for (const auto& f : fields)
        if (f.region == region) return f;
    throw std::out_of_range("no measured field for region " + std::to_string(region));
}

namespace {

constexpr int kMaxSolverIterations = 20000;

// Full precision: the .pro file must carry the value the caller meant.
std::string number(double v) { return format_number(v, 17); }

std::string vector_text(const Vec3& v) {
    return "Vector[" + number(v.x) + ", " + number(v.y) + ", " + number(v.z) + "]";
}

std::string group_list(const std::vector<RegionMaterial>& regions) {
    std::string s;
    for (const auto& r : regions) s += (s.empty() ? "" : ", ") + r.name;
    return s;
}

}  // namespace

std::string getdp_problem_text(const ProblemRequest& p) {
    const double mu0 = 4e-7 * std::numbers::pi;
    std::ostringstream o;
    o << "// Written by mrjam magnetics: magnetic scalar potential, H = -grad phi, B = mu H + Br.\n";
    o << "Group {\n";
    for (const auto& r : p.regions) o << "  " << r.name << " = Region[" << r.region << "];\n";
    o << "  Boundary = Region[" << p.boundary_region << "];\n";
    o << "  Domain = Region[{" << group_list(p.regions) << "}];\n";
    std::string saturating;
    for (const auto& r : p.regions)
        if (r.saturating) saturating += (saturating.empty() ? "" : ", ") + r.name;
    if (!saturating.empty()) o << "  Saturating = Region[{" << saturating << "}];\n";
    o << "}\n\nFunction {\n  mu0 = " << number(mu0) << ";\n";
    for (const auto& r : p.regions) {
        if (r.saturating) {
            // Frohlich-Kennelly: B = mu0 H + J_s H / (H_k + H), H_k = J_s / ((mu_r - 1) mu0), so that
            // mu -> mu0 mu_r at low field and the polarisation saturates at J_s.
            const double hk = r.saturation / ((r.relative_permeability - 1.0) * mu0);
            o << "  mu[" << r.name << "] = mu0 + " << number(r.saturation) << " / (" << number(hk) << " + Norm[$1]);\n";
            // d mu / d|H| divided by |H|, for the Newton Jacobian's dyadic term.
            o << "  dmudh_over_h[" << r.name << "] = -" << number(r.saturation) << " / ((" << number(hk)
              << " + Norm[$1])^2 * (Norm[$1] + 1e-12));\n";
        } else {
            o << "  mu[" << r.name << "] = " << number(r.relative_permeability) << " * mu0;\n";
        }
        o << "  br[" << r.name << "] = " << vector_text(r.remanence) << ";\n";
    }
    const Vec3& h0 = p.applied_field;
    o << "  phi_applied[] = -(" << number(h0.x) << " * X[] + " << number(h0.y) << " * Y[] + " << number(h0.z)
      << " * Z[]);\n}\n\n";
    // The applied potential is linear, which the nodal functions carry exactly: the second-order
    // (edge) coefficients on the boundary are zero.
    o << "Constraint { { Name PhiApplied; Case { { Region Boundary; Value phi_applied[]; } } }\n"
         "  { Name EdgeZero; Case { { Region Boundary; Value 0.; } } } }\n\n";
    o << "Jacobian { { Name Vol; Case { { Region All; Jacobian " << (p.axisymmetric ? "VolAxi" : "Vol")
      << "; } } } }\n";
    o << "Integration { { Name Gauss2; Case { { Type Gauss; Case {\n"
         "  { GeoElement Triangle; NumberOfPoints 4; } { GeoElement Tetrahedron; NumberOfPoints 4; }\n"
         "  { GeoElement Line; NumberOfPoints 3; } } } } } }\n\n";
    // Second-order hierarchical elements: the edge functions need the boundary constraint too.
    o << "FunctionSpace { { Name Hphi; Type Form0;\n"
         "  BasisFunction {\n"
         "    { Name sn; NameOfCoef phin; Function BF_Node; Support Domain; Entity NodesOf[All]; }\n"
         "    { Name se; NameOfCoef phie; Function BF_Node_2E; Support Domain; Entity EdgesOf[All]; } }\n"
         "  Constraint {\n"
         "    { NameOfCoef phin; EntityType NodesOf; NameOfConstraint PhiApplied; }\n"
         "    { NameOfCoef phie; EntityType EdgesOf; NameOfConstraint EdgeZero; } } } }\n\n";
    const std::string mu_of = saturating.empty() ? "mu[]" : "mu[-{d phi}]";
    o << "Formulation { { Name Magnetostatics; Type FemEquation;\n"
         "  Quantity { { Name phi; Type Local; NameOfSpace Hphi; } }\n"
         "  Equation {\n"
         "    Galerkin { [ "
      << mu_of
      << " * Dof{d phi}, {d phi} ]; In Domain; Jacobian Vol; Integration Gauss2; }\n"
         "    Galerkin { [ -br[], {d phi} ]; In Domain; Jacobian Vol; Integration Gauss2; }\n";
    // Newton: d(mu(|H|) H)/dH = mu I + (dmu/d|H|) H (x) H / |H|; the second part is JacNL.
    if (!saturating.empty())
        o << "    Galerkin { JacNL [ dmudh_over_h[-{d phi}] * SquDyadicProduct[{d phi}] * Dof{d phi}, {d phi} ]; "
             "In Saturating; Jacobian Vol; Integration Gauss2; }\n";
    o << "  } } }\n\n";
    o << "Resolution { { Name Magnetostatics; System { { Name A; NameOfFormulation Magnetostatics; } }\n  Operation "
         "{\n";
    if (saturating.empty()) {
        o << "    Generate[A]; Solve[A];\n";
    } else {
        // Newton iteration (the JacNL term above completes the Jacobian).
        o << "    InitSolution[A];\n    IterativeLoop[" << p.nonlinear_iterations << ", "
          << number(p.nonlinear_tolerance) << ", 1] { GenerateJac[A]; SolveJac[A]; }\n";
    }
    o << "    SaveSolution[A]; } } }\n\n";
    o << "PostProcessing { { Name Field; NameOfFormulation Magnetostatics; Quantity {\n"
         "  { Name b; Value { Local { [ -"
      << mu_of
      << " * {d phi} + br[] ]; In Domain; Jacobian Vol; } } }\n"
         "  { Name normb; Value { Local { [ Norm[-"
      << mu_of
      << " * {d phi} + br[]] ]; In Domain; Jacobian Vol; } } }\n"
         "  { Name volume; Value { Integral { [ 1 ]; In Domain; Jacobian Vol; Integration Gauss2; } } }\n"
         "  { Name intb; Value { Integral { [ Norm[-"
      << mu_of
      << " * {d phi} + br[]] ]; In Domain; Jacobian Vol; Integration Gauss2; } } }\n"
         "  { Name intb2; Value { Integral { [ SquNorm[-"
      << mu_of
      << " * {d phi} + br[]] ]; In Domain; Jacobian Vol; Integration Gauss2; } } }\n"
         "} } }\n\n";
    o << "PostOperation { { Name Report; NameOfPostProcessing Field; Operation {\n";
    for (int r : p.measured_regions) {
        const std::string g = "Region[" + std::to_string(r) + "]";
        for (const char* q : {"volume", "intb", "intb2"})
            o << "  Print[ " << q << "[" << g << "], OnGlobal, Format Table, File \"" << q << "_" << r << ".txt\" ];\n";
        o << "  Print[ normb, OnElementsOf " << g << ", Format SimpleTable, File \"nodes_" << r << ".txt\" ];\n";
    }
    for (int r : p.sampled_regions)
        o << "  Print[ b, OnElementsOf Region[" << r << "], Format SimpleTable, File \"elements_" << r << ".txt\" ];\n";
    if (p.section) {
        if (p.dimension == 3)
            o << "  Print[ normb, OnSection { {0, 0, 0} {1, 0, 0} {0, 1, 0} }, Format SimpleTable, File "
                 "\"section.txt\" ];\n";
        else
            o << "  Print[ normb, OnElementsOf Domain, Format SimpleTable, File \"section.txt\" ];\n";
    }
    for (std::size_t i = 0; i < p.lines.size(); ++i) {
        const auto& l = p.lines[i];
        o << "  Print[ b, OnLine { {" << number(l.from.x) << ", " << number(l.from.y) << ", " << number(l.from.z)
          << "} {" << number(l.to.x) << ", " << number(l.to.y) << ", " << number(l.to.z) << "} } {" << l.points - 1
          << "}, Format SimpleTable, File \"line_" << i << ".txt\" ];\n";
    }
    o << "} } }\n";
    return o.str();
}

std::string find_getdp() {
    const char* path = std::getenv("PATH");
    if (!path) return {};
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        if (dir.empty()) continue;
        const fs::path candidate = fs::path(dir) / "getdp";
        std::error_code ec;
        if (fs::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) return candidate.string();
    }
    return {};
}

namespace {

std::vector<std::vector<double>> read_rows(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw SolverError("GetDP did not write " + file.string() + " (see getdp.log next to it)");
    std::vector<std::vector<double>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::vector<double> row;
        double v;
        while (s >> v) row.push_back(v);
        if (!row.empty()) rows.push_back(std::move(row));
    }
    return rows;
}

double global_value(const fs::path& file) {
    const auto rows = read_rows(file);
    if (rows.empty() || rows.back().empty()) throw SolverError("empty GetDP output " + file.string());
    return rows.back().back();
}

// SimpleTable rows of a vector quantity end with its three components.
std::vector<Vec3> vector_rows(const fs::path& file) {
    std::vector<Vec3> out;
    for (const auto& r : read_rows(file)) {
        if (r.size() < 6) throw SolverError("unexpected row in " + file.string());
        const std::size_t n = r.size();
        out.push_back({r[n - 3], r[n - 2], r[n - 1]});
    }
    return out;
}

// OnElementsOf / OnSection rows: the element's vertices (3 coordinates each), then the
// quantity's components at each vertex. Polygons from a section are split into a fan of
// triangles.
ElementField element_rows(const fs::path& file, int components, int dimension) {
    ElementField f;
    f.vertices = dimension == 3 ? 4 : 3;
    for (const auto& r : read_rows(file)) {
        const std::size_t k = r.size() / (3 + components);
        if (k * (3 + components) != r.size()) throw SolverError("unexpected element row in " + file.string());
        if (k < 3) continue;  // a section touching an element only along an edge
        auto point = [&](std::size_t v) { return Vec3{r[3 * v], r[3 * v + 1], r[3 * v + 2]}; };
        auto value = [&](std::size_t v) {
            const std::size_t at = 3 * k + components * v;
            return components == 3 ? Vec3{r[at], r[at + 1], r[at + 2]} : Vec3{r[at], 0, 0};
        };
        if (dimension == 3) {
            if (k != 4) throw SolverError("expected tetrahedra in " + file.string());
            for (std::size_t v = 0; v < 4; ++v) {
                f.points.push_back(point(v));
                f.values.push_back(value(v));
            }
            continue;
        }
        for (std::size_t v = 1; v + 1 < k; ++v)
            for (std::size_t u : {std::size_t{0}, v, v + 1}) {
                f.points.push_back(point(u));
                f.values.push_back(value(u));
            }
    }
    return f;
}

// OnElementsOf rows: the element's nodes (3 coordinates each) then one value per node.
double max_node_value(const fs::path& file) {
    double m = 0;
    for (const auto& r : read_rows(file)) {
        const std::size_t values = r.size() / 4;
        for (std::size_t i = r.size() - values; i < r.size(); ++i) m = std::max(m, r[i]);
    }
    return m;
}

std::string tail_of(const fs::path& log, std::size_t lines) {
    std::ifstream in(log);
    std::vector<std::string> all;
    std::string line;
    while (std::getline(in, line)) all.push_back(line);
    std::string out;
    for (std::size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i) out += "  " + all[i] + "\n";
    return out;
}

}  // namespace

Solution solve_with_getdp(const ProblemRequest& p, const fs::path& work_dir, const fs::path& mesh_file) {
    const std::string getdp = find_getdp();
    if (getdp.empty())
        throw SolverError(
            "getdp was not found on PATH; install it with `apt-get install getdp` "
            "(or run scripts/install-deps.sh)");
    const auto start = std::chrono::steady_clock::now();
    const fs::path pro = work_dir / "problem.pro";
    const fs::path log = work_dir / "getdp.log";
    {
        std::ofstream out(pro);
        out << getdp_problem_text(p);
        if (!out) throw SolverError("cannot write " + pro.string());
    }
    // -v 4 makes GetDP log the iteration count, which is how non-convergence is detected: it
    // returns 0 even when CG stops at the iteration limit.
    std::vector<std::string> argv{
        getdp, pro.string(), "-msh", mesh_file.string(), "-solve", "Magnetostatics", "-pos", "Report", "-v", "4"};
    if (p.direct_solver)
        argv.insert(argv.end(), {"-ksp_type", "preonly", "-pc_type", "lu"});
    else
        argv.insert(argv.end(), {"-ksp_type", "cg", "-pc_type", "icc", "-ksp_rtol", number(p.solver_tolerance),
                                 "-ksp_max_it", std::to_string(kMaxSolverIterations)});
    const ChildResult run = run_child(argv, log);
    const int status = run.wait_status;
    if (run.stopped_by_us) throw SolverError("getdp was stopped: mrjam was interrupted");
    // Ctrl-C in a terminal reaches GetDP as well (the whole process group): the handler in this
    // process has seen it too, or (none installed) the signal is passed on for its default action.
    if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM)) {
        std::raise(SIGINT);
        throw SolverError("getdp was interrupted");
    }
    if (status != 0)
        throw SolverError("getdp failed (status " + std::to_string(status) + "); the end of its log " + log.string() +
                          ":\n" + tail_of(log, 12));

    Solution s;
    {
        std::ifstream in(log);
        std::string line;
        const std::regex iterations(R"(Info\s*:\s*(\d+) iterations)");
        const std::regex dofs(R"(System \d+/\d+: (\d+) Dofs)");
        const std::regex error(R"(^Error)");
        const std::regex nonlinear(R"(Nonlinear Residual norm\s+([0-9.eE+-]+))");
        std::smatch m;
        while (std::getline(in, line)) {
            if (std::regex_search(line, m, iterations)) s.solver_iterations = std::stoi(m[1]);
            if (std::regex_search(line, m, dofs)) s.unknowns = std::stoi(m[1]);
            if (std::regex_search(line, error))
                throw SolverError("getdp reported: " + line + " (log: " + log.string() + ")");
            if (std::regex_search(line, m, nonlinear)) {
                ++s.nonlinear_steps;
                s.nonlinear_residual = std::stod(m[1]);
            }
        }
    }
    if (s.solver_iterations >= kMaxSolverIterations)
        throw SolverError("the CG solver did not converge in " + std::to_string(kMaxSolverIterations) +
                          " iterations (" + std::to_string(s.unknowns) +
                          " unknowns); check the mesh for slivers or use a coarser mesh. Log: " + log.string());

    const bool saturating = std::any_of(p.regions.begin(), p.regions.end(), [](const auto& r) { return r.saturating; });
    if (saturating && !(s.nonlinear_residual <= p.nonlinear_tolerance))
        throw SolverError(
            "the nonlinear (saturating iron) iteration did not converge: residual " +
            format_number(s.nonlinear_residual) + " after " + std::to_string(s.nonlinear_steps) + " steps (tolerance " +
            format_number(p.nonlinear_tolerance) + ", " + std::to_string(s.unknowns) +
            " unknowns); the iron may be deep in saturation: check the remanence and the saturation. Log: " +
            log.string());

    // Results are written next to the .pro file.
    for (int r : p.measured_regions) {
        RegionField f;
        f.region = r;
        const std::string suffix = "_" + std::to_string(r) + ".txt";
        f.volume = global_value(work_dir / ("volume" + suffix));
        if (!(f.volume > 0)) throw SolverError("region " + std::to_string(r) + " has no volume in the mesh");
        f.mean_b = global_value(work_dir / ("intb" + suffix)) / f.volume;
        f.mean_b_squared = global_value(work_dir / ("intb2" + suffix)) / f.volume;
        f.max_b = max_node_value(work_dir / ("nodes" + suffix));
        if (!std::isfinite(f.mean_b) || !std::isfinite(f.mean_b_squared))
            throw SolverError("GetDP returned a non-finite field in region " + std::to_string(r));
        s.fields.push_back(f);
    }
    for (int r : p.sampled_regions)
        s.sampled.append(element_rows(work_dir / ("elements_" + std::to_string(r) + ".txt"), 3, p.dimension));
    if (p.section) s.section = element_rows(work_dir / "section.txt", 1, 2);
    for (std::size_t i = 0; i < p.lines.size(); ++i)
        s.line_values.push_back(vector_rows(work_dir / ("line_" + std::to_string(i) + ".txt")));
    s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return s;
}

}  // namespace mrjam::magnetics
