#include <hemivem/app/engine_pairs.hpp>

#include <algorithm>
#include <type_traits>
#include <chrono>
#include <cmath>
#include <limits>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/error.hpp>
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

std::vector<Pair> available_pairs() {
  std::vector<Pair> pairs;
  for (const auto& l : available_factorizations())
    for (const auto& m : available_minimizers()) pairs.push_back({l, m});
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
  return {{"linear", r.pair.linear},   {"minimizer", r.pair.minimizer}, {"status", r.status},
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

// the engines of every pair, before any work (an unknown name is an InputError here)
PairEngines make_engines(const Scene& scene, const std::vector<Pair>& pairs) {
  PairEngines e;
  for (const auto& p : pairs) {
    if (std::find(e.linears.begin(), e.linears.end(), p.linear) == e.linears.end()) e.linears.push_back(p.linear);
    if (!e.minimizers.count(p.minimizer)) e.minimizers[p.minimizer] = make_scene_minimizer(scene, p.minimizer);
  }
  for (const auto& l : e.linears) {
    FactorizationOptions fo;
    fo.engine = l;
    (void)make_factorization(fo);
  }
  return e;
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
  r.timings["assembly"] = out.assembly_seconds;
  r.timings["total"] += out.assembly_seconds;
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

/// The path of one pair into `r`: its last step as a static solve (record_solution), converged
/// when every step is, with the status and message of the first step that is not, the
/// iterations of every step, each step's t and displacement, and the path's own timings
/// (minimize: every step's; back_substitution: every step's displacement).
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
  r.timings["minimize"] = path.timings["path"];
  r.timings["back_substitution"] = path.timings["frames"];
  r.seconds = out.mesh_seconds + r.timings["total"];
}

/// Every pair along the scene's path, one after the other on `problem` (each path sets the
/// problem to the t of each of its steps): each pair assembles and condenses it itself, every
/// step is a frame (its displacement is kept). A NumericalError fails the pair; so does an
/// InputError when the options say so, else it is thrown naming the scene's key.
template <int dim>
void run_path_pairs(const Scene& scene, BasicContactProblem<dim>& problem, const std::vector<Pair>& pairs,
                    const PairEngines& engines, const MinimizerOptions& mo, const PairRunOptions& o, PairRuns& out) {
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    PairRun& r = out.runs[i];
    r.pair = pairs[i];
    r.mesh_seconds = out.mesh_seconds;
    std::string failure;
    try {
      FactorizationOptions fo;
      fo.engine = pairs[i].linear;
      BasicPathOptions<dim> po;
      po.minimizer = mo;
      po.frame = [](int) { return true; };
      BasicPathSolution<dim> path = solve_path(problem, make_factorization(fo), *engines.minimizers.at(pairs[i].minimizer),
                                               scene_path_loading<dim>(scene), std::move(po));
      ++out.assemblies;
      ++out.condensations;
      record_path(r, path, out, mo.tolerance);
    } catch (const NumericalError& e) {
      failure = e.what();
    } catch (const InputError& e) {
      if (!o.input_errors_fail_pairs) detail::rethrow_naming_scene_key(scene, e);
      failure = e.what();
    }
    if (!failure.empty()) {
      r.failed = true;
      r.message = failure;
      r.seconds = out.mesh_seconds;
    }
    if (o.done) o.done(r);
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
  if (out.path) {
    if (solid) run_path_pairs(scene, out.built3d->problem, pairs, engines, mo, o, out);
    else run_path_pairs(scene, out.built->problem, pairs, engines, mo, o, out);
    return out;
  }
  const auto t_assembly = Clock::now();
  const LinearSystem system = solid ? assemble(out.built3d->problem.elasticity) : assemble(out.built->problem.elasticity);
  out.assembly_seconds = since(t_assembly);
  out.assemblies = 1;
  for (const auto& linear : engines.linears) run_engine_pairs(linear, pairs, engines, system, mo, o, out);
  return out;
}

}  // namespace hemivem::app
