#include <hemivem/nlopt_mma_minimizer.hpp>

#include <hemivem/smooth_engine.hpp>

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace hemivem {
namespace {

using smoothing::SmoothedLaw;

// One MMA run over the free nodes of `a` (the others stay where they are).
struct Stage {
  const ReducedProblem* p = nullptr;
  const MinimizerOptions* o = nullptr;
  const SmoothedLaw* law = nullptr;
  const smoothing::AnchoredEnergy* energy = nullptr;
  std::vector<Eigen::Index> free;  // indices optimized
  Eigen::VectorXd a;               // the full point (pinned entries fixed)
  bool certify = false;            // stop as soon as a (snapped) point is certified
  double snap = 0.0;               // snapping distance
  smoothing::BestPoint* best = nullptr;
  int* fevals = nullptr;           // function evaluations of the run
  int* gevals = nullptr;           // gradient evaluations of the run
  int budget = 0;                  // evaluation budget (function + gradient) of the run
  bool certified = false, out_of_budget = false;
  nlopt_opt opt = nullptr;
};

double objective(unsigned n, const double* x, double* grad, void* data) {
  auto& s = *static_cast<Stage*>(data);
  for (unsigned k = 0; k < n; ++k) s.a(s.free[k]) = x[k];
  Eigen::VectorXd g;
  const double f = (*s.energy)(s.a, grad ? &g : nullptr);
  ++*s.fevals;
  if (grad) ++*s.gevals;
  if (grad)
    for (unsigned k = 0; k < n; ++k) grad[k] = g(s.free[k]);
  if (s.certify && grad && std::isfinite(f)) {
    // the hemivem certificate on the unsmoothed problem decides; MMA's own tests only end a stage
    const Eigen::VectorXd feasible = s.p->project(s.a);
    if (s.best->offer(*s.p, *s.o, feasible) ||
        s.best->offer(*s.p, *s.o, smoothing::snap_to_bounds(*s.p, feasible, g, s.snap, smoothing::snap_push(*s.p, *s.o)))) {
      s.certified = true;
      nlopt_force_stop(s.opt);
    }
  }
  if (*s.fevals + *s.gevals >= s.budget) {
    s.out_of_budget = true;
    nlopt_force_stop(s.opt);
  }
  return f;
}

struct OptDeleter {
  void operator()(nlopt_opt o) const { nlopt_destroy(o); }
};

}  // namespace

MinimizerResult NloptMmaMinimizer::minimize(const ReducedProblem& p, const Eigen::VectorXd& start,
                                            const MinimizerOptions& o) const {
  const std::string where = "nonsmooth engine 'nlopt-mma'";
  std::map<std::string, double> extra{{"xtol_rel", 1e-10},
                                      {"stage_evaluations", 20000},
                                      {"inner_maxeval", 50},
                                      {"snap", 1e-7},
                                      {"polish_passes", 5}};
  const smoothing::Continuation cont = smoothing::read_parameters(o, extra, where);
  const double xtol = extra["xtol_rel"];
  const int stage_evaluations = static_cast<int>(std::max(1.0, extra["stage_evaluations"]));
  const int polish_passes = static_cast<int>(std::max(0.0, extra["polish_passes"]));
  if (!(xtol >= 0.0)) throw InputError("xtol_rel must be >= 0", where);

  smoothing::Clock clock;
  MinimizerResult result;
  Eigen::VectorXd a = smoothing::projected_start(p, start, where);
  const Eigen::Index n = p.size();
  if (n == 0) {  // nothing to minimize
    result.a = a;
    result.timings["total"] = clock.seconds();
    finish(p, o, MinimizerStatus::converged, result);
    result.message = "empty problem";
    return result;
  }
  const double scale_a = smoothing::length_scale(p, a);
  const double snap = extra["snap"] * std::max(scale_a, 1e-300);
  int fevals = 0, gevals = 0;
  smoothing::BestPoint best;
  MinimizerStatus reason = MinimizerStatus::stalled;
  std::string message;

  auto record = [&](const Eigen::VectorXd& x) { return smoothing::record_iteration(p, o, clock.seconds(), x, result); };

  // one MMA run at smoothing scale eps over the nodes not pinned; returns false on a hard stop
  auto run = [&](const SmoothedLaw& law, const std::vector<char>& pinned, bool final_stage, bool polish) {
    Stage s;
    s.p = &p;
    s.o = &o;
    s.law = &law;
    const smoothing::AnchoredEnergy energy(p, law, a);
    s.energy = &energy;
    s.a = a;
    s.certify = final_stage;
    s.snap = snap;
    s.best = &best;
    s.fevals = &fevals;
    s.gevals = &gevals;
    const int evaluations = fevals + gevals;
    s.budget = std::min<long long>(o.max_evaluations, static_cast<long long>(evaluations) + stage_evaluations);
    for (Eigen::Index i = 0; i < n; ++i)
      if (!pinned[static_cast<std::size_t>(i)]) s.free.push_back(i);
    const unsigned m = static_cast<unsigned>(s.free.size());
    if (m == 0) {
      if (final_stage) s.certified = best.offer(p, o, a);
      return s.certified;
    }
    std::unique_ptr<nlopt_opt_s, OptDeleter> opt(nlopt_create(NLOPT_LD_MMA, m));
    if (!opt) throw Error("nlopt-mma: nlopt_create failed");
    s.opt = opt.get();
    std::vector<double> x(m), lb(m), ub(m), step(m);
    for (unsigned k = 0; k < m; ++k) {
      const Eigen::Index i = s.free[k];
      x[k] = a(i);
      lb[k] = std::isfinite(p.lower(i)) ? p.lower(i) : -HUGE_VAL;
      ub[k] = std::isfinite(p.upper(i)) ? p.upper(i) : HUGE_VAL;
      step[k] = std::max(scale_a, 1e-12);
      if (std::isfinite(lb[k]) && std::isfinite(ub[k])) step[k] = std::max(0.5 * (ub[k] - lb[k]), 1e-12);
    }
    nlopt_set_lower_bounds(opt.get(), lb.data());
    nlopt_set_upper_bounds(opt.get(), ub.data());
    nlopt_set_initial_step(opt.get(), step.data());
    nlopt_set_min_objective(opt.get(), objective, &s);
    nlopt_set_xtol_rel(opt.get(), polish ? 0.0 : xtol);
    nlopt_set_ftol_rel(opt.get(), polish ? 0.0 : 1e-15);
    nlopt_set_maxeval(opt.get(), std::max(1, (s.budget - evaluations) / 2 + 1));  // each one is f and grad
    if (extra["inner_maxeval"] > 0) nlopt_set_param(opt.get(), "inner_maxeval", extra["inner_maxeval"]);
    double fmin = 0.0;
    const nlopt_result rc = nlopt_optimize(opt.get(), x.data(), &fmin);
    if (rc == NLOPT_FAILURE || rc == NLOPT_INVALID_ARGS || rc == NLOPT_OUT_OF_MEMORY)
      message = "NLopt MMA returned " + std::string(nlopt_result_to_string(rc));
    // NLopt returns its best point in x (also on roundoff_limited and forced stops)
    for (unsigned k = 0; k < m; ++k) a(s.free[k]) = x[k];
    a = p.project(a);
    if (s.certified) a = best.a;
    if (s.out_of_budget && !s.certified && fevals + gevals >= o.max_evaluations) reason = MinimizerStatus::evaluation_limit;
    return s.certified;
  };

  const std::vector<double> schedule = cont.schedule(*p.law);
  std::vector<char> none(static_cast<std::size_t>(n), 0);
  bool done = false, stop = false;
  for (std::size_t k = 0; k < schedule.size() && !done && !stop; ++k) {
    const bool final_stage = k + 1 == schedule.size();
    const SmoothedLaw law(p.law, schedule[k]);
    done = run(law, none, final_stage, false);
    if (!record(a)) {
      reason = MinimizerStatus::stopped_by_callback;
      stop = true;
    }
    if (reason == MinimizerStatus::evaluation_limit) stop = true;
    if (!done && !stop && result.iterations >= o.max_iterations && !final_stage) {
      reason = MinimizerStatus::iteration_limit;
      stop = true;
    }
  }
  // polishing at the final scale: nodes the gradient pushes onto a bound are pinned there
  if (!done && !stop) {
    const SmoothedLaw law(p.law, schedule.back());
    for (int pass = 0; pass < polish_passes && !done && !stop; ++pass) {
      if (result.iterations >= o.max_iterations) {
        reason = MinimizerStatus::iteration_limit;
        break;
      }
      Eigen::VectorXd g;
      smoothing::smoothed_energy(p, law, a, &g);
      ++fevals;
      ++gevals;
      a = smoothing::snap_to_bounds(p, a, g, snap, smoothing::snap_push(p, o));
      std::vector<char> pinned(static_cast<std::size_t>(n), 0);
      for (Eigen::Index i = 0; i < n; ++i) pinned[static_cast<std::size_t>(i)] = a(i) == p.upper(i) || a(i) == p.lower(i);
      done = run(law, pinned, true, true);
      if (!record(a)) {
        reason = MinimizerStatus::stopped_by_callback;
        stop = true;
      }
      if (reason == MinimizerStatus::evaluation_limit) stop = true;
    }
    if (!done && !stop && law.kinks() > 0)
      message = smoothing::smoothing_limit_message(schedule.back());
  }
  result.a = done ? best.a : a;
  result.function_evaluations = fevals;
  result.subgradient_evaluations = gevals;
  result.timings["total"] = clock.seconds();
  finish(p, o, done ? MinimizerStatus::converged : reason, result);
  if (result.converged() && message.empty()) message = "certificate below tolerance";
  result.message = message.empty() ? to_string(result.status) : message;
  return result;
}

}  // namespace hemivem
