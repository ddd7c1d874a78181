// The contract of a nonsmooth minimizer of the reduced contact problem (docs/reference/certificate.md, docs/reference/engines.md):
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t. a in C.
//
// An engine derives from NonsmoothMinimizer and writes its numerics only, in run(): the
// public minimize() checks the options, the problem and the start, answers the empty problem,
// and hands the engine a MinimizerRun (hemivem/minimizer_run.hpp), which keeps the clock, the
// evaluation counts, the history, the best point so far and builds the final result.
// Whatever the engine's own stopping rule, "converged" is decided by the certificate of
// docs/reference/certificate.md (certify(), certificate.hpp) at the point returned, never by an engine's flag. A run that does not
// converge still returns its best point with its certificate.
//
// Engine-specific parameters are typed options of each engine (engine_parameters.hpp).
#pragma once

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <string_view>
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
  unbounded,            ///< F is unbounded below: there is no solution (existence.hpp; message says along what)
};

/// "converged", "iteration limit", "evaluation limit", "stalled", "stopped by callback", "failed",
/// "unbounded".
std::string to_string(MinimizerStatus status);
/// The names of to_string (case-insensitive, '_' as ' '); InputError otherwise.
MinimizerStatus minimizer_status_from_string(std::string_view name);

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
  /// Decide first whether F is bounded below (check_existence, existence.hpp) and answer
  /// "unbounded" without iterating when it is not; a caller that decided it already for the
  /// same problem may skip it.
  bool check_existence = true;

  bool is_valid(std::string* error) const {
    if (const std::string why = tolerance_problem(tolerance); !why.empty()) {
      if (error) *error = "tolerance: " + why;
      return false;
    }
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

class MinimizerRun;

class NonsmoothMinimizer {
 public:
  virtual ~NonsmoothMinimizer() = default;
  /// The engine's name: ssn, bundle-dca, nlopt-mma, ceres-active-set.
  virtual std::string name() const = 0;

  /// Minimizes from `start` (projected onto C first; empty: zero). Throws InputError for
  /// unusable options, an inconsistent problem or a start of the wrong size; algorithmic
  /// outcomes are statuses. The empty problem, a problem whose F is unbounded below (status
  /// unbounded, the start returned) and a start the certificate accepts are answered at once
  /// (0 iterations; the start only for a local engine). A problem with groups of coordinates
  /// (ReducedProblem::groups) is an InputError naming the engine (groups_refusal()) unless it
  /// takes_groups().
  MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                           const MinimizerOptions& options) const;
  /// True when the engine minimizes laws of a group's norm (a solid's friction).
  virtual bool takes_groups() const noexcept { return false; }
  /// Why a problem with groups is refused, when takes_groups() is false: "NAME does not take
  /// groups of coordinates ...", or what an engine made of others names.
  virtual std::string groups_refusal() const;

 protected:
  /// A local engine answers a start the certificate accepts at once; a search for the lowest
  /// of several critical points (GlobalSearch) does not.
  virtual bool answers_certified_start() const noexcept { return true; }
  /// The engine's numerics on a problem with at least one unknown; ends with run.finish()
  /// (MinimizerRun: hemivem/minimizer_run.hpp).
  virtual MinimizerResult run(MinimizerRun& run) const = 0;
};

}  // namespace hemivem
