#include <hemivem/app/engine_pairs.hpp>

#include <algorithm>
#include <type_traits>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <hemivem/path/path.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>

#include "scene_setup.hpp"

namespace hemivem::app {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

bool Pair::full_space() const { return is_krylov_solver(linear); }

std::vector<Pair> available_pairs() {
  std::vector<Pair> pairs;
  const std::vector<std::string> minimizers = available_minimizers();
  for (const auto& l : available_factorizations())
    for (const auto& m : minimizers) pairs.push_back({l, m});
  // the full-space route's method is ssn's Newton iteration in the whole space: one pair per engine
  if (std::find(minimizers.begin(), minimizers.end(), "ssn") != minimizers.end())
    for (const auto& k : available_krylov_solvers()) pairs.push_back({k, "ssn"});
  return pairs;
}

double max_abs(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

double max_abs_u(const PairRun& r) {
  double m = max_abs(r.u);
  for (const auto& u : r.path_u) m = std::max(m, max_abs(u));
  return m;
}

double step_difference(const PairRun& a, const PairRun& b, std::size_t k) {
  if (k >= a.path_u.size() || k >= b.path_u.size() || a.path_u[k].size() != b.path_u[k].size())
    return std::numeric_limits<double>::quiet_NaN();
  return max_abs(a.path_u[k] - b.path_u[k]);
}

double max_difference(const PairRun& a, const PairRun& b) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (a.u.size() != b.u.size() || a.path_u.size() != b.path_u.size()) return nan;
  double d = max_abs(a.u - b.u);
  for (std::size_t k = 0; k < a.path_u.size(); ++k) d = std::max(d, step_difference(a, b, k));  // NaN stays NaN
  return d;
}

double difference_scale(const std::vector<PairRun>& runs) {
  for (const auto& r : runs)
    if (r.pair.linear == "eigen" && r.pair.minimizer == "ssn" && r.converged && max_abs_u(r) > 0.0) return max_abs_u(r);
  double scale = 0.0;
  for (const auto& r : runs)
    if (r.converged) scale = std::max(scale, max_abs_u(r));
  return scale > 0.0 ? scale : 1.0;
}

double largest_margin(const std::vector<PairRun>& runs) {
  double margin = std::numeric_limits<double>::quiet_NaN();
  for (const auto& r : runs)
    if (!r.failed && !std::isnan(r.margin)) margin = std::isnan(margin) ? r.margin : std::max(margin, r.margin);
  return margin;
}

nlohmann::json pair_json(const PairRun& r) {
  return {{"linear", r.pair.linear},   {"minimizer", r.pair.minimizer}, {"route", r.pair.route()}, {"status", r.status},
          {"converged", r.converged}, {"message", r.message},         {"certificate", certificate_json(r.certificate)},
          {"iterations", r.iterations}, {"potential_energy", number(r.energy)}};
}

namespace {

/// The engines of a list of pairs: the linear engines in order of first use and one minimizer
/// of each name.
struct PairEngines {
  std::vector<std::string> linears;
  std::map<std::string, std::unique_ptr<NonsmoothMinimizer>> minimizers;
};

// the engines of every pair, before any work (an unknown name, or a Krylov engine paired with
// a minimizer other than ssn, is an InputError here)
PairEngines make_engines(const Scene& scene, const std::vector<Pair>& pairs) {
  PairEngines e;
  for (const auto& p : pairs) {
    if (std::find(e.linears.begin(), e.linears.end(), p.linear) == e.linears.end()) e.linears.push_back(p.linear);
    if (!e.minimizers.count(p.minimizer)) e.minimizers[p.minimizer] = make_scene_minimizer(scene, p.minimizer);
    if (p.full_space() && e.minimizers.at(p.minimizer)->name() != "ssn")
      throw InputError("the pair " + p.label() + " is not one: the full-space route (linear engine " + p.linear +
                           ") runs ssn's Newton iteration in the whole space; pair it with ssn, or " +
                           p.minimizer + " with a linear engine that factorizes",
                       "pairs");
  }
  for (const auto& l : e.linears) {
    if (is_krylov_solver(l)) {
      (void)make_krylov_solver(l);
      continue;
    }
    FactorizationOptions fo;
    fo.engine = l;
    (void)make_factorization(fo);
  }
  return e;
}

/// A full-space pair's InputError, caught: its route refuses the scene. The pair is refused
/// with the error's message (the scene's key named, rethrow_naming_scene_key); `first` keeps
/// the first refusal, thrown when every pair is refused.
void refuse_pair(PairRun& r, const Scene& scene, const InputError& e, std::exception_ptr& first) {
  try {
    detail::rethrow_naming_scene_key(scene, e);
  } catch (const InputError& named) {
    r.message = named.what();
    if (!first) first = std::current_exception();
  }
  r.failed = r.refused = true;
  r.status = "refused";
}

/// What the solution `s` of one pair (plane or 3D) says, into `r` (its timings completed with the
/// shared assembly); the solution's displacement is moved into `r`.
template <class Solution>
void record_solution(PairRun& r, Solution& s, const PairRuns& out, const ReducedProblem* reduced, double tolerance) {
  r.status = to_string(s.status);
  r.message = s.message;
  r.converged = s.converged();
  r.certificate = s.certificate;
  r.iterations = s.iterations();
  r.margin = s.uniqueness_margin;
  r.energy = s.energy;
  if constexpr (std::is_same_v<Solution, ContactSolution>) {
    r.rcond = s.rcond;
    r.condition = s.condition_estimate;
    if (std::any_of(s.contact.begin(), s.contact.end(), [](const ContactNode& c) { return c.friction_state != FrictionState::none; }))
      r.stick = static_cast<int>(std::count_if(s.contact.begin(), s.contact.end(),
                                               [](const ContactNode& c) { return c.friction_state == FrictionState::stick; }));
  }
  r.timings = s.timings;
  if (!r.pair.full_space()) {  // the shared assembly; a full-space pair's solver assembled its own
    r.timings["assembly"] = out.assembly_seconds;
    r.timings["total"] += out.assembly_seconds;
  }
  r.seconds = out.mesh_seconds + r.timings["total"];
  r.contact_nodes = static_cast<int>(s.contact.size());
  r.at_bound = static_cast<int>(
      std::count_if(s.contact.begin(), s.contact.end(), [](const auto& c) { return at_a_bound(c.state); }));
  r.unknowns = s.unknowns;
  r.vertices = out.vertices;
  if (r.converged && !s.u.allFinite()) {
    r.guarantee = false;
    r.broken = "converged with a non-finite displacement";
  } else if (r.converged && reduced && reduced->size() > 0) {
    const Certificate c = certificate(*reduced, s.minimizer->a, tolerance);
    if (!c.converged()) {
      r.guarantee = false;
      r.broken = "converged, but the recomputed certificate is " + certificate_text(c);
    }
  }
  r.u = std::move(s.u);
}

/// The pairs of one linear engine: it condenses the assembly once and each of its minimizers
/// runs on that condensation; a NumericalError (an InputError too, when the options say so)
/// fails them all.
void run_engine_pairs(const std::string& linear, const std::vector<Pair>& pairs, const PairEngines& engines,
                      const LinearSystem& system, const MinimizerOptions& mo, const PairRunOptions& o, PairRuns& out) {
  const bool has_contact = out.built3d ? !out.built3d->problem.parts.empty() : out.built->has_contact;
  std::vector<std::size_t> mine;  // the pairs of this engine, in order
  std::vector<const NonsmoothMinimizer*> minimizers;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (pairs[i].linear == linear) {
      mine.push_back(i);
      minimizers.push_back(engines.minimizers.at(pairs[i].minimizer).get());
    }
  std::vector<ContactSolution> sols;
  std::vector<ContactSolution3D> sols3d;
  std::string failure;
  ReducedProblem reduced;
  try {
    FactorizationOptions fo;
    fo.engine = linear;
    if (out.built3d)
      sols3d = solve_contact(out.built3d->problem, system, make_factorization(fo), minimizers, mo,
                                has_contact ? &reduced : nullptr);
    else
      sols = solve_contact(out.built->problem, system, make_factorization(fo), minimizers, mo,
                           has_contact ? &reduced : nullptr, o.estimate_condition);
    ++out.condensations;
  } catch (const NumericalError& e) {
    failure = e.what();
  } catch (const InputError& e) {
    if (!o.input_errors_fail_pairs) throw;
    failure = e.what();
  }
  for (std::size_t k = 0; k < mine.size(); ++k) {
    PairRun& r = out.runs[mine[k]];
    r.pair = pairs[mine[k]];
    r.mesh_seconds = out.mesh_seconds;
    if (!failure.empty()) {
      r.failed = true;
      r.message = failure;
      r.seconds = out.mesh_seconds + out.assembly_seconds;
    } else if (out.built3d) {
      record_solution(r, sols3d[k], out, has_contact ? &reduced : nullptr, mo.tolerance);
    } else {
      record_solution(r, sols[k], out, has_contact ? &reduced : nullptr, mo.tolerance);
    }
    if (o.done) o.done(r);
  }
}

/// A converged full-space pair's certificate, recomputed from the posed whole system at its
/// displacement (certify_full_space, as the route certifies): the guarantee of record_solution,
/// which has no reduced problem to recompute it from on this route.
void recheck_full_space(PairRun& r, const Condensation& posed, double tolerance) {
  if (!r.converged || !r.guarantee || r.u.size() == 0) return;
  const Certificate c = certify_full_space(posed, posed.rotated_free(r.u), tolerance).certificate;
  if (c.converged()) return;
  r.guarantee = false;
  r.broken = "converged, but the recomputed certificate is " + certificate_text(c);
}

/// The full-space pair `i` (a Krylov engine with ssn) on `problem`, static: BasicContactSolver
/// with that engine, which assembles and poses the problem itself and runs the route's Newton
/// iteration. A NumericalError fails the pair; an InputError refuses it (refuse_pair).
template <int dim>
void run_full_space_pair(const Scene& scene, const BasicContactProblem<dim>& problem, std::size_t i,
                         const std::vector<Pair>& pairs, const PairEngines& engines, const MinimizerOptions& mo,
                         const PairRunOptions& o, PairRuns& out, std::exception_ptr& refusal) {
  PairRun& r = out.runs[i];
  r.pair = pairs[i];
  r.mesh_seconds = out.mesh_seconds;
  const NonsmoothMinimizer* minimizers[] = {engines.minimizers.at(r.pair.minimizer).get()};
  try {
    BasicContactSolver<dim> solver(problem, make_krylov_solver(r.pair.linear), mo);
    BasicContactSolution<dim> solution = std::move(solver.run(minimizers).front());
    ++out.assemblies;
    if (solver.condensation()) ++out.posings;
    record_solution(r, solution, out, nullptr, mo.tolerance);
    if (solver.condensation()) recheck_full_space(r, *solver.condensation(), mo.tolerance);
  } catch (const NumericalError& e) {
    r.failed = true;
    r.message = e.what();
  } catch (const InputError& e) {
    refuse_pair(r, scene, e, refusal);
  }
  if (r.failed) r.seconds = out.mesh_seconds;
  if (o.done) o.done(r);
}

/// The path of one pair into `r`: its last step as a static solve (record_solution), converged
/// when every step is, with the status and message of the first step that is not, the
/// iterations of every step, each step's t and displacement, and the path's own timings
/// (minimize, a full-space pair's full_space: every step's; back_substitution: every step's
/// displacement).
template <int dim>
void record_path(PairRun& r, BasicPathSolution<dim>& path, const PairRuns& out, double tolerance) {
  record_solution(r, path.last, out, nullptr, tolerance);
  r.iterations = 0;
  for (auto& step : path.steps) {
    r.iterations += step.iterations;
    r.path_t.push_back(step.t);
    r.path_u.push_back(std::move(step.u));
  }
  const auto bad = std::find_if(path.steps.begin(), path.steps.end(), [](const auto& s) { return !s.converged(); });
  if (bad != path.steps.end()) {
    r.converged = false;
    r.status = to_string(bad->status);
    r.message = "step " + std::to_string(bad->index) + " (t = " + sci(bad->t, 3) + "): " + bad->message;
  }
  r.timings = path.timings;
  r.timings[r.pair.full_space() ? "full_space" : "minimize"] = path.timings["path"];
  r.timings["back_substitution"] = path.timings["frames"];
  r.seconds = out.mesh_seconds + r.timings["total"];
}

/// The path of one pair on `problem`: solve_path with its linear engine (a Krylov engine: the
/// full-space route), every step a frame (its displacement kept).
template <int dim>
BasicPathSolution<dim> solve_pair_path(const Scene& scene, BasicContactProblem<dim>& problem, const Pair& pair,
                                       const NonsmoothMinimizer& minimizer, const MinimizerOptions& mo) {
  BasicPathOptions<dim> po;
  po.minimizer = mo;
  po.frame = [](int) { return true; };
  if (pair.full_space())
    return solve_path(problem, make_krylov_solver(pair.linear), minimizer, scene_path_loading<dim>(scene), std::move(po));
  FactorizationOptions fo;
  fo.engine = pair.linear;
  return solve_path(problem, make_factorization(fo), minimizer, scene_path_loading<dim>(scene), std::move(po));
}

/// Every pair along the scene's path, one after the other on `problem` (each path sets the
/// problem to the t of each of its steps): each pair assembles and condenses (or poses) it
/// itself, every step is a frame. A NumericalError fails the pair; an InputError refuses a
/// full-space pair (refuse_pair) and fails a condensed one when the options say so, else it
/// is thrown naming the scene's key.
template <int dim>
void run_path_pairs(const Scene& scene, BasicContactProblem<dim>& problem, const std::vector<Pair>& pairs,
                    const PairEngines& engines, const MinimizerOptions& mo, const PairRunOptions& o, PairRuns& out,
                    std::exception_ptr& refusal) {
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    PairRun& r = out.runs[i];
    r.pair = pairs[i];
    r.mesh_seconds = out.mesh_seconds;
    try {
      BasicPathSolution<dim> path =
          solve_pair_path(scene, problem, pairs[i], *engines.minimizers.at(pairs[i].minimizer), mo);
      ++out.assemblies;
      ++(pairs[i].full_space() ? out.posings : out.condensations);
      record_path(r, path, out, mo.tolerance);
    } catch (const NumericalError& e) {
      r.failed = true;
      r.message = e.what();
    } catch (const InputError& e) {
      if (pairs[i].full_space()) {
        refuse_pair(r, scene, e, refusal);
      } else {
        if (!o.input_errors_fail_pairs) detail::rethrow_naming_scene_key(scene, e);
        r.failed = true;
        r.message = e.what();
      }
    }
    if (r.failed) r.seconds = out.mesh_seconds;
    if (o.done) o.done(r);
  }
}

/// The pairs of a static scene: the condensed pairs share one assembly (made when there is
/// one), each linear engine that factorizes condenses it once; each full-space pair runs on
/// its own (run_full_space_pair), in the order of the linear engines' first use.
void run_static_pairs(const Scene& scene, const std::vector<Pair>& pairs, const PairEngines& engines,
                      const MinimizerOptions& mo, const PairRunOptions& o, PairRuns& out, std::exception_ptr& refusal) {
  std::optional<LinearSystem> system;
  if (std::any_of(pairs.begin(), pairs.end(), [](const Pair& p) { return !p.full_space(); })) {
    const auto t_assembly = Clock::now();
    system = out.built3d ? assemble(out.built3d->problem.elasticity) : assemble(out.built->problem.elasticity);
    out.assembly_seconds = since(t_assembly);
    out.assemblies = 1;
  }
  for (const auto& linear : engines.linears) {
    if (!is_krylov_solver(linear)) {
      run_engine_pairs(linear, pairs, engines, *system, mo, o, out);
      continue;
    }
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].linear != linear) continue;
      if (out.built3d)
        run_full_space_pair<3>(scene, out.built3d->problem, i, pairs, engines, mo, o, out, refusal);
      else
        run_full_space_pair<2>(scene, out.built->problem, i, pairs, engines, mo, o, out, refusal);
    }
  }
}

}  // namespace

PairRuns run_pairs(const Scene& scene, const std::vector<Pair>& pairs, const PairRunOptions& o) {
  const PairEngines engines = make_engines(scene, pairs);
  MinimizerOptions mo;
  mo.tolerance = scene.solver.tolerance;
  mo.max_iterations = scene.solver.max_iterations;

  PairRuns out;
  const auto t_mesh = Clock::now();
  const bool solid = scene.dimension() == 3;
  if (solid) {
    out.built3d = build_problem<3>(scene);
    out.vertices = out.built3d->mesh.num_vertices();
  } else {
    out.built = build_problem(scene);
    out.vertices = out.built->mesh.num_vertices();
  }
  out.mesh_seconds = since(t_mesh);
  out.runs.resize(pairs.size());
  out.path = scene_is_path(scene);
  std::exception_ptr refusal;  // the first full-space pair's refusal
  if (!out.path)
    run_static_pairs(scene, pairs, engines, mo, o, out, refusal);
  else if (solid)
    run_path_pairs(scene, out.built3d->problem, pairs, engines, mo, o, out, refusal);
  else
    run_path_pairs(scene, out.built->problem, pairs, engines, mo, o, out, refusal);
  // nothing solved: the scene cannot be run with these pairs
  if (refusal && !o.input_errors_fail_pairs &&
      std::all_of(out.runs.begin(), out.runs.end(), [](const PairRun& r) { return r.refused; }))
    std::rethrow_exception(refusal);
  return out;
}

}  // namespace hemivem::app
