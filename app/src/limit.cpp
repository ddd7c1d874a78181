// The limit of a scene: every stage of a cholmod solve against a plain Q1 assembly and one
// CHOLMOD factorization of the same matrix, each measured in a fresh child process
// (hemivem/app/limit.hpp).
#include <hemivem/support/blas_threads.hpp>
#include <hemivem/app/limit.hpp>

#include <hemivem/app/outputs.hpp>
#include <hemivem/app/run.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/uniqueness.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <Eigen/Sparse>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <exception>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scene_setup.hpp"

namespace hemivem::app {

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

using Triplets = std::vector<Eigen::Triplet<double, int>>;

/// The lower triangle of the free dofs of one element's stiffness `Ke`, whose dof k is `d[k]`
/// (-1: prescribed), appended to `triplets`.
template <int N>
void add_lower(Triplets& triplets, const Eigen::Matrix<double, N, N>& Ke, const int (&d)[N]) {
  for (int q = 0; q < N; ++q)
    for (int p = 0; p < N; ++p)
      if (d[p] >= 0 && d[q] >= 0 && d[p] >= d[q]) triplets.emplace_back(d[p], d[q], Ke(p, q));
}

SparseMatrix from_triplets(const DofMap& dofs, const Triplets& triplets) {
  SparseMatrix A(dofs.num_free(), dofs.num_free());
  A.setFromTriplets(triplets.begin(), triplets.end());
  A.makeCompressed();
  return A;
}

void require_squares(const Mesh& mesh) {
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (mesh.element_size(e) != 4)
      throw InputError("the limit's plain assembly is the Q1 stiffness of squares: element " + std::to_string(e) +
                           " has " + std::to_string(mesh.element_size(e)) + " vertices",
                       "mesh.generator");
}

void require_boxes(const Mesh3D& mesh) {
  for (int c = 0; c < mesh.num_cells(); ++c)
    if (mesh.cell_vertices(c).size() != 8 || mesh.cell_faces(c).size() != 6)
      throw InputError("the limit's plain assembly is the Q1 stiffness of boxes: cell " + std::to_string(c) +
                           " is not a box",
                       "mesh.generator");
}

/// The Q1 plane-strain stiffness of an h x h square, its vertices counterclockwise from the
/// lower left (2 x 2 Gauss).
Eigen::Matrix<double, 8, 8> square_stiffness(double h, double lambda, double mu) {
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
  return Ke;
}

/// The Q1 stiffness of a box of the given size, its corners a = i + 2 j + 4 k (2 x 2 x 2 Gauss).
Eigen::Matrix<double, 24, 24> box_stiffness(const Vec3& size, double lambda, double mu) {
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
  return Ke;
}

/// The plain assembly on squares, the mesh checked by the caller: one element's stiffness
/// (every element is the first one's size), added for every element.
SparseMatrix assemble_squares(const Mesh& mesh, const DofMap& dofs, double lambda, double mu) {
  const auto first = mesh.element(0);
  const auto Ke = square_stiffness((mesh.vertex(first[1]) - mesh.vertex(first[0])).norm(), lambda, mu);
  const std::vector<int> free_index = dofs.free_index_table();  // a table, as any whole assembly's
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_elements()) * 36);
  int d[8];
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto v = mesh.element(e);
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 2; ++c) d[2 * a + c] = free_index[static_cast<std::size_t>(2 * v[static_cast<std::size_t>(a)] + c)];
    add_lower(triplets, Ke, d);
  }
  return from_triplets(dofs, triplets);
}

/// The plain assembly on boxes, the mesh checked by the caller: the vertices of a box of
/// make_cubes, sorted by id, are its corners a = i + 2 j + 4 k.
SparseMatrix assemble_boxes(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu) {
  const auto& first = mesh.cell_vertices(0);
  const auto Ke = box_stiffness(mesh.vertex(first[7]) - mesh.vertex(first[0]), lambda, mu);
  const std::vector<int> free_index = dofs.free_index_table();
  Triplets triplets;
  triplets.reserve(static_cast<std::size_t>(mesh.num_cells()) * 300);
  int d[24];
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& v = mesh.cell_vertices(c);
    for (int a = 0; a < 8; ++a)
      for (int k = 0; k < 3; ++k) d[3 * a + k] = free_index[static_cast<std::size_t>(3 * v[static_cast<std::size_t>(a)] + k)];
    add_lower(triplets, Ke, d);
  }
  return from_triplets(dofs, triplets);
}

}  // namespace

SparseMatrix plain_q1_matrix(const Mesh& mesh, const DofMap& dofs, double lambda, double mu) {
  require_squares(mesh);
  return assemble_squares(mesh, dofs, lambda, mu);
}

SparseMatrix plain_q1_matrix(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu) {
  require_boxes(mesh);
  return assemble_boxes(mesh, dofs, lambda, mu);
}

double plain_q1_assembly_seconds(const Mesh& mesh, const DofMap& dofs, double lambda, double mu) {
  require_squares(mesh);
  const auto start = Clock::now();
  const SparseMatrix A = assemble_squares(mesh, dofs, lambda, mu);
  return since(start);
}

double plain_q1_assembly_seconds(const Mesh3D& mesh, const DofMap& dofs, double lambda, double mu) {
  require_boxes(mesh);
  const auto start = Clock::now();
  const SparseMatrix A = assemble_boxes(mesh, dofs, lambda, mu);
  return since(start);
}

namespace {

/// Forks from the calling thread, runs `work` in the child and returns the JSON it produced. An
/// exception in the child comes back as the same kind of error (an InputError with its key).
nlohmann::json fork_and_run(const std::function<nlohmann::json()>& work) {
  int fd[2];
  if (::pipe(fd) != 0) throw NumericalError("the limit: cannot create a pipe");
  const pid_t pid = ::fork();
  if (pid < 0) throw NumericalError("the limit: cannot start a child process");
  if (pid == 0) {
    ::close(fd[0]);
    nlohmann::json j;
    try {
      j = work();
    } catch (const InputError& e) {
      std::string message = e.what();
      const std::string prefix = e.where() + ": ";
      if (!e.where().empty() && message.compare(0, prefix.size(), prefix) == 0) message.erase(0, prefix.size());
      j = {{"error", "input"}, {"message", message}, {"where", e.where()}};
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
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!WIFEXITED(status) || text.empty())
    throw NumericalError("the limit: the measuring process ended without a result (out of memory?)");
  nlohmann::json j = nlohmann::json::parse(text);
  if (j.contains("error")) {
    const std::string message = j.at("message").get<std::string>();
    if (j.at("error") == "input") throw InputError(message, j.value("where", std::string()));
    throw NumericalError(message);
  }
  return j;
}

/// Runs `work` in a fresh child process and returns the JSON it produced: every measurement
/// starts, as `hemivem solve` does, with a fresh heap, and the peak memory is the child's own.
/// The fork is made from a new thread, so the child's one thread carries none of the caller's
/// OpenMP state: a libgomp thread pool of a thread that has run a parallel region does not
/// survive a fork (the child would wait for its threads forever).
nlohmann::json in_child(const std::function<nlohmann::json()>& work) {
  nlohmann::json result;
  std::exception_ptr error;
  std::thread forking([&] {
    try {
      result = fork_and_run(work);
    } catch (...) {
      error = std::current_exception();
    }
  });
  forking.join();
  if (error) std::rethrow_exception(error);
  return result;
}

/// The record of a solve started at `start`: its stages up to result.json, written by
/// `write(dir, false)`, its wall time, then the uniqueness margin (which runs inside the
/// condensation) and every output (`write(dir, true)`), each timed on its own.
template <class Solved>
nlohmann::json solve_record(Clock::time_point start, const Solved& s, const ReducedProblem& reduced,
                            const std::function<void(const fs::path&, bool all)>& write) {
  std::map<std::string, double> stage;
  stage["mesh"] = s.mesh_seconds;
  for (const char* k :
       {"setup", "assembly", "condensation", "condition", "minimize", "back_substitution", "post_process", "release",
        "estimate"}) {
    const auto it = s.solution.timings.find(k);
    stage[k] = it == s.solution.timings.end() ? 0.0 : it->second;
  }
  const fs::path dir = fs::temp_directory_path() / ("hemivem-limit-" + std::to_string(::getpid()));
  auto t = Clock::now();
  write(dir / "result-only", false);
  stage["result_json"] = since(t);
  const double wall = since(start);
  t = Clock::now();
  if (!reduced.laws.empty()) (void)uniqueness_margin(reduced.S, reduced.w, reduced.laws.front()->alpha());
  stage["margin"] = since(t);
  t = Clock::now();
  write(dir / "all", true);
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

/// One solve with cholmod (in this process), timed as `hemivem solve` with
/// `output.write = ["result-json"]`: from the scene to result.json, through run_scene.
nlohmann::json measure_solve(const Scene& scene) {
  const auto start = Clock::now();
  ReducedProblem reduced;
  RunOptions options;
  options.reduced = &reduced;
  const SceneRun run = run_scene(scene, std::move(options));
  const std::vector<std::string> result_only{"result.json"};
  auto write = [&](const fs::path& dir, bool all) { (void)run.write(dir, all ? nullptr : &result_only); };
  return run.dimension() == 3 ? solve_record(start, *run.solid(), reduced, write)
                              : solve_record(start, *run.plane(), reduced, write);
}

/// The limit of a built problem (in this process): the plain assembly first, its memory as
/// fresh as a program's, then one CHOLMOD factorization of hemivem's A with the given ordering.
template <class Built>
nlohmann::json limit_of(const Built& built, bool metis) {
  const auto& elasticity = built.problem.elasticity;
  const Lame lame = elasticity.materials.lame(built.mesh.region(0));
  const double plain =
      plain_q1_assembly_seconds(built.mesh, make_dof_map(built.mesh, elasticity.dirichlet), lame.lambda, lame.mu);
  const LinearSystem system = assemble(elasticity);
  const double matrix_bytes = static_cast<double>(system.A.nonZeros()) * (sizeof(double) + sizeof(int)) +
                              static_cast<double>(system.A.outerSize() + 1) * sizeof(int);
  const ReferenceFactorization r = measure_reference_factorization(system.A, metis);
  if (!r.ok) throw NumericalError("the limit's CHOLMOD factorization (" + r.ordering + ") failed: " + r.message);
  return {{"plain_assembly", plain},        {"analysis", r.analysis_seconds}, {"factorization", r.factorization_seconds},
          {"factor_bytes", r.factor_bytes}, {"matrix_bytes", matrix_bytes},   {"ordering", r.ordering}};
}

nlohmann::json measure_limit(const Scene& scene, bool metis) {
  const SingleThreadedRun one_thread;  // as the solves it is compared with (docs/performance.md, "Threads")
  if (scene.dimension() == 3) return limit_of(*build_problem<3>(scene), metis);
  return limit_of(*build_problem(scene), metis);
}

double factor_seconds(const nlohmann::json& l) {
  return l.at("analysis").get<double>() + l.at("factorization").get<double>();
}

/// A row from the fastest solve, the fastest limit of each ordering (by METIS) and the fastest
/// plain assembly.
LimitRow row_of(int n, const nlohmann::json& solve, const std::map<bool, nlohmann::json>& limit, double plain) {
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

/// One size, measured `repeat` times in turn (solve, AMD, METIS, solve, ...).
LimitRow measure(const Scene& scene, int n, int repeat) {
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
  return row_of(n, solve, limit, plain);
}


}  // namespace

std::vector<int> limit_default_sizes(int dimension) {
  return dimension == 3 ? std::vector<int>{16, 24, 32} : std::vector<int>{128, 256, 512};
}

std::vector<LimitRatio> limit_ratios(const LimitRow& r) {
  const double factor = r.analysis + r.factorization;
  auto st = [&r](const char* k) {
    const auto it = r.stage.find(k);
    return it == r.stage.end() ? std::numeric_limits<double>::quiet_NaN() : it->second;
  };
  return {{"solve_over_limit", "solve/limit", 1.3, r.solve / (r.plain_assembly + factor)},
          {"mesh_over_factorization", "mesh/factor", 0.05, st("mesh") / factor},
          {"assembly_over_plain", "assembly/plain", 1.5, st("assembly") / r.plain_assembly},
          {"condensation_over_factorization", "condens/factor", 1.2, st("condensation") / factor},
          {"minimize_back_substitution_margin_over_factorization", "min+back+margin/f", 0.1,
           (st("minimize") + st("back_substitution") + st("margin")) / factor},
          {"outputs_over_total", "outputs/total", 0.15, st("outputs") / (r.solve - st("result_json") + st("outputs"))},
          {"peak_rss_over_factor_and_matrix", "peak/(L+A)", 1.5, r.peak_rss / (r.factor_bytes + r.matrix_bytes)}};
}

void check_limit_options(const LimitOptions& o) {
  const std::vector<std::string> built = available_factorizations();
  if (std::find(built.begin(), built.end(), "cholmod") == built.end())
    throw InputError("the limit is one CHOLMOD factorization, and the cholmod engine was not built", o.keys.limit);
  if (o.repeat < 1)
    throw InputError("give at least one measurement per size, got " + std::to_string(o.repeat), o.keys.repeat);
  for (int n : o.sizes)
    if (n < 1) throw InputError("mesh sizes must be >= 1, got " + std::to_string(n), o.keys.sizes);
}

LimitPlan plan_limit(const Scene& scene, const LimitOptions& options) {
  check_limit_options(options);
  LimitPlan plan{scene, options, {}};
  apply_overrides(plan.base, {"solver.linear=\"cholmod\""});
  const bool solid = plan.base.dimension() == 3;
  if (!plan.base.mesh.file.empty() || plan.base.mesh.generator != (solid ? "cubes" : "squares"))
    throw InputError(solid ? "the limit measures a solid against a plain Q1 assembly on boxes: the scene's mesh "
                             "must be generated by 'cubes'"
                           : "the limit measures against a plain Q1 assembly on squares: the scene's mesh must be "
                             "generated by 'squares'",
                     "mesh.generator");
  std::vector<int>& ns = plan.options.sizes;
  if (ns.empty()) ns = limit_default_sizes(plan.base.dimension());
  std::sort(ns.begin(), ns.end());
  ns.erase(std::unique(ns.begin(), ns.end()), ns.end());
  for (int n : ns) {
    Scene s = plan.base;
    try {
      apply_override(s, "mesh.n=" + std::to_string(n));
    } catch (const InputError& e) {
      throw InputError(e.what(), options.keys.sizes);
    }
    detail::require_memory_of(s, options.keys.sizes);
    plan.scenes.push_back(std::move(s));
  }
  return plan;
}

LimitResult run_limit(const LimitPlan& plan) {
  LimitResult result{plan, {}};
  const LimitOptions& o = plan.options;
  for (std::size_t k = 0; k < plan.scenes.size(); ++k) {
    const int n = o.sizes[k];
    if (o.size_started) o.size_started(n);
    result.rows.push_back(measure(plan.scenes[k], n, o.repeat));
    if (o.size_done) o.size_done(result.rows.back());
  }
  return result;
}

LimitResult run_limit(const Scene& scene, const LimitOptions& options) { return run_limit(plan_limit(scene, options)); }

nlohmann::json limit_row_json(const LimitRow& r) {
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
  for (const LimitRatio& q : limit_ratios(r)) j["ratios"][q.key] = q.value;
  return j;
}

nlohmann::json limit_json(const LimitResult& result) {
  nlohmann::json rows = nlohmann::json::array();
  for (const LimitRow& r : result.rows) rows.push_back(limit_row_json(r));
  const Scene& base = result.plan.base;
  return {{"schema", "hemivem-bench-limit/4"},
          {"scene", base.source},
          {"linear", "cholmod"},
          {"minimizer", base.solver.minimizer},
          {"repeat", result.plan.options.repeat},
          {"rows", rows}};
}

}  // namespace hemivem::app
