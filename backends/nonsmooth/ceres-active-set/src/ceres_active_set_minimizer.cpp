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

using smoothing::SmoothedLaws;

// Shared between the cost function and the iteration callback of one subproblem.
struct Subproblem {
  MinimizerRun* run = nullptr;
  const SmoothedLaws* law = nullptr;
  const smoothing::AnchoredEnergy* energy = nullptr;
  std::vector<Eigen::Index> free;
  Eigen::VectorXd a;      // full point; the pinned entries stay fixed
  std::vector<double> x;  // the free entries scaled, x_k = a_i / s_i (Ceres' parameter block)
  Eigen::VectorXd s;      // Jacobi scaling s_i = 1 / sqrt(S_ii)
  bool certify = false;
  double snap = 0.0;
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
    s.run->count_functions();
    if (gradient) {
      s.run->count_subgradients();
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
      smoothing::smoothed_energy(s.run->problem(), *s.law, s.a, &g);
      if (s.run->problem().project(s.a) == s.a && smoothing::offer_candidates(*s.run, s.a, g, s.snap)) {
        s.certified = true;
        return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
      }
    }
    if (!s.run->budget_left()) {
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

// The state of one minimize() call shared by its active-set passes.
struct PassDriver : smoothing::EngineState {
  const CeresActiveSetOptions& prm;
  double cscale = 0.0;  // |c|_inf, the scale of Ceres' gradient tolerance

  PassDriver(MinimizerRun& r, const CeresActiveSetOptions& options)
      : EngineState(r, options.snap), prm(options), cscale(std::max(p.c.cwiseAbs().maxCoeff(), 1e-300)) {}

  // Minimizes F_eps over the nodes not in `active` (Ceres LBFGS, unconstrained), then projects;
  // true when certified.
  bool solve(const SmoothedLaws& law, const std::vector<char>& active, bool final_stage) {
    const MinimizerOptions& o = run.options();
    const Eigen::Index n = p.size();
    Subproblem s;
    s.run = &run;
    s.law = &law;
    const smoothing::AnchoredEnergy energy(p, law, a);
    s.energy = &energy;
    s.a = a;
    s.certify = final_stage;
    s.snap = snap;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!active[static_cast<std::size_t>(i)]) s.free.push_back(i);
    if (s.free.empty()) return final_stage && run.offer(a);
    s.s = p.S.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    for (Eigen::Index i : s.free) s.x.push_back(a(i) / s.s(i));
    ceres::GradientProblemSolver::Options opts;
    opts.line_search_direction_type = ceres::LBFGS;
    opts.max_lbfgs_rank = prm.lbfgs_rank;
    opts.max_num_iterations = prm.subproblem_iterations;
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
    if (s.certified) a = run.best();
    if (s.out_of_budget && !s.certified) reason = MinimizerStatus::evaluation_limit;
    return s.certified;
  }

  // The active set: nodes on a bound that the smoothed gradient pushes outward.
  std::vector<char> pushed_out(const SmoothedLaws& law, const Eigen::VectorXd& x) {
    const Eigen::Index n = p.size();
    Eigen::VectorXd g;
    smoothing::smoothed_energy(p, law, x, &g);
    run.count_functions();
    run.count_subgradients();
    std::vector<char> act(static_cast<std::size_t>(n), 0);
    for (Eigen::Index i = 0; i < n; ++i)
      act[static_cast<std::size_t>(i)] = (x(i) == p.upper(i) && g(i) <= 0.0) || (x(i) == p.lower(i) && g(i) >= 0.0);
    return act;
  }

  // The active set at the point a: the nodes pushed_out(), and the groups stuck at v = 0 (an
  // active pair: smoothing::hold_stuck_groups puts them there); a slipping group is free.
  std::vector<char> active_set(const SmoothedLaws& law) {
    std::vector<char> act = pushed_out(law, a);
    smoothing::hold_stuck_groups(p, &a, &act);
    return act;
  }
};

}  // namespace

bool CeresActiveSetOptions::is_valid(std::string* error) const {
  if (!smoothing::shared_fields_valid(epsilon, epsilon0, reduction, snap, error)) return false;
  if (max_passes < 1) return invalid_field(error, "max_passes", ">= 1", max_passes);
  if (subproblem_iterations < 1) return invalid_field(error, "subproblem_iterations", ">= 1", subproblem_iterations);
  if (!(lbfgs_rank >= 1 && lbfgs_rank <= 1000)) return invalid_field(error, "lbfgs_rank", "in [1, 1000]", lbfgs_rank);
  return true;
}

MinimizerResult CeresActiveSetMinimizer::run(MinimizerRun& run) const {
  const ReducedProblem& p = run.problem();
  const CeresActiveSetOptions& prm = options_;
  PassDriver passes(run, options_);
  Eigen::VectorXd& a = passes.a;
  MinimizerStatus& reason = passes.reason;
  std::string& message = passes.message;
  const double snap = passes.snap;
  const std::vector<double> schedule = smoothing::schedule(p, prm.epsilon, prm.epsilon0, prm.reduction);
  bool done = false, stop = false;
  for (std::size_t k = 0; k < schedule.size() && !done && !stop; ++k) {
    const bool final_stage = k + 1 == schedule.size();
    const SmoothedLaws law(p, schedule[k]);
    std::vector<char> active = passes.active_set(law);
    double last_residual = std::numeric_limits<double>::infinity();
    for (int pass = 0; pass < prm.max_passes && !done && !stop; ++pass) {
      if (!run.iterations_left()) {
        reason = MinimizerStatus::iteration_limit;
        stop = true;
        break;
      }
      done = passes.solve(law, active, final_stage);
      if (!done && final_stage) {  // snapping the nodes just short of a bound may certify
        Eigen::VectorXd g;
        smoothing::smoothed_energy(p, law, a, &g);
        done = smoothing::offer_candidates(run, a, g, snap);
        if (done) a = run.best();
      }
      const Certificate c = run.check(a);
      if (!run.record(a, p.energy(a), c)) {
        reason = MinimizerStatus::stopped_by_callback;
        stop = true;
      }
      if (reason == MinimizerStatus::evaluation_limit) stop = true;
      if (done || stop) break;
      // update: nodes that left C were projected onto their bound and join; nodes whose
      // multiplier has the wrong sign leave
      // (an unchanged active set ends the stage unless the final stage still improves: LBFGS
      // restarted from the new point, with a fresh memory and anchor)
      const std::vector<char> next = passes.active_set(law);
      if (next == active) {
        if (!final_stage || !(c.worst() < 0.5 * last_residual)) break;
      }
      last_residual = c.worst();
      active = next;
    }
  }
  // one more try at the final scale: nodes held inside a kink's rounding stuck on the kink
  // (with the nodes on a bound) and the others solved for; kept only when it is certified
  if (!done && !stop && smoothing::has_kinks(p) && run.iterations_left()) {
    // (stuck nodes whose force leaves the kink's interval are let go and the rest solved again)
    const SmoothedLaws law(p, schedule.back());
    const Eigen::VectorXd smoothed = a;
    std::vector<char> stuck;
    a = smoothing::snap_to_kinks(p, law, a, &stuck);
    double last = std::numeric_limits<double>::infinity();
    for (int round = 0; round < smoothing::kink_rounds && !done && run.iterations_left(); ++round) {
      std::vector<char> fixed = passes.active_set(law);
      for (std::size_t i = 0; i < fixed.size(); ++i) fixed[i] = fixed[i] || stuck[i];
      done = passes.solve(law, fixed, true);
      if (done) break;
      // again with the stuck nodes let go, or from the point reached while it still improves
      const double now = run.check(a).worst();
      const bool released = smoothing::release_from_kinks(p, a, smoothing::snap_push(p, run.options()), &stuck);
      if (!released && !(now < 0.5 * last)) break;
      last = now;
    }
    if (!done) a = smoothed;
  }
  if (!done && !stop && smoothing::has_kinks(p) && message.empty())
    message = smoothing::smoothing_limit_message(schedule.back());
  // without a certificate the answer is the solution at the final smoothing scale (error O(eps))
  return run.finish(reason, message,
                    std::to_string(run.iterations()) + " active-set passes over " + std::to_string(schedule.size()) +
                        " smoothing stages",
                    run.has_certified_point() ? nullptr : &a);
}

}  // namespace hemivem
