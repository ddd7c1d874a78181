#include <hemivem/nlopt_mma_minimizer.hpp>

#include <hemivem/smooth_engine.hpp>

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace hemivem {
namespace {

using smoothing::SmoothedLaws;

// One MMA run over the free nodes of `a` (the others stay where they are).
struct Stage {
  MinimizerRun* run = nullptr;
  const SmoothedLaws* law = nullptr;
  const smoothing::AnchoredEnergy* energy = nullptr;
  std::vector<Eigen::Index> free;  // indices optimized
  Eigen::VectorXd a;               // the full point (pinned entries fixed)
  bool certify = false;            // stop as soon as a (snapped) point is certified
  double snap = 0.0;               // snapping distance
  int budget = 0;                  // evaluation budget (function + gradient) of this MMA run
  bool certified = false, out_of_budget = false;
  nlopt_opt opt = nullptr;
};

double objective(unsigned n, const double* x, double* grad, void* data) {
  auto& s = *static_cast<Stage*>(data);
  for (unsigned k = 0; k < n; ++k) s.a(s.free[k]) = x[k];
  Eigen::VectorXd g;
  const double f = (*s.energy)(s.a, grad ? &g : nullptr);
  s.run->count_functions();
  if (grad) {
    s.run->count_subgradients();
    for (unsigned k = 0; k < n; ++k) grad[k] = g(s.free[k]);
  }
  // the certificate on the unsmoothed problem decides; MMA's own tests only end a stage
  if (s.certify && grad && std::isfinite(f) && smoothing::offer_candidates(*s.run, s.a, g, s.snap)) {
    s.certified = true;
    nlopt_force_stop(s.opt);
  }
  if (s.run->evaluations() >= s.budget) {
    s.out_of_budget = true;
    nlopt_force_stop(s.opt);
  }
  return f;
}

struct OptDeleter {
  void operator()(nlopt_opt o) const { nlopt_destroy(o); }
};

// The state of one minimize() call shared by its MMA runs.
struct MmaDriver : smoothing::EngineState {
  const NloptMmaOptions& prm;

  MmaDriver(MinimizerRun& r, const NloptMmaOptions& options) : EngineState(r, options.snap), prm(options) {}

  // One MMA run at the smoothing scale of `law` over the nodes not pinned; true when certified.
  bool stage(const SmoothedLaws& law, const std::vector<char>& pinned, bool final_stage, bool polish) {
    const MinimizerOptions& o = run.options();
    const Eigen::Index n = p.size();
    Stage s;
    s.run = &run;
    s.law = &law;
    const smoothing::AnchoredEnergy energy(p, law, a);
    s.energy = &energy;
    s.a = a;
    s.certify = final_stage;
    s.snap = snap;
    const int evaluations = run.evaluations();
    s.budget = static_cast<int>(std::min<long long>(o.max_evaluations, static_cast<long long>(evaluations) + prm.stage_evaluations));
    for (Eigen::Index i = 0; i < n; ++i)
      if (!pinned[static_cast<std::size_t>(i)]) s.free.push_back(i);
    const unsigned m = static_cast<unsigned>(s.free.size());
    if (m == 0) {
      if (final_stage) s.certified = run.offer(a);
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
      step[k] = std::max(length, 1e-12);
      if (std::isfinite(lb[k]) && std::isfinite(ub[k])) step[k] = std::max(0.5 * (ub[k] - lb[k]), 1e-12);
    }
    nlopt_set_lower_bounds(opt.get(), lb.data());
    nlopt_set_upper_bounds(opt.get(), ub.data());
    nlopt_set_initial_step(opt.get(), step.data());
    nlopt_set_min_objective(opt.get(), objective, &s);
    nlopt_set_xtol_rel(opt.get(), polish ? 0.0 : prm.xtol_rel);
    nlopt_set_ftol_rel(opt.get(), polish ? 0.0 : 1e-15);
    nlopt_set_maxeval(opt.get(), std::max(1, (s.budget - evaluations) / 2 + 1));  // each one is f and grad
    if (prm.inner_maxeval > 0) nlopt_set_param(opt.get(), "inner_maxeval", prm.inner_maxeval);
    double fmin = 0.0;
    const nlopt_result rc = nlopt_optimize(opt.get(), x.data(), &fmin);
    if (rc == NLOPT_FAILURE || rc == NLOPT_INVALID_ARGS || rc == NLOPT_OUT_OF_MEMORY)
      message = "NLopt MMA returned " + std::string(nlopt_result_to_string(rc));
    // NLopt returns its best point in x (also on roundoff_limited and forced stops)
    for (unsigned k = 0; k < m; ++k) a(s.free[k]) = x[k];
    a = p.project(a);
    if (s.certified) a = run.best();
    if (s.out_of_budget && !s.certified && !run.budget_left()) reason = MinimizerStatus::evaluation_limit;
    return s.certified;
  }
};

}  // namespace

bool NloptMmaOptions::is_valid(std::string* error) const {
  if (!smoothing::shared_fields_valid(epsilon, epsilon0, reduction, snap, error)) return false;
  if (!(xtol_rel >= 0.0 && std::isfinite(xtol_rel))) return invalid_field(error, "xtol_rel", "finite and >= 0", xtol_rel);
  if (stage_evaluations < 1) return invalid_field(error, "stage_evaluations", ">= 1", stage_evaluations);
  if (inner_maxeval < 0) return invalid_field(error, "inner_maxeval", ">= 0", inner_maxeval);
  if (polish_passes < 0) return invalid_field(error, "polish_passes", ">= 0", polish_passes);
  return true;
}

MinimizerResult NloptMmaMinimizer::run(MinimizerRun& run) const {
  const ReducedProblem& p = run.problem();
  const MinimizerOptions& o = run.options();
  const Eigen::Index n = p.size();
  MmaDriver mma(run, options_);
  Eigen::VectorXd& a = mma.a;
  MinimizerStatus& reason = mma.reason;
  std::string& message = mma.message;
  const double snap = mma.snap;
  const NloptMmaOptions& prm = options_;
  const std::vector<double> schedule = smoothing::schedule(p, prm.epsilon, prm.epsilon0, prm.reduction);
  std::vector<char> none(static_cast<std::size_t>(n), 0);
  bool done = false, stop = false;
  for (std::size_t k = 0; k < schedule.size() && !done && !stop; ++k) {
    if (!run.iterations_left()) {
      reason = MinimizerStatus::iteration_limit;
      break;
    }
    const bool final_stage = k + 1 == schedule.size();
    const SmoothedLaws law(p, schedule[k]);
    std::vector<char> held = none;  // the groups stuck at v = 0 stay there during the stage
    smoothing::hold_stuck_groups(p, &a, &held);
    done = mma.stage(law, held, final_stage, false);
    if (!run.record(a)) {
      reason = MinimizerStatus::stopped_by_callback;
      stop = true;
    }
    if (reason == MinimizerStatus::evaluation_limit) stop = true;
  }
  // polishing at the final scale: nodes the gradient pushes onto a bound are pinned there
  if (!done && !stop) {
    const SmoothedLaws law(p, schedule.back());
    for (int pass = 0; pass < prm.polish_passes && !done && !stop; ++pass) {
      if (!run.iterations_left()) {
        reason = MinimizerStatus::iteration_limit;
        break;
      }
      Eigen::VectorXd g;
      smoothing::smoothed_energy(p, law, a, &g);
      run.count_functions();
      run.count_subgradients();
      a = smoothing::snap_to_bounds(p, a, g, snap, smoothing::snap_push(p, o));
      std::vector<char> pinned(static_cast<std::size_t>(n), 0);
      for (Eigen::Index i = 0; i < n; ++i) pinned[static_cast<std::size_t>(i)] = a(i) == p.upper(i) || a(i) == p.lower(i);
      smoothing::hold_stuck_groups(p, &a, &pinned);
      done = mma.stage(law, pinned, true, true);
      if (!run.record(a)) {
        reason = MinimizerStatus::stopped_by_callback;
        stop = true;
      }
      if (reason == MinimizerStatus::evaluation_limit) stop = true;
    }
    // one more try: nodes held inside a kink's rounding stuck on the kink (with those on a
    // bound); kept only when it is certified
    if (!done && !stop && law.kinks() > 0 && run.iterations_left()) {
      // (stuck nodes whose force leaves the kink's interval are let go and the rest solved again)
      const Eigen::VectorXd smoothed = a;
      std::vector<char> stuck;
      a = smoothing::snap_to_kinks(p, law, a, &stuck);
      double last = std::numeric_limits<double>::infinity();
      for (int round = 0; round < smoothing::kink_rounds && !done && run.iterations_left(); ++round) {
        std::vector<char> pinned(static_cast<std::size_t>(n), 0);
        for (Eigen::Index i = 0; i < n; ++i)
          pinned[static_cast<std::size_t>(i)] = stuck[static_cast<std::size_t>(i)] || a(i) == p.upper(i) || a(i) == p.lower(i);
        smoothing::hold_stuck_groups(p, &a, &pinned);
        done = mma.stage(law, pinned, true, true);
        if (done) break;
        // again with the stuck nodes let go, or from the point reached while it still improves
        const double now = run.check(a).worst();
        const bool released = smoothing::release_from_kinks(p, a, smoothing::snap_push(p, o), &stuck);
        if (!released && !(now < 0.5 * last)) break;
        last = now;
      }
      if (!done) a = smoothed;
    }
    if (!done && !stop && law.kinks() > 0 && message.empty()) message = smoothing::smoothing_limit_message(schedule.back());
  }
  // without a certificate the answer is the solution at the final smoothing scale (error O(eps))
  return run.finish(reason, message, std::to_string(schedule.size()) + " smoothing stages",
                    run.has_certified_point() ? nullptr : &a);
}

}  // namespace hemivem
