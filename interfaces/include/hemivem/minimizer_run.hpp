// The scaffolding of one NonsmoothMinimizer::minimize() call, shared by every engine: what an
// engine's run() works with, and what only engines (and tests of them) include.
//
// A MinimizerRun keeps the clock, the evaluation and iteration counts against the options'
// budgets, the history, and the best point offered so far (a certified point beats one that is
// not, then the smaller worst residual); finish() builds the MinimizerResult at that point,
// certified and snapped by certify() (hemivem/certificate.hpp).
#pragma once

#include <Eigen/Core>

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include <hemivem/certificate.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

/// The number of coordinates of `a` exactly at one of their bounds.
int count_at_bound(const ReducedProblem& p, const Eigen::VectorXd& a);

class MinimizerRun {
 public:
  /// InputError naming `engine` for invalid options, inconsistent sizes or a bad start.
  MinimizerRun(const std::string& engine, const ReducedProblem& problem, const Eigen::VectorXd& start,
               const MinimizerOptions& options);

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
  bool offer(const Eigen::VectorXd& x, const Certificate& c);
  bool has_certified_point() const noexcept { return best_ok_; }
  /// The best point offered so far (the start before any offer).
  const Eigen::VectorXd& best() const noexcept { return best_.size() == p_.size() ? best_ : start_; }

  // ---- history ----------------------------------------------------------------------------
  /// Records an iteration at x (F and its certificate), offers x, and returns the callback's
  /// verdict (true: go on).
  bool record(const Eigen::VectorXd& x) { return record(x, p_.energy(x), check(x)); }
  bool record(const Eigen::VectorXd& x, double objective, const Certificate& c);
  /// Records the start as iteration 0 (it does not count as an iteration).
  void record_start(const Eigen::VectorXd& x, double objective, const Certificate& c);
  /// Adds seconds to an engine stage of the timings.
  void add_time(const std::string& stage, double seconds) { timings_[stage] += seconds; }

  // ---- the end ------------------------------------------------------------------------------
  /// The result at the best point offered (or `point` when given): certified and snapped, its
  /// objective, the forces, the history and counts. The status is converged when the
  /// certificate holds, whatever `reason`; otherwise `reason` (stalled when `reason` says
  /// converged). The message is `summary`, preceded by `why` when the run did not converge.
  MinimizerResult finish(MinimizerStatus reason, const std::string& why = {}, const std::string& summary = {},
                         const Eigen::VectorXd* point = nullptr) const;

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

}  // namespace hemivem
