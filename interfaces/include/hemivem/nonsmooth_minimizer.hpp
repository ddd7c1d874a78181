// The contract of a nonsmooth minimizer of the reduced contact problem (DESIGN §3, §5):
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t. a in C.
//
// An engine sees the problem through ReducedProblem (energy, Clarke subgradients, the DC
// components F1 - F2, the constraint set and its projection). Whatever the engine's own
// stopping rule, the status "converged" is decided by the certificate of DESIGN §3
// (hemivem::certificate): residual <= tolerance and feasibility <= feasibility_tolerance.
// A run that does not converge still returns its best point with its certificate.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include <hemivem/reduced_problem.hpp>

namespace hemivem {

enum class MinimizerStatus {
  converged,            ///< the certificate is below the tolerances
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
  double energy = 0.0;       ///< F at the current point
  double residual = 0.0;     ///< certificate residual at the current point
  double feasibility = 0.0;  ///< certificate feasibility at the current point
  int active = 0;            ///< nodes at a bound
  double seconds = 0.0;      ///< wall time since the start of minimize()
};

/// One flat options struct. Engine-specific parameters go in `parameters` by name (each
/// engine documents its names; an unknown name is an InputError from that engine).
struct MinimizerOptions {
  double tolerance = 1e-10;              ///< on Certificate::residual
  double feasibility_tolerance = 1e-12;  ///< on Certificate::feasibility (units of a)
  int max_iterations = 1000;
  int max_evaluations = 1000000;         ///< function + subgradient evaluations
  /// Called after every iteration; returning false stops the run (stopped_by_callback).
  std::function<bool(const IterationRecord&)> callback;
  std::map<std::string, double> parameters;
  int verbosity = 0;  ///< forwarded to engines that print; hemivem itself never prints

  bool is_valid(std::string* error) const {
    auto fail = [&](const std::string& m) {
      if (error) *error = m;
      return false;
    };
    if (!(tolerance > 0.0)) return fail("tolerance must be > 0");
    if (!(feasibility_tolerance >= 0.0)) return fail("feasibility_tolerance must be >= 0");
    if (max_iterations < 1) return fail("max_iterations must be >= 1");
    if (max_evaluations < 1) return fail("max_evaluations must be >= 1");
    return true;
  }
};

struct MinimizerResult {
  MinimizerStatus status = MinimizerStatus::failed;
  std::string message;
  Eigen::VectorXd a;  ///< the point returned (the best one found)
  double energy = std::numeric_limits<double>::quiet_NaN();
  Certificate certificate;
  int iterations = 0;
  int function_evaluations = 0;
  int subgradient_evaluations = 0;
  std::vector<IterationRecord> history;
  std::map<std::string, double> timings;  ///< seconds by stage (at least "total")
  /// The problem's uniqueness margin is not positive (or unknown): F may have several
  /// critical points and the point returned is one of them.
  bool may_be_nonunique = true;
  bool converged() const noexcept { return status == MinimizerStatus::converged; }
};

class NonsmoothMinimizer {
 public:
  virtual ~NonsmoothMinimizer() = default;
  /// The engine's name: ssn, bundle-dca, nlopt-mma, ceres-active-set.
  virtual std::string name() const = 0;
  /// Minimizes from `start` (projected onto C first; empty: zero). Throws InputError for
  /// unusable options or a start of the wrong size; algorithmic outcomes are statuses.
  virtual MinimizerResult minimize(const ReducedProblem& problem, const Eigen::VectorXd& start,
                                   const MinimizerOptions& options) const = 0;
};

/// Sets result.certificate and result.energy at result.a and decides the status from the
/// certificate: converged when it is below the tolerances; otherwise `otherwise` (the
/// engine's reason for stopping). Every engine ends its minimize() with this.
inline void finish(const ReducedProblem& p, const MinimizerOptions& o, MinimizerStatus otherwise,
                   MinimizerResult& result) {
  result.certificate = certificate(p, result.a);
  result.energy = result.a.allFinite() && result.a.size() == p.size() ? p.energy(result.a)
                                                                       : std::numeric_limits<double>::quiet_NaN();
  const bool ok = result.certificate.residual <= o.tolerance &&
                  result.certificate.feasibility <= o.feasibility_tolerance;
  result.may_be_nonunique = !(p.uniqueness_margin > 0.0);
  result.status = ok ? MinimizerStatus::converged
                     : (otherwise == MinimizerStatus::converged ? MinimizerStatus::stalled : otherwise);
}

}  // namespace hemivem
