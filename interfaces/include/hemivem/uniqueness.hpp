// The uniqueness margin of a reduced problem (hemivem/reduced_problem.hpp), one implementation
// for the condensation, the reduced-problem files, the command and Python:
//
//   m = lambda_min(M),   M = S - diag(alpha_i w_i),
//
// alpha_i the curvature bound of coordinate i's law (ContactLaw::alpha). When m > 0, F is
// strongly convex and its critical point is unique.
//
// Round-off. The smallest eigenvalue is computed by a backward-stable symmetric eigensolver,
// so the computed value differs from the exact one of the stored M by a small multiple of
// eps ||M||_2, and S itself carries the round-off of the condensation. The bound used is
//
//   r = n * eps * (||S||_1 + max_i |alpha_i w_i|)       (||S||_1 >= ||S||_2 for a symmetric S)
//
// (widened by widen_uniqueness_roundoff where the condition number of the condensation's
// interior block is known) and a computed margin with |m| <= r is reported as exactly 0: F is then convex, up to
// round-off, but not strongly convex along some direction (a semi-coercive problem, or a law
// whose curvature bound is reached), and uniqueness is not proved. Only a margin above r proves
// it. A law with a concave kink (alpha = +inf) gives -inf; an empty problem +inf.
#pragma once

#include <Eigen/Core>

#include <limits>
#include <string>

#include <hemivem/reduced_problem.hpp>

namespace hemivem {

struct UniquenessMargin {
  double margin = std::numeric_limits<double>::quiet_NaN();    ///< m as reported: 0 when |computed| <= roundoff
  double computed = std::numeric_limits<double>::quiet_NaN();  ///< lambda_min(M) as computed
  double roundoff = std::numeric_limits<double>::quiet_NaN();  ///< r, the round-off bound
  /// m > 0 (beyond round-off): F is strongly convex, its critical point unique.
  bool proves_uniqueness() const noexcept { return margin > 0.0; }
};

/// The margin of S, w and the curvature bounds alpha (one per coordinate, or one for all).
UniquenessMargin measure_uniqueness(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, const Eigen::VectorXd& alpha);
/// The margin of a problem's S, w and laws (its sizes must fit: check_sizes).
UniquenessMargin measure_uniqueness(const ReducedProblem& p);

/// measure_uniqueness(...).margin.
double uniqueness_margin(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, double alpha);
double uniqueness_margin(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, const Eigen::VectorXd& alpha);

/// True when a margin given with a problem (a file's, a caller's) is the computed one: equal
/// (the same infinity included) or within the round-off bound plus 1e-8 relative.
bool margin_agrees(double given, const UniquenessMargin& computed);

/// A reported margin's verdict: "unique" (m > 0), "zero" (m = 0: convex, not strongly convex
/// along some direction), "negative" (F may have several critical points), "unknown" (NaN).
std::string uniqueness_verdict(double margin);
/// What that verdict means, as one sentence for reports.
std::string uniqueness_meaning(double margin);

/// Sets p.uniqueness_margin and p.uniqueness_roundoff from measure_uniqueness(p).
void set_uniqueness_margin(ReducedProblem& p);

/// Widens p's round-off bound by the round-off S carries from the condensation that produced
/// it: eps * kappa * ||S||_1, kappa an estimate of the condition number of the interior block
/// A22 that was factorized (a perturbation of the order eps kappa relative to ||S|| is what a
/// backward-stable elimination of A22 can leave in A12 A22^-1 A21). A margin within the wider
/// bound is then reported as exactly 0. Nothing changes for a kappa that is not finite or
/// positive, or a margin that is infinite or NaN.
void widen_uniqueness_roundoff(ReducedProblem& p, double kappa);

}  // namespace hemivem
