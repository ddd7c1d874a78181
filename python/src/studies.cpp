// hemivem.check, hemivem.study, hemivem.bench and hemivem.limit: the computations of `hemivem
// check`, `hemivem study`, `hemivem bench` and `hemivem bench --limit` (app::run_check,
// app::run_study, app::run_bench, app::run_limit) as dicts of their JSON reports, with NumPy
// arrays for the numbers one plots.
#include "bindings.hpp"

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

#include <hemivem/app/bench.hpp>
#include <hemivem/app/check.hpp>
#include <hemivem/app/limit.hpp>
#include <hemivem/app/study.hpp>

namespace hemivem::python {

namespace {

using PairList = std::optional<std::vector<std::pair<std::string, std::string>>>;

/// The scene of a call, with the tolerance of every solve when given (as --tol).
Scene studies_scene(const py::object& scene_arg, const std::string& function, std::optional<double> tolerance) {
  Scene scene = scene_argument(scene_arg, function);
  if (tolerance) {
    std::ostringstream v;
    v << std::setprecision(17) << *tolerance;
    apply_overrides(scene, {"solver.tolerance=" + v.str()});
  }
  return scene;
}

/// The pairs asked for, or every built pair but those of mumps-mpi (which runs under an MPI
/// launcher, never inside Python) and of PETSc's Krylov engines (which run in the command
/// only): the condensed route's pairs and eigen-cg+ssn, the full-space route's.
std::vector<app::Pair> pairs_of(const PairList& given) {
  std::vector<app::Pair> pairs;
  if (given) {
    for (const auto& [linear, minimizer] : *given) {
      check_linear_engine(linear, "pairs");
      pairs.push_back({linear, minimizer});
    }
    if (pairs.empty()) throw InputError("give at least one (linear, minimizer) pair", "pairs");
    return pairs;
  }
  for (const auto& p : app::available_pairs())
    if (p.linear != "mumps-mpi") pairs.push_back(p);
  return pairs;
}

py::object to_dict(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

/// `rows` x `cols` of a JSON matrix whose nulls are NaN.
py::array_t<double> matrix(const std::vector<std::vector<double>>& m) {
  const auto n = static_cast<py::ssize_t>(m.size());
  py::array_t<double> a({n, n});
  auto v = a.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i)
    for (py::ssize_t k = 0; k < n; ++k) v(i, k) = m[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
  return a;
}

/// Runs `compute` without the GIL; `watch` is polled by the computation's callbacks, which
/// throw Interrupted to leave it; Ctrl-C then raises KeyboardInterrupt.
template <class F>
void without_gil(SignalWatch& watch, F&& compute) {
  try {
    py::gil_scoped_release release;
    compute();
  } catch (const Interrupted&) {
  }
  watch.raise_if_interrupted();
}

py::object check(const py::object& scene_arg, double agree, std::optional<double> tolerance, const PairList& pairs) {
  const Scene scene = studies_scene(scene_arg, "hemivem.check", tolerance);
  app::CheckOptions o;
  o.agree = agree;
  o.pairs = pairs_of(pairs);
  SignalWatch watch;
  o.done = [&](const app::PairRun&) {
    if (watch.poll()) throw Interrupted{};
  };
  app::CheckResult r;
  without_gil(watch, [&] { r = app::run_check(scene, o); });
  py::dict d = to_dict(app::check_json(scene, r));
  d["differences"] = matrix(r.comparison.diff);
  py::list list = d["pairs"];
  for (std::size_t i = 0; i < r.runs.size(); ++i) {
    list[i]["displacement"] = copy(r.runs[i].u);
    if (r.path_t.empty()) continue;
    py::list steps;  // a loading path: the displacement of every step
    for (const auto& u : r.runs[i].path_u) steps.append(copy(u));
    list[i]["path_displacements"] = steps;
  }
  return d;
}

py::object study(const py::object& scene_arg, const std::vector<int>& n, int ref,
                 const std::optional<std::filesystem::path>& out) {
  const Scene scene = studies_scene(scene_arg, "hemivem.study", std::nullopt);
  app::StudyOptions o;
  o.n = n;
  o.ref = ref;
  (void)app::study_sizes(scene, o);
  SignalWatch watch;
  o.solved = [&](const app::StudySolveInfo&) {
    if (watch.poll()) throw Interrupted{};
  };
  app::StudyResult r;
  app::StudyFiles files;
  without_gil(watch, [&] {
    r = app::run_study(scene, o);
    if (out) files = app::write_study(*out, scene, o, r);
  });
  py::dict d = to_dict(app::study_json(scene, o, r));
  std::vector<double> h, error;
  for (const auto& row : r.rows) h.push_back(row.h), error.push_back(row.error);
  d["h"] = copy(h);
  d["error"] = copy(error);
  if (out) {
    d["files"] = files.written;
    d["warnings"] = files.warnings;
  }
  for (const auto& w : files.warnings)  // a figure not drawn (also in study.json's warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return d;
}

struct BenchKeywords {
  std::vector<int> n;
  std::optional<int> ref, levels;
  std::optional<double> reference_energy, tolerance;
  PairList pairs;
};

py::object bench(const py::object& scene_arg, const BenchKeywords& k, const std::optional<std::filesystem::path>& out) {
  app::BenchOptions o;
  o.n = k.n;
  o.ref = k.ref;
  o.levels = k.levels;
  o.reference_energy = k.reference_energy;
  app::check_bench_options(o);
  const Scene scene = studies_scene(scene_arg, "hemivem.bench", k.tolerance);
  o.pairs = pairs_of(k.pairs);
  SignalWatch watch;
  o.progress.pair_done = [&](const app::PairRun&, int) {
    if (watch.poll()) throw Interrupted{};
  };
  o.progress.refinement = [&](const app::RefinementPoint&) {
    if (watch.poll()) throw Interrupted{};
  };
  const app::BenchPlan plan = app::plan_bench(scene, o);
  nlohmann::json j;
  std::vector<std::string> warnings;
  without_gil(watch, [&] {
    const app::BenchResult r = app::run_bench(plan);
    if (!out) {
      j = app::bench_json(r);
      return;
    }
    app::BenchFiles files = app::write_bench(*out, r);
    j = std::move(files.json);
    warnings = std::move(files.warnings);
  });
  for (const auto& w : warnings)  // a plot not drawn (also in bench.json's warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  return to_dict(j);
}

py::object limit(const py::object& scene_arg, const std::vector<int>& n, int repeat, std::optional<double> tolerance) {
  app::LimitOptions o;
  o.sizes = n;
  o.repeat = repeat;
  app::check_limit_options(o);
  const Scene scene = studies_scene(scene_arg, "hemivem.limit", tolerance);
  SignalWatch watch;
  o.size_done = [&](const app::LimitRow&) {
    if (watch.poll()) throw Interrupted{};
  };
  const app::LimitPlan plan = app::plan_limit(scene, o);
  nlohmann::json j;
  without_gil(watch, [&] { j = app::limit_json(app::run_limit(plan)); });
  return to_dict(j);
}

constexpr const char* kCheckDoc = R"doc(Solves a scene with every pair of engines and compares them, as `hemivem check --json`
does (app::run_check): returns the dict of that report (schema hemivem-check/5: pairs,
differences, uniqueness_margin, verdict, exit_code ...), with "differences" a NumPy matrix
(NaN where a pair failed) and each pair's "displacement" (2 or 3 per vertex) a NumPy array.
A loading path (a [path] table, or Coulomb friction) is solved by every pair along the whole
path and compared at every step ("path": the steps, each with its largest difference); each
pair's "path_displacements" lists every step's displacement, "displacement" being the last.

scene: a Scene (default: Scene.default()), a path to a scene file or TOML text. agree: the
largest relative difference of u accepted between converged pairs (--agree). tolerance:
solver.tolerance of every pair (--tol). pairs: a list of (linear, minimizer) names; default
every built pair but mumps-mpi's, which run under an MPI launcher only: the condensed route's
pairs and the full-space route's, a Krylov engine with ssn ("petsc-gamg", "petsc-hypre",
"eigen-cg"; a Krylov engine takes ssn only). Each pair's
"route" is "condensed" or "full_space"; a full-space pair whose route refuses the scene (an
InputError of the route) has the status "refused", its reason in "message", and is not a
failure (the scene's "refused" lists them). Runs without the GIL; Ctrl-C is honoured after
each pair.)doc";

constexpr const char* kStudyDoc = R"doc(The convergence study of the paper's Table 1, as `hemivem study --json` (app::run_study):
the scene on N x N squares for each N of `n` and on `ref` x `ref` squares, the relative energy
error of each against the reference. Returns study.json's dict (schema hemivem-study/2) with
"h" and "error" as NumPy arrays (coarse to fine). out: a folder to write study.csv,
study.json and study.png into, as the command does ("files" lists them). InputError for a
scene that is not on squares (mesh.generator) or an N that does not divide ref. Runs without
the GIL; Ctrl-C is honoured after each solve.)doc";

constexpr const char* kBenchDoc = R"doc(Every pair of engines timed against its error for several mesh sizes, and the refinement
study, as `hemivem bench --json` (app::run_bench). Returns bench.json's dict (schema
hemivem-bench/6; a loading path is measured at its last step, "path" says so). n, ref, levels, reference_energy, tolerance: as the flags --n, --ref,
--levels, --reference-energy, --tol (None: the defaults of the scene's dimension). pairs: as
for check. out: a folder to write bench.csv, bench.json, bench.png and bench-error.png into
(the dict then names the plots, as the file does). Runs without the GIL; Ctrl-C is honoured
after each pair and each refinement step.)doc";

constexpr const char* kLimitDoc = R"doc(Every stage of a cholmod solve against the limit of the same job on this machine, as
`hemivem bench --limit --json` (app::run_limit): for each mesh size, the solve (the scene's
minimizer on cholmod) and the limit (a plain Q1 triplet assembly of the same sparsity and one
CHOLMOD analysis and factorization of hemivem's A, with AMD and with METIS), each measured in a
fresh child process. Returns limit.json's dict (schema hemivem-bench-limit/4): per row n, dofs,
contact_nodes, status, stages (seconds), solve, peak_rss_bytes (of the child, which starts as a
copy of this process), limit {plain_assembly, ordering, analysis, factorization,
other_orderings, factor_bytes, matrix_bytes} and ratios (solve_over_limit, ...).

scene: a Scene (default: Scene.default()), a path to a scene file or TOML text; its mesh must
come from the squares generator (a solid's: cubes), InputError at mesh.generator otherwise.
n: the mesh sizes (default 128, 256, 512; a solid: 16, 24, 32). repeat: measurements per size,
the fastest of each kept. tolerance: solver.tolerance (--tol). InputError without the cholmod
engine. Runs without the GIL; Ctrl-C is honoured after each size.)doc";

}  // namespace

void register_studies(py::module_& m) {
  m.def("check", &check, py::arg("scene") = py::none(), py::kw_only(), py::arg("agree") = 1e-6,
        py::arg("tolerance") = py::none(), py::arg("pairs") = py::none(), kCheckDoc);
  m.def("study", &study, py::arg("scene") = py::none(), py::kw_only(),
        py::arg("n") = std::vector<int>{4, 8, 16, 32, 64}, py::arg("ref") = 256, py::arg("out") = py::none(), kStudyDoc);
  m.def(
      "bench",
      [](const py::object& scene, std::vector<int> n, std::optional<int> ref, std::optional<int> levels,
         std::optional<double> reference_energy, std::optional<double> tolerance, PairList pairs,
         const std::optional<std::filesystem::path>& out) {
        return bench(scene, {std::move(n), ref, levels, reference_energy, tolerance, std::move(pairs)}, out);
      },
      py::arg("scene") = py::none(), py::kw_only(), py::arg("n") = std::vector<int>{}, py::arg("ref") = py::none(),
      py::arg("levels") = py::none(), py::arg("reference_energy") = py::none(), py::arg("tolerance") = py::none(),
      py::arg("pairs") = py::none(), py::arg("out") = py::none(), kBenchDoc);
  m.def("limit", &limit, py::arg("scene") = py::none(), py::kw_only(), py::arg("n") = std::vector<int>{},
        py::arg("repeat") = 1, py::arg("tolerance") = py::none(), kLimitDoc);
}

}  // namespace hemivem::python
