// The contract of a nonsmooth minimizer of the reduced contact problem (DESIGN §3, §5):
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t. a in C.
//
// An engine derives from NonsmoothMinimizer and writes its numerics only, in run(): the
// public minimize() checks the options, the problem and the start, answers the empty problem,
// and hands the engine a MinimizerRun, which keeps the clock, the evaluation counts, the
// history, the best point so far and builds the final result. Whatever the engine's own
// stopping rule, "converged" is decided by the certificate of DESIGN §3 (certify(),
// certificate.hpp) at the point returned, never by an engine's flag. A run that does not
// converge still returns its best point with its certificate.
//
// Engine-specific parameters are typed options of each engine (engine_parameters.hpp).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/certificate.hpp>
#include <hemivem/engine_parameters.hpp>
#include <hemivem/error.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

enum class MinimizerStatus {
  converged,            ///< the certificate is below the tolerance
  iteration_limit,      ///< max_iterations reached
  evaluation_limit,     ///< max_evaluations reached
  stalled,              ///< no further progress possible at the engine's precision
  stopped_by_callback,  ///< the callback asked to stop
  failed,               ///< the engine failed (message says why)
};

inline std::string to_string(MinimizerStatus s) {
  switch (s) {
    case MinimizerStatus::converged: return "converged";
    case MinimizerStatus::iteration_limit: return "iteration limit";
    case MinimizerStatus::evaluation_limit: return "evaluation limit";
    case MinimizerStatus::stalled: return "stalled";
    case MinimizerStatus::stopped_by_callback: return "stopped by callback";
    default: return "failed";
  }
}

/// One line of the per-iteration history (what "iteration" means is the engine's: a Newton
/// step, a DC step, an outer active-set pass, a continuation stage ...).
struct IterationRecord {
  int iteration = 0;
  double objective = 0.0;  ///< the reduced objective F at the current point
  double primal = 0.0;     ///< certificate at the current point
  double dual = 0.0;
  int active = 0;          ///< coordinates at a bound
  double seconds = 0.0;    ///< wall time since the start of minimize()
};

/// The options every engine shares.
struct MinimizerOptions {
  double tolerance = 1e-10;  ///< of the certificate (primal and dual)
  int max_iterations = 1000;
  int max_evaluations = 1000000;  ///< function + subgradient evaluations
  /// Called after every iteration; returning false stops the run (stopped_by_callback).
  std::function<bool(const IterationRecord&)> callback;
  int verbosity = 0;  ///< forwarded to engines that print; hemivem itself never prints

  bool is_valid(std::string* error) const {
    if (!(tolerance > 0.0 && tolerance < 1.0)) return invalid_field(error, "tolerance", "in (0, 1)", tolerance);
    if (max_iterations < 0) return invalid_field(error, "max_iterations", ">= 0", max_iterations);
    if (max_evaluations < 1) return invalid_field(error, "max_evaluations", ">= 1", max_evaluations);
    if (verbosity < 0) return invalid_field(error, "verbosity", ">= 0", verbosity);
    return true;
  }
};

/// A certified critical point of F found by a search over several starts (GlobalSearch):
/// the point, F there, its certificate, how many starts reached it and with which engines.
struct CriticalPoint {
  Eigen::VectorXd a;
  double objective = std::numeric_limits<double>::quiet_NaN();
  Certificate certificate;
  int starts = 0;
  std::vector<std::string> engines;
};

struct MinimizerResult {
  MinimizerStatus status = MinimizerStatus::failed;
  std::string message;
  Eigen::VectorXd a;          ///< the point returned (the best one found, snapped by the certificate)
  Eigen::VectorXd law_force;  ///< zeta of the certificate at a
  Eigen::VectorXd reaction;   ///< lambda of the certificate at a
  double objective = std::numeric_limits<double>::quiet_NaN();  ///< F(a)
  Certificate certificate;
  int iterations = 0;
  int function_evaluations = 0;
  int subgradient_evaluations = 0;
  std::vector<IterationRecord> history;
  std::map<std::string, double> timings;  ///< seconds by stage (at least "total")
  /// The problem's uniqueness margin is not positive (or unknown): F may have several
  /// critical points and the point returned is one of them.
  bool may_be_nonunique = true;
  /// A global search's distinct certified critical points, lowest F first (the point
  /// returned is the first); empty for a local engine.
  std::vector<CriticalPoint> critical_points;
  bool converged() const noexcept { return status == MinimizerStatus::converged; }
};

/// The number of coordinates of `a` exactly at one of their bounds.
inline int count_at_bound(const ReducedProblem& p, const Eigen::VectorXd& a) {
  int k = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) k += (a(i) == p.lower(i) || a(i) == p.upper(i)) ? 1 : 0;
  return k;
}

/// The scaffolding of one minimize() call, shared by every engine.
class MinimizerRun {
 public:
  /// InputError naming `engine` for invalid options, inconsistent sizes or a bad start.
  MinimizerRun(const std::string& engine, const ReducedProblem& problem, const Eigen::VectorXd& start,
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

  const ReducedProblem& problem() const noexcept { return p_; }
  const MinimizerOptions& options() const noexcept { return o_; }
  Eigen::Index size() const noexcept { return p_.size(); }
  /// The start projected onto C.
  const Eigen::VectorXd& start() const noexcept { return start_; }
  /// Seconds since the run began.
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }

  // ---- evaluations ----------------------------------------------------------------------
  void count_functions(int k = 1) noexcept { functions_ += k; }
  void count_subgradients(int k = 1) noexcept { subgradients_ += k; }
  int evaluations() const noexcept { return functions_ + subgradients_; }
  /// True when `more` evaluations still fit in max_evaluations.
  bool budget_left(int more = 1) const noexcept {
    return static_cast<long long>(evaluations()) + more <= o_.max_evaluations;
  }
  int iterations() const noexcept { return iterations_; }
  bool iterations_left() const noexcept { return iterations_ < o_.max_iterations; }

  // ---- the certificate and the best point ----------------------------------------------
  /// The certificate of x at the run's tolerance.
  Certificate check(const Eigen::VectorXd& x) const { return certificate(p_, x, o_.tolerance); }
  /// Offers a point for the result: a certified point beats one that is not, then the smaller
  /// worst residual wins (the first of equals stays). Returns true when x is certified.
  bool offer(const Eigen::VectorXd& x) { return offer(x, check(x)); }
  bool offer(const Eigen::VectorXd& x, const Certificate& c) {
    const bool good = c.converged();
    if (best_.size() == 0 || (good && !best_ok_) || (good == best_ok_ && c.worst() < best_cert_.worst())) {
      best_ = x;
      best_cert_ = c;
      best_ok_ = good;
    }
    return good;
  }
  bool has_certified_point() const noexcept { return best_ok_; }
  /// The best point offered so far (the start before any offer).
  const Eigen::VectorXd& best() const noexcept { return best_.size() == p_.size() ? best_ : start_; }

  // ---- history ----------------------------------------------------------------------------
  /// Records an iteration at x (F and its certificate), offers x, and returns the callback's
  /// verdict (true: go on).
  bool record(const Eigen::VectorXd& x) { return record(x, p_.energy(x), check(x)); }
  bool record(const Eigen::VectorXd& x, double objective, const Certificate& c) {
    offer(x, c);
    const IterationRecord r{++iterations_, objective, c.primal, c.dual, count_at_bound(p_, x), seconds()};
    history_.push_back(r);
    return !o_.callback || o_.callback(r);
  }
  /// Records the start as iteration 0 (it does not count as an iteration).
  void record_start(const Eigen::VectorXd& x, double objective, const Certificate& c) {
    offer(x, c);
    history_.push_back({0, objective, c.primal, c.dual, count_at_bound(p_, x), seconds()});
  }
  /// Adds seconds to an engine stage of the timings.
  void add_time(const std::string& stage, double seconds) { timings_[stage] += seconds; }

  // ---- the end ------------------------------------------------------------------------------
  /// The result at the best point offered (or `point` when given): certified and snapped, its
  /// objective, the forces, the history and counts. The status is converged when the
  /// certificate holds, whatever `reason`; otherwise `reason` (stalled when `reason` says
  /// converged). The message is `summary`, preceded by `why` when the run did not converge.
  MinimizerResult finish(MinimizerStatus reason, const std::string& why = {}, const std::string& summary = {},
                         const Eigen::VectorXd* point = nullptr) const {
    MinimizerResult r;
    CertifiedPoint cp = certify(p_, point ? *point : best(), o_.tolerance);
    r.certificate = cp.certificate;
    r.a = cp.a.size() == p_.size() ? std::move(cp.a) : (point ? *point : best());
    r.law_force = std::move(cp.law_force);
    r.reaction = std::move(cp.reaction);
    r.objective = r.a.size() == p_.size() && r.a.allFinite() ? p_.energy(r.a) : std::numeric_limits<double>::quiet_NaN();
    r.may_be_nonunique = !(p_.uniqueness_margin > 0.0);
    r.status = r.certificate.converged() && std::isfinite(r.objective)
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

 private:
  const ReducedProblem& p_;
  const MinimizerOptions& o_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  Eigen::VectorXd start_;
  int functions_ = 0, subgradients_ = 0, iterations_ = 0;
  Eigen::VectorXd best_;
  Certificate best_cert_;
  bool best_ok_ = false;
  std::vector<IterationRecord> history_;
  std::map<std::string, double> timings_;
};

class NonsmoothMinimizer {
 public:
  virtual ~NonsmoothMinimizer() = default;
  /// The engine's name: ssn, bundle-dca, nlopt-mma, ceres-active-set.
  virtual std::string name() const = 0;

  /// Minimizes from `start` (projected onto C first; empty: zero). Throws InputError for
  /// unusable options, an inconsistent problem or a start of the wrong size; algorithmic
  /// outcomes are statuses. The empty problem, and a start the certificate accepts, are
  /// answered at once (0 iterations; the start only for a local engine).
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const {
    MinimizerRun r(name(), problem, start, options);
    if (r.size() == 0) return r.finish(MinimizerStatus::converged, {}, "empty problem", &r.start());
    if (answers_certified_start() && r.offer(r.start()))
      return r.finish(MinimizerStatus::converged, {}, "the start is certified", &r.start());
    return run(r);
  }

 protected:
  /// A local engine answers a start the certificate accepts at once; a search for the lowest
  /// of several critical points (GlobalSearch) does not.
  virtual bool answers_certified_start() const noexcept { return true; }
  /// The engine's numerics on a problem with at least one unknown; ends with run.finish().
  virtual MinimizerResult run(MinimizerRun& run) const = 0;
};

}  // namespace hemivem
