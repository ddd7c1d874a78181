#include <hemivem/engine_parameters.hpp>
#include <hemivem/error.hpp>
#include <hemivem/existence.hpp>
#include <hemivem/minimizer_run.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <utility>

namespace hemivem {

std::string to_string(MinimizerStatus status) {
  switch (status) {
    case MinimizerStatus::converged: return "converged";
    case MinimizerStatus::iteration_limit: return "iteration limit";
    case MinimizerStatus::evaluation_limit: return "evaluation limit";
    case MinimizerStatus::stalled: return "stalled";
    case MinimizerStatus::stopped_by_callback: return "stopped by callback";
    case MinimizerStatus::failed: return "failed";
    case MinimizerStatus::unbounded: return "unbounded";
  }
  throw InternalError("a MinimizerStatus out of range: " + std::to_string(static_cast<int>(status)));
}

MinimizerStatus minimizer_status_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = ch == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (MinimizerStatus status :
       {MinimizerStatus::converged, MinimizerStatus::iteration_limit, MinimizerStatus::evaluation_limit,
        MinimizerStatus::stalled, MinimizerStatus::stopped_by_callback, MinimizerStatus::failed,
        MinimizerStatus::unbounded})
    if (s == to_string(status)) return status;
  throw InputError("unknown minimizer status '" + std::string(name) +
                   "'; expected converged, iteration limit, evaluation limit, stalled, stopped by callback, failed or unbounded");
}

MinimizerResult NonsmoothMinimizer::minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                                             const MinimizerOptions& options) const {
  if (!problem.groups.empty() && !takes_groups()) throw InputError(groups_refusal(), name());
  MinimizerRun r(name(), problem, start, options);
  if (r.size() == 0) return r.finish(MinimizerStatus::converged, {}, "empty problem", &r.start());
  if (options.check_existence) {
    const Existence e = check_existence(problem);
    if (!e.bounded) return r.finish(MinimizerStatus::unbounded, e.message, {}, &r.start());
  }
  if (answers_certified_start() && r.offer(r.start()))
    return r.finish(MinimizerStatus::converged, {}, "the start is certified", &r.start());
  return run(r);
}

std::string NonsmoothMinimizer::groups_refusal() const {
  return name() + " does not take groups of coordinates (the law of a tangential displacement's norm: friction on a "
                  "solid's surface); choose an engine that does";
}

int count_at_bound(const ReducedProblem& p, const Eigen::VectorXd& a) {
  int k = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) k += (a(i) == p.lower(i) || a(i) == p.upper(i)) ? 1 : 0;
  return k;
}

MinimizerRun::MinimizerRun(const std::string& engine, const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options)
    : p_(problem), o_(options) {
  require_valid(o_, engine);
  check_sizes(p_, engine);
  const Eigen::Index n = p_.size();
  if (start.size() != 0 && start.size() != n)
    throw InputError("the start has size " + std::to_string(start.size()) + ", the problem " + std::to_string(n),
                     engine);
  if (!start.allFinite()) throw InputError("the start is not finite", engine);
  start_ = p_.project(start.size() == 0 ? Eigen::VectorXd::Zero(n) : start);
}

bool MinimizerRun::offer(const Eigen::VectorXd& x, const Certificate& c) {
  const bool good = c.converged();
  if (best_.size() == 0 || (good && !best_ok_) || (good == best_ok_ && c.worst() < best_cert_.worst())) {
    best_ = x;
    best_cert_ = c;
    best_ok_ = good;
  }
  return good;
}

bool MinimizerRun::record(const Eigen::VectorXd& x, double objective, const Certificate& c) {
  offer(x, c);
  const IterationRecord r{++iterations_, objective, c.primal, c.dual, count_at_bound(p_, x), seconds()};
  history_.push_back(r);
  return !o_.callback || o_.callback(r);
}

void MinimizerRun::record_start(const Eigen::VectorXd& x, double objective, const Certificate& c) {
  offer(x, c);
  history_.push_back({0, objective, c.primal, c.dual, count_at_bound(p_, x), seconds()});
}

MinimizerResult MinimizerRun::finish(MinimizerStatus reason, const std::string& why, const std::string& summary,
                                     const Eigen::VectorXd* point) const {
  MinimizerResult r;
  CertifiedPoint cp = certify(p_, point ? *point : best(), o_.tolerance);
  r.certificate = cp.certificate;
  r.a = cp.a.size() == p_.size() ? std::move(cp.a) : (point ? *point : best());
  r.law_force = std::move(cp.law_force);
  r.reaction = std::move(cp.reaction);
  r.objective = r.a.size() == p_.size() && r.a.allFinite() ? p_.energy(r.a) : std::numeric_limits<double>::quiet_NaN();
  r.may_be_nonunique = !(p_.uniqueness_margin > 0.0);
  r.status = reason != MinimizerStatus::unbounded && r.certificate.converged() && std::isfinite(r.objective)
                 ? MinimizerStatus::converged
                 : (reason == MinimizerStatus::converged ? MinimizerStatus::stalled : reason);
  std::string head = r.converged() ? std::string() : (why.empty() ? to_string(r.status) : why);
  r.message = head.empty() ? summary : (summary.empty() ? head : head + "; " + summary);
  r.iterations = iterations_;
  r.function_evaluations = functions_;
  r.subgradient_evaluations = subgradients_;
  r.history = history_;
  r.timings = timings_;
  r.timings["total"] = seconds();
  return r;
}

}  // namespace hemivem
