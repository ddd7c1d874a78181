#include <hemivem/ceres_active_set_minimizer.hpp>

#include <hemivem/smooth_engine.hpp>

#include <ceres/ceres.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

namespace hemivem {
namespace {

using smoothing::SmoothedLaw;

// Shared between the cost function and the iteration callback of one subproblem.
struct Subproblem {
  const ReducedProblem* p = nullptr;
  const MinimizerOptions* o = nullptr;
  const SmoothedLaw* law = nullptr;
  const smoothing::AnchoredEnergy* energy = nullptr;
  std::vector<Eigen::Index> free;
  Eigen::VectorXd a;      // full point; the pinned entries stay fixed
  std::vector<double> x;  // the free entries scaled, x_k = a_i / s_i (Ceres' parameter block)
  Eigen::VectorXd s;      // Jacobi scaling s_i = 1 / sqrt(S_ii)
  int* fevals = nullptr;
  int* gevals = nullptr;
  int budget = 0;
  bool certify = false;
  double snap = 0.0;
  smoothing::BestPoint* best = nullptr;
  bool certified = false, out_of_budget = false;

  void scatter(const double* y) {
    for (std::size_t k = 0; k < free.size(); ++k) a(free[k]) = s(free[k]) * y[k];
  }
};

class SmoothedEnergy final : public ceres::FirstOrderFunction {
 public:
  explicit SmoothedEnergy(Subproblem* s) : s_(s) {}
  bool Evaluate(const double* parameters, double* cost, double* gradient) const override {
    Subproblem& s = *s_;
    Eigen::VectorXd a = s.a;
    for (std::size_t k = 0; k < s.free.size(); ++k) a(s.free[k]) = s.s(s.free[k]) * parameters[k];
    Eigen::VectorXd g;
    *cost = (*s.energy)(a, gradient ? &g : nullptr);
    ++*s.fevals;
    if (gradient) {
      ++*s.gevals;
      for (std::size_t k = 0; k < s.free.size(); ++k) gradient[k] = s.s(s.free[k]) * g(s.free[k]);
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return static_cast<int>(s_->free.size()); }

 private:
  Subproblem* s_;
};

// Stops Ceres when the hemivem certificate holds (final stage) or the budget is spent.
class Monitor final : public ceres::IterationCallback {
 public:
  explicit Monitor(Subproblem* s) : s_(s) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
    Subproblem& s = *s_;
    if (s.certify) {
      s.scatter(s.x.data());
      Eigen::VectorXd g;
      smoothing::smoothed_energy(*s.p, *s.law, s.a, &g);
      const Eigen::VectorXd feasible = s.p->project(s.a);
      if (feasible == s.a && (s.best->offer(*s.p, *s.o, s.a) ||
                              s.best->offer(*s.p, *s.o, smoothing::snap_to_bounds(*s.p, s.a, g, s.snap, smoothing::snap_push(*s.p, *s.o))))) {
        s.certified = true;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    }
    if (*s.fevals + *s.gevals >= s.budget) {
      s.out_of_budget = true;
      return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  Subproblem* s_;
};

// glog prints Ceres' warnings to stderr; hemivem prints nothing, so they are muted while
// Ceres runs (the previous level is restored afterwards).
std::mutex glog_mutex;
class QuietGlog {
 public:
  explicit QuietGlog(bool quiet) : lock_(glog_mutex), saved_(FLAGS_minloglevel), quiet_(quiet) {
    if (quiet_) FLAGS_minloglevel = std::max(saved_, 3);
  }
  ~QuietGlog() {
    if (quiet_) FLAGS_minloglevel = saved_;
  }

 private:
  std::lock_guard<std::mutex> lock_;
  int saved_;
  bool quiet_;
};

}  // namespace

MinimizerResult CeresActiveSetMinimizer::minimize(const ReducedProblem& p, const Eigen::VectorXd& start,
                                                  const MinimizerOptions& o) const {
  const std::string where = "nonsmooth engine 'ceres-active-set'";
  std::map<std::string, double> extra{{"max_passes", 50}, {"subproblem_iterations", 10000}, {"lbfgs_rank", 20},
                                      {"snap", 1e-7}};
  const smoothing::Continuation cont = smoothing::read_parameters(o, extra, where);
  const int max_passes = static_cast<int>(std::max(1.0, extra["max_passes"]));
  const int sub_iterations = static_cast<int>(std::max(1.0, extra["subproblem_iterations"]));
  const int rank = static_cast<int>(std::max(1.0, extra["lbfgs_rank"]));

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
  const double cscale = std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, 1e-300);
  const double snap = extra["snap"] * std::max(smoothing::length_scale(p, a), 1e-300);
  int fevals = 0, gevals = 0;
  smoothing::BestPoint best;
  MinimizerStatus reason = MinimizerStatus::stalled;
  std::string message;

  auto record = [&](const Eigen::VectorXd& x) { return smoothing::record_iteration(p, o, clock.seconds(), x, result); };

  // minimizes F_eps over the nodes not in `active` (Ceres LBFGS, unconstrained), then projects
  auto solve = [&](const SmoothedLaw& law, const std::vector<char>& active, bool final_stage) {
    Subproblem s;
    s.p = &p;
    s.o = &o;
    s.law = &law;
    const smoothing::AnchoredEnergy energy(p, law, a);
    s.energy = &energy;
    s.a = a;
    s.fevals = &fevals;
    s.gevals = &gevals;
    s.budget = o.max_evaluations;
    s.certify = final_stage;
    s.snap = snap;
    s.best = &best;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!active[static_cast<std::size_t>(i)]) s.free.push_back(i);
    if (s.free.empty()) return final_stage && best.offer(p, o, a);
    s.s = p.S.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    for (Eigen::Index i : s.free) s.x.push_back(a(i) / s.s(i));
    ceres::GradientProblemSolver::Options opts;
    opts.line_search_direction_type = ceres::LBFGS;
    opts.max_lbfgs_rank = rank;
    opts.max_num_iterations = sub_iterations;
    opts.function_tolerance = 1e-20;
    opts.parameter_tolerance = 1e-20;
    opts.min_line_search_step_size = 1e-20;
    opts.gradient_tolerance = (final_stage ? 1e-2 * o.tolerance : 1e-8) * cscale * s.s.minCoeff();
    opts.logging_type = ceres::SILENT;
    opts.minimizer_progress_to_stdout = false;
    opts.update_state_every_iteration = true;
    Monitor monitor(&s);
    opts.callbacks.push_back(&monitor);
    ceres::GradientProblem problem(new SmoothedEnergy(&s));
    ceres::GradientProblemSolver::Summary summary;
    {
      QuietGlog quiet(o.verbosity <= 0);
      ceres::Solve(opts, problem, s.x.data(), &summary);
    }
    if (summary.termination_type == ceres::FAILURE) message = "Ceres: " + summary.message;
    s.scatter(s.x.data());
    a = p.project(s.a);
    if (s.certified) a = best.a;
    if (s.out_of_budget && !s.certified) reason = MinimizerStatus::evaluation_limit;
    return s.certified;
  };

  // the active set: nodes on a bound that the smoothed gradient pushes outward
  auto pushed_out = [&](const SmoothedLaw& law, const Eigen::VectorXd& x) {
    Eigen::VectorXd g;
    smoothing::smoothed_energy(p, law, x, &g);
    ++fevals;
    ++gevals;
    std::vector<char> act(static_cast<std::size_t>(n), 0);
    for (Eigen::Index i = 0; i < n; ++i)
      act[static_cast<std::size_t>(i)] = (x(i) == p.upper(i) && g(i) <= 0.0) || (x(i) == p.lower(i) && g(i) >= 0.0);
    return act;
  };

  const std::vector<double> schedule = cont.schedule(*p.law);
  bool done = false, stop = false;
  for (std::size_t k = 0; k < schedule.size() && !done && !stop; ++k) {
    const bool final_stage = k + 1 == schedule.size();
    const SmoothedLaw law(p.law, schedule[k]);
    std::vector<char> active = pushed_out(law, a);
    double last_residual = std::numeric_limits<double>::infinity();
    for (int pass = 0; pass < max_passes && !done && !stop; ++pass) {
      done = solve(law, active, final_stage);
      if (!done && final_stage) {  // snapping the nodes just short of a bound may certify
        Eigen::VectorXd g;
        smoothing::smoothed_energy(p, law, a, &g);
        done = best.offer(p, o, smoothing::snap_to_bounds(p, a, g, snap, smoothing::snap_push(p, o)));
        if (done) a = best.a;
      }
      if (!record(a)) {
        reason = MinimizerStatus::stopped_by_callback;
        stop = true;
      }
      if (reason == MinimizerStatus::evaluation_limit) stop = true;
      if (done || stop) break;
      if (result.iterations >= o.max_iterations) {
        reason = MinimizerStatus::iteration_limit;
        stop = true;
        break;
      }
      // update: nodes that left C were projected onto their bound and join; nodes whose
      // multiplier has the wrong sign leave
      // (an unchanged active set ends the stage unless the final stage still improves: LBFGS
      // restarted from the new point, with a fresh memory and anchor)
      const std::vector<char> next = pushed_out(law, a);
      const double residual = result.history.back().residual;
      if (next == active) {
        if (!final_stage || !(residual < 0.5 * last_residual)) break;
      }
      last_residual = residual;
      active = next;
    }
  }
  if (!done && !stop && SmoothedLaw(p.law, 0.0).kinks() > 0)
    message = smoothing::smoothing_limit_message(schedule.back());
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
