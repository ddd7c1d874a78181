// hemivem bench --limit: every stage of a solve against the machine's limit, measured in one run
// (drivers/limit.hpp).
#include "limit.hpp"

#include "commands.hpp"
#include "common.hpp"
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/support/output_folder.hpp>

#include <Eigen/Sparse>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace hemivem::cli {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The peak resident memory of this process so far, in bytes.
double peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) * 1024.0;
}

/// The plain assembly of limit.cpp, written for hemivem's mesh and dof numbering: the bilinear
/// (Q1) plane-strain stiffness of one h x h square (2 x 2 Gauss), added for every element with
/// Eigen triplets (lower triangle), one setFromTriplets. Same sparsity as the VEM matrix on
/// squares; meaningless (and refused) on other meshes.
double plain_q1_assembly_seconds(const Mesh& mesh, const DofMap& dofs, double lambda, double mu) {
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (mesh.element_size(e) != 4)
      throw InputError("the limit's plain assembly is the Q1 stiffness of squares: element " + std::to_string(e) +
                           " has " + std::to_string(mesh.element_size(e)) + " vertices",
                       "mesh.generator");
  const auto start = Clock::now();
  const auto first = mesh.element(0);
  const double h = (mesh.vertex(first[1]) - mesh.vertex(first[0])).norm();
  Eigen::Matrix<double, 8, 8> Ke = Eigen::Matrix<double, 8, 8>::Zero();
  Eigen::Matrix3d C;
  C << lambda + 2 * mu, lambda, 0, lambda, lambda + 2 * mu, 0, 0, 0, mu;
  const double gauss[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
  const double xs[4] = {0, 1, 1, 0}, ys[4] = {0, 0, 1, 1};
  for (double s : gauss)
    for (double t : gauss) {
      Eigen::Matrix<double, 3, 8> B = Eigen::Matrix<double, 3, 8>::Zero();
      for (int a = 0; a < 4; ++a) {
        const double dx = (xs[a] != 0.0 ? 1 : -1) * (ys[a] != 0.0 ? t : 1 - t) / h;
        const double dy = (ys[a] != 0.0 ? 1 : -1) * (xs[a] != 0.0 ? s : 1 - s) / h;
        B(0, 2 * a) = dx, B(1, 2 * a + 1) = dy, B(2, 2 * a) = dy, B(2, 2 * a + 1) = dx;
      }
      Ke += 0.25 * h * h * B.transpose() * C * B;
    }
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_elements()) * 36);
  int d[8];
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto v = mesh.element(e);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 2; ++c) d[2 * a + c] = dofs.free_index[static_cast<std::size_t>(2 * v[static_cast<std::size_t>(a)] + c)];
    for (int q = 0; q < 8; ++q)
      for (int p = 0; p < 8; ++p)
        if (d[p] >= 0 && d[q] >= 0 && d[p] >= d[q]) triplets.emplace_back(d[p], d[q], Ke(p, q));
  }
  SparseMatrix A(dofs.num_free(), dofs.num_free());
  A.setFromTriplets(triplets.begin(), triplets.end());
  A.makeCompressed();
  return since(start);
}

/// The plain assembly of limit3d.cpp, written for hemivem's mesh of boxes and dof numbering: the
/// trilinear (Q1) stiffness of one hx x hy x hz box (2 x 2 x 2 Gauss), added for every cell with
/// Eigen triplets (lower triangle), one setFromTriplets. Same sparsity as the VEM matrix on
/// boxes; refused on other meshes.
double plain_q1_hex_assembly_seconds(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu) {
  for (int c = 0; c < mesh.num_cells(); ++c)
    if (mesh.cell_vertices(c).size() != 8 || mesh.cell_faces(c).size() != 6)
      throw InputError("the limit's plain assembly is the Q1 stiffness of boxes: cell " + std::to_string(c) +
                           " is not a box",
                       "mesh.generator");
  const auto start = Clock::now();
  // the vertices of a box of make_cubes, sorted by id, are its corners a = i + 2 j + 4 k
  const auto& first = mesh.cell_vertices(0);
  const Vec3 size = mesh.vertex(first[7]) - mesh.vertex(first[0]);
  Eigen::Matrix<double, 24, 24> Ke = Eigen::Matrix<double, 24, 24>::Zero();
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) C(a, b) = lambda;
    C(a, a) = lambda + 2 * mu;
    C(3 + a, 3 + a) = mu;
  }
  const double gauss[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
  for (double r : gauss)
    for (double q : gauss)
      for (double t : gauss) {
        Eigen::Matrix<double, 6, 24> B = Eigen::Matrix<double, 6, 24>::Zero();
        for (int a = 0; a < 8; ++a) {
          const int cx = a & 1, cy = a >> 1 & 1, cz = a >> 2 & 1;
          const double fx = cx ? r : 1 - r, fy = cy ? q : 1 - q, fz = cz ? t : 1 - t;
          const double dx = (cx ? 1 : -1) * fy * fz / size.x(), dy = (cy ? 1 : -1) * fx * fz / size.y(),
                       dz = (cz ? 1 : -1) * fx * fy / size.z();
          B(0, 3 * a) = dx, B(1, 3 * a + 1) = dy, B(2, 3 * a + 2) = dz;
          B(3, 3 * a + 1) = dz, B(3, 3 * a + 2) = dy;
          B(4, 3 * a) = dz, B(4, 3 * a + 2) = dx;
          B(5, 3 * a) = dy, B(5, 3 * a + 1) = dx;
        }
        Ke += 0.125 * size.prod() * B.transpose() * C * B;
      }
  std::vector<Eigen::Triplet<double, int>> triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_cells()) * 300);
  int d[24];
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cell_vertices(c);
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 3; ++k) d[3 * a + k] = dofs.free_index[static_cast<std::size_t>(3 * v[static_cast<std::size_t>(a)] + k)];
    for (int q = 0; q < 24; ++q)
      for (int p = 0; p < 24; ++p)
        if (d[p] >= 0 && d[q] >= 0 && d[p] >= d[q]) triplets.emplace_back(d[p], d[q], Ke(p, q));
  }
  SparseMatrix A(dofs.num_free(), dofs.num_free());
  A.setFromTriplets(triplets.begin(), triplets.end());
  A.makeCompressed();
  return since(start);
}

struct LimitRow {
  int n = 0;
  int dofs = 0;
  int contact_nodes = 0;
  // mesh, assembly, condensation, minimize, back_substitution, result_json; margin, outputs
  std::map<std::string, double> stage;
  double solve = 0.0;                   // wall time from the scene to result.json
  double peak_rss = 0.0;                // bytes, of the solve's process
  double plain_assembly = 0.0;
  std::string ordering;                 // CHOLMOD's faster ordering
  double analysis = 0.0, factorization = 0.0, factor_bytes = 0.0, matrix_bytes = 0.0;
  std::map<std::string, double> alternative;  // the other ordering: analysis + factorization
  std::string status;
};

/// Runs `work` in a fresh child process (fork) and returns the JSON it produced: every
/// measurement starts, as `hemivem solve` and limit.cpp do, with a fresh heap, and the peak
/// memory is the child's own. An exception in the child comes back as the same kind of error.
nlohmann::json in_child(const std::function<nlohmann::json()>& work) {
  int fd[2];
  if (::pipe(fd) != 0) throw NumericalError("bench --limit: cannot create a pipe");
  const pid_t pid = ::fork();
  if (pid < 0) throw NumericalError("bench --limit: cannot start a child process");
  if (pid == 0) {
    ::close(fd[0]);
    nlohmann::json j;
    try {
      j = work();
    } catch (const InputError& e) {
      j = {{"error", "input"}, {"message", e.what()}};
    } catch (const std::exception& e) {
      j = {{"error", "numerical"}, {"message", e.what()}};
    }
    const std::string text = j.dump();
    std::size_t done = 0;
    while (done < text.size()) {
      const ssize_t w = ::write(fd[1], text.data() + done, text.size() - done);
      if (w <= 0) break;
      done += static_cast<std::size_t>(w);
    }
    ::close(fd[1]);
    ::_exit(0);
  }
  ::close(fd[1]);
  std::string text;
  char buffer[65536];
  for (ssize_t r; (r = ::read(fd[0], buffer, sizeof buffer)) != 0;) {
    if (r < 0) {
      if (errno == EINTR) continue;
      break;
    }
    text.append(buffer, static_cast<std::size_t>(r));
  }
  ::close(fd[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || text.empty())
    throw NumericalError("bench --limit: the measuring process ended without a result (out of memory?)");
  nlohmann::json j = nlohmann::json::parse(text);
  if (j.contains("error")) {
    const std::string message = j.at("message").get<std::string>();
    if (j.at("error") == "input") throw InputError(message);
    throw NumericalError(message);
  }
  return j;
}

/// One solve with cholmod (in this process): its wall time from the scene to result.json (as
/// `hemivem solve` with `output.write = ["result-json"]`), every stage, then the uniqueness margin
/// and the writing of all outputs, each timed on its own.
nlohmann::json measure_solve_3d(const Scene& scene) {
  const auto start = Clock::now();
  std::map<std::string, double> stage;
  ReducedProblem reduced;
  app::SceneSolve3DOptions so;
  so.reduced = &reduced;
  const app::SceneSolve3D s = app::solve_scene_3d(scene, so);
  stage["mesh"] = s.mesh_seconds;
  for (const char* k : {"assembly", "condensation", "minimize", "back_substitution"}) {
    const auto it = s.solution.timings.find(k);
    stage[k] = it == s.solution.timings.end() ? 0.0 : it->second;
  }
  const fs::path dir = fs::temp_directory_path() / ("hemivem-limit-" + std::to_string(::getpid()));
  const std::vector<std::string> result_only{"result.json"};
  auto t = Clock::now();
  (void)app::write_results(dir / "result-only", scene, s, &result_only);
  stage["result_json"] = since(t);
  const double wall = since(start);
  t = Clock::now();
  if (!reduced.laws.empty()) (void)uniqueness_margin(reduced.S, reduced.w, reduced.laws.front()->alpha());
  stage["margin"] = since(t);
  t = Clock::now();
  (void)app::write_results(dir / "all", scene, s);
  stage["outputs"] = since(t);
  std::error_code ec;
  fs::remove_all(dir, ec);
  return {{"stages", stage},
          {"wall", wall},
          {"dofs", s.solution.unknowns},
          {"contact_nodes", reduced.S.rows()},
          {"status", to_string(s.solution.status)},
          {"peak_rss", peak_rss_bytes()}};
}

nlohmann::json measure_solve(const Scene& scene) {
  if (scene.dimension() == 3) return measure_solve_3d(scene);
  const auto start = Clock::now();
  std::map<std::string, double> stage;
  ReducedProblem reduced;
  SceneSolve s = solve_scene(scene, {}, {}, &reduced);
  stage["mesh"] = s.mesh_seconds;
  for (const char* k : {"assembly", "condensation", "minimize", "back_substitution"}) {
    const auto it = s.solution.timings.find(k);
    stage[k] = it == s.solution.timings.end() ? 0.0 : it->second;
  }
  const fs::path dir = fs::temp_directory_path() / ("hemivem-limit-" + std::to_string(::getpid()));
  RunInfo info;
  info.scene_name = scene.title;
  info.scene_toml = to_toml(scene);
  info.linear = s.linear;
  info.minimizer = s.minimizer;
  auto t = Clock::now();
  (void)write_outputs(dir / "result-only", s.built->mesh, s.built->problem.elasticity.materials, s.solution, info,
                      {"result.json"});
  stage["result_json"] = since(t);
  const double wall = since(start);
  // the uniqueness margin runs inside the condensation; timed here on its own
  t = Clock::now();
  if (!reduced.laws.empty()) (void)uniqueness_margin(reduced.S, reduced.w, reduced.laws.front()->alpha());
  stage["margin"] = since(t);
  t = Clock::now();
  (void)write_outputs(dir / "all", s.built->mesh, s.built->problem.elasticity.materials, s.solution, info, all_outputs());
  stage["outputs"] = since(t);
  std::error_code ec;
  fs::remove_all(dir, ec);
  return {{"stages", stage},
          {"wall", wall},
          {"dofs", s.solution.unknowns},
          {"contact_nodes", reduced.S.rows()},
          {"status", to_string(s.solution.status)},
          {"peak_rss", peak_rss_bytes()}};
}

/// The limit (in this process): the plain assembly, and one CHOLMOD factorization of hemivem's
/// A with the given ordering.
nlohmann::json measure_limit(const Scene& scene, bool metis) {
  if (scene.dimension() == 3) {
    const auto built = build_problem_3d(scene);
    const auto& elasticity = built->problem.elasticity;
    const Lame lame = elasticity.materials.lame(built->mesh.region(0));
    const double plain =
        plain_q1_hex_assembly_seconds(built->mesh, make_dof_map(built->mesh, elasticity.dirichlet), lame.lambda, lame.mu);
    const LinearSystem system = assemble(elasticity);
    const double matrix_bytes = static_cast<double>(system.A.nonZeros()) * (sizeof(double) + sizeof(int)) +
                                static_cast<double>(system.A.outerSize() + 1) * sizeof(int);
    const ReferenceFactorization r = measure_reference_factorization(system.A, metis);
    if (!r.ok) throw NumericalError("the limit's CHOLMOD factorization (" + r.ordering + ") failed: " + r.message);
    return {{"plain_assembly", plain},        {"analysis", r.analysis_seconds}, {"factorization", r.factorization_seconds},
            {"factor_bytes", r.factor_bytes}, {"matrix_bytes", matrix_bytes},   {"ordering", r.ordering}};
  }
  const auto built = build_problem(scene);
  const auto& elasticity = built->problem.elasticity;
  // the plain assembly first, as in limit.cpp: its memory is as fresh as a program's
  const Lame lame = elasticity.materials.lame(built->mesh.region(0));
  const double plain = plain_q1_assembly_seconds(built->mesh, make_dof_map(built->mesh, elasticity.dirichlet), lame.lambda, lame.mu);
  const LinearSystem system = assemble(elasticity);
  const double matrix_bytes = static_cast<double>(system.A.nonZeros()) * (sizeof(double) + sizeof(int)) +
                              static_cast<double>(system.A.outerSize() + 1) * sizeof(int);
  const ReferenceFactorization r = measure_reference_factorization(system.A, metis);
  if (!r.ok) throw NumericalError("the limit's CHOLMOD factorization (" + r.ordering + ") failed: " + r.message);
  return {{"plain_assembly", plain},          {"analysis", r.analysis_seconds}, {"factorization", r.factorization_seconds},
          {"factor_bytes", r.factor_bytes},   {"matrix_bytes", matrix_bytes},   {"ordering", r.ordering}};
}

/// One size: the solve and the limit (AMD, METIS) each measured `repeat` times in fresh
/// processes, taken in turn (solve, AMD, METIS, solve, ...) so that a machine that slows down
/// or speeds up meanwhile affects both alike; the fastest solve (by its wall time), the fastest
/// analysis + factorization of each ordering and the fastest plain assembly are kept.
LimitRow measure(const Scene& scene, int n, int repeat) {
  auto factor_seconds = [](const nlohmann::json& l) {
    return l.at("analysis").get<double>() + l.at("factorization").get<double>();
  };
  nlohmann::json solve;
  std::map<bool, nlohmann::json> limit;  // by METIS
  double plain = std::numeric_limits<double>::infinity();
  for (int k = 0; k < repeat; ++k) {
    nlohmann::json run = in_child([&] { return measure_solve(scene); });
    if (k == 0 || run.at("wall").get<double>() < solve.at("wall").get<double>()) solve = std::move(run);
    for (bool metis : {false, true}) {
      nlohmann::json l = in_child([&] { return measure_limit(scene, metis); });
      plain = std::min(plain, l.at("plain_assembly").get<double>());
      if (k == 0 || factor_seconds(l) < factor_seconds(limit.at(metis))) limit[metis] = std::move(l);
    }
  }
  LimitRow row;
  row.n = n;
  row.stage = solve.at("stages").get<std::map<std::string, double>>();
  row.dofs = solve.at("dofs");
  row.contact_nodes = solve.at("contact_nodes");
  row.status = solve.at("status");
  row.peak_rss = solve.at("peak_rss");
  row.solve = solve.at("wall");
  row.plain_assembly = plain;
  const bool metis = factor_seconds(limit.at(true)) < factor_seconds(limit.at(false));
  const nlohmann::json& best = limit.at(metis);
  row.ordering = best.at("ordering");
  row.analysis = best.at("analysis");
  row.factorization = best.at("factorization");
  row.factor_bytes = best.at("factor_bytes");
  row.matrix_bytes = best.at("matrix_bytes");
  row.alternative[limit.at(!metis).at("ordering")] = factor_seconds(limit.at(!metis));
  return row;
}

/// One ratio of a row against its target.
struct Ratio {
  const char* key;    // its name in limit.json
  const char* label;  // its name in the table
  double target;
  double value;
};

/// Every ratio of a row, in the order of the table.
std::vector<Ratio> ratios(const LimitRow& r) {
  const double factor = r.analysis + r.factorization;
  const auto& st = r.stage;
  return {{"solve_over_limit", "solve/limit", 1.3, r.solve / (r.plain_assembly + factor)},
          {"mesh_over_factorization", "mesh/factor", 0.05, st.at("mesh") / factor},
          {"assembly_over_plain", "assembly/plain", 1.5, st.at("assembly") / r.plain_assembly},
          {"condensation_over_factorization", "condens/factor", 1.2, st.at("condensation") / factor},
          {"minimize_back_substitution_margin_over_factorization", "min+back+margin/f", 0.1,
           (st.at("minimize") + st.at("back_substitution") + st.at("margin")) / factor},
          {"outputs_over_total", "outputs/total", 0.15,
           st.at("outputs") / (r.solve - st.at("result_json") + st.at("outputs"))},
          {"peak_rss_over_factor_and_matrix", "peak/(L+A)", 1.5, r.peak_rss / (r.factor_bytes + r.matrix_bytes)}};
}

nlohmann::json row_json(const LimitRow& r) {
  nlohmann::json j{{"n", r.n},
                   {"dofs", r.dofs},
                   {"contact_nodes", r.contact_nodes},
                   {"status", r.status},
                   {"stages", r.stage},
                   {"solve", r.solve},
                   {"peak_rss_bytes", r.peak_rss},
                   {"limit",
                    {{"plain_assembly", r.plain_assembly},
                     {"ordering", r.ordering},
                     {"analysis", r.analysis},
                     {"factorization", r.factorization},
                     {"other_orderings", r.alternative},
                     {"factor_bytes", r.factor_bytes},
                     {"matrix_bytes", r.matrix_bytes}}}};
  for (const Ratio& q : ratios(r)) j["ratios"][q.key] = q.value;
  return j;
}

/// The scene of --limit: the scene file read as hemivem solve reads it, on cholmod; its mesh
/// must come from the squares generator.
Scene limit_scene(const BenchOptions& o) {
  SolveOptions so;
  so.scene = o.scene;
  so.tolerance = o.tolerance;
  so.set = o.set;
  so.linear = "cholmod";
  Scene base = load_scene(so);
  const bool solid = base.dimension() == 3;
  if (!base.mesh.file.empty() || base.mesh.generator != (solid ? "cubes" : "squares"))
    throw InputError(solid ? "bench --limit measures a solid against a plain Q1 assembly on boxes: the scene's mesh "
                             "must be generated by 'cubes'"
                           : "bench --limit measures against a plain Q1 assembly on squares: the scene's mesh must be "
                             "generated by 'squares'",
                     "mesh.generator");
  return base;
}

/// The seconds of each stage per size, against the limit.
void print_limit_table(std::ostream& out, const Scene& base, const BenchOptions& o, const std::vector<LimitRow>& table) {
  out << "hemivem bench --limit: " << base.title << ", cholmod + " << base.solver.minimizer
      << "; limit = plain Q1 assembly + one CHOLMOD analysis and factorization of the same A"
      << (o.repeat > 1 ? "; the fastest of " + std::to_string(o.repeat) + " measurements of each" : std::string()) << "\n\n";
  out << std::left << std::setw(6) << "n" << std::right << std::setw(9) << "dofs" << std::setw(8) << "mesh"
      << std::setw(10) << "assembly" << std::setw(8) << "condens" << std::setw(8) << "minim" << std::setw(8)
      << "back" << std::setw(8) << "result" << std::setw(8) << "solve" << std::setw(8) << "margin" << std::setw(9)
      << "outputs" << std::setw(9)
      << "plain" << std::setw(10) << "factor" << std::setw(9) << "peakMB" << "\n";
  for (const auto& r : table) {
    out << std::left << std::setw(6) << r.n << std::right << std::setw(9) << r.dofs;
    for (const char* k : {"mesh", "assembly", "condensation", "minimize", "back_substitution", "result_json"})
      out << std::setw(std::string(k) == "assembly" ? 10 : 8) << fixed(r.stage.at(k), 2);
    out << std::setw(8) << fixed(r.solve, 2) << std::setw(8) << fixed(r.stage.at("margin"), 2) << std::setw(9)
        << fixed(r.stage.at("outputs"), 2) << std::setw(9) << fixed(r.plain_assembly, 2) << std::setw(10)
        << (fixed(r.analysis + r.factorization, 2) + (r.ordering == "amd" ? "a" : "m")) << std::setw(9)
        << fixed(r.peak_rss / 1048576.0, 0) << "\n";
  }
}

/// Each ratio per size, with its target.
void print_ratios(std::ostream& out, const std::vector<LimitRow>& table) {
  out << "\nratios (target)        ";
  for (const auto& r : table) out << std::setw(9) << ("n=" + std::to_string(r.n));
  out << "\n";
  const std::size_t count = ratios(table.front()).size();
  for (std::size_t q = 0; q < count; ++q) {
    const Ratio first = ratios(table.front())[q];
    std::ostringstream target;
    target << first.target;
    out << std::left << std::setw(23) << (std::string(first.label) + " (" + target.str() + ")") << std::right;
    for (const auto& r : table) {
      const double v = ratios(r)[q].value;
      out << std::setw(9) << (std::isfinite(v) ? fixed(v, 2) : "-");
    }
    out << "\n";
  }
}


}  // namespace

int run_bench_limit(const BenchOptions& o, const std::vector<int>& sizes, std::ostream& out, std::ostream& err) {
  const std::vector<std::string> built = available_factorizations();
  if (std::find(built.begin(), built.end(), "cholmod") == built.end())
    throw InputError("the limit is one CHOLMOD factorization, and the cholmod engine was not built", "--limit");
  if (o.repeat < 1) throw InputError("give at least one measurement per size", "--repeat");
  const Scene base = limit_scene(o);
  std::vector<int> ns = sizes;
  if (ns.empty()) ns = base.dimension() == 3 ? std::vector<int>{16, 24, 32} : std::vector<int>{128, 256, 512};
  std::sort(ns.begin(), ns.end());
  ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
  std::vector<Scene> scenes;
  for (int n : ns) {
    Scene s = base;
    apply_override(s, "mesh.n=" + std::to_string(n));
    scenes.push_back(std::move(s));
  }
  const bool progress = o.verbosity >= 1;
  nlohmann::json rows = nlohmann::json::array();
  std::vector<LimitRow> table;
  for (std::size_t k = 0; k < ns.size(); ++k) {
    if (progress) err << "hemivem bench --limit: n = " << ns[k] << " ... " << std::flush;
    table.push_back(measure(scenes[k], ns[k], o.repeat));
    rows.push_back(row_json(table.back()));
    if (progress) err << "done\n";
  }
  const nlohmann::json doc{{"schema", "hemivem-bench-limit/2"},
                           {"scene", base.source},
                           {"linear", "cholmod"},
                           {"minimizer", base.solver.minimizer},
                           {"repeat", o.repeat},
                           {"rows", rows}};
  OutputTransaction tx(o.out, {"limit.json"});  // the folder changes at once
  tx.write("limit.json", [&](std::ostream& os) { os << doc.dump(2) << "\n"; });
  (void)tx.commit();
  if (o.json) {
    out << doc.dump(2) << "\n";
    return kSuccess;
  }
  if (o.verbosity < 1) return kSuccess;
  print_limit_table(out, base, o, table);
  print_ratios(out, table);
  out << "\nseconds; solve: the wall time from the scene to result.json (its stages before it); margin (inside the\n"
         "condensation) and outputs (all files) timed again after it; factor: analysis + factorization with\n"
         "CHOLMOD's faster ordering (a: AMD, m: METIS); peak: the peak RSS of the solve's process; wrote "
      << (fs::path(o.out) / "limit.json").string() << "\n";
  return kSuccess;
}

}  // namespace hemivem::cli
