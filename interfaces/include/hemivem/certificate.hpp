// The certificate of a point of the reduced problem (docs/reference/certificate.md): a primal and a dual
// residual, each dimensionless, decided by this one implementation for every engine, for
// the command's reports and for `check`.
//
//   1. Scales. D = diag(S); the length scale
//        l = max(||a||_inf, max |bound| over the finite bounds, ||D^-1 c||_inf)
//      and, after step 3, the force scale
//        f = max(||c||_inf, ||S a||_inf, ||zeta||_inf, force_floor).
//   2. Snap. Every coordinate within tol * l of one of its bounds or of a kink of the law
//      (ContactLaw::kinks of the coordinate's law) is put exactly there (the nearer one; a bound before a kink at the
//      same distance). A group of coordinates (ReducedProblem::groups) has its norm snapped
//      instead: onto a positive kink of its law, or onto 0 where j'(0+) > 0, by scaling the
//      pair. The snapped point is the one reported and certified.
//   3. Forces. Per coordinate the law force zeta_i in w_i [j'(a_i-), j'(a_i+)] and the reaction
//      lambda_i of the constraint (0 off the bounds, >= 0 at an upper bound, <= 0 at a lower
//      one, free where both bounds coincide) minimise |(S a - c)_i + zeta_i + lambda_i|; of the
//      minimisers the one with the smallest |lambda_i| is taken. The contact force of node i
//      is zeta_i + lambda_i. A group's law force zeta_G (a pair, no reaction) is the point
//      nearest to -(S a - c)_G of w times its Clarke subdifferential: on the ray of a_G at a
//      length in w [j'(r-), j'(r+)], r = |a_G| > 0; in the disc of radius w j'(0+) at a_G = 0.
//   4. primal = ||dist(a, C)||_inf / l, dual = ||S a - c + zeta + lambda||_inf / f, the
//      maximum over single coordinates of |.| and over groups of the pair's Euclidean norm;
//      converged <=> primal <= tol and dual <= tol.
//
// Both numbers are unchanged when S, c and w j are multiplied by one factor (a change of the
// unit of force) and when lengths are (a, g, the kinks and c / S by one factor, j' by it too:
// a change of the unit of length). A residual of exactly zero is zero whatever the scales (so
// a = 0 solves a problem with c = 0 and no law force at 0).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <functional>
#include <limits>
#include <string>

#include <hemivem/reduced_problem.hpp>
#include <hemivem/row_distribution.hpp>

namespace hemivem {

/// The numbers of the certificate at one point.
struct Certificate {
  double primal = std::numeric_limits<double>::infinity();  ///< ||dist(a, C)||_inf / length_scale
  double dual = std::numeric_limits<double>::infinity();    ///< ||S a - c + zeta + lambda||_inf / force_scale
  double length_scale = std::numeric_limits<double>::quiet_NaN();  ///< l (units of a)
  double force_scale = std::numeric_limits<double>::quiet_NaN();   ///< f (units of c)
  double tolerance = std::numeric_limits<double>::quiet_NaN();     ///< tol, of snapping and of the verdict
  /// primal <= tolerance and dual <= tolerance (false for NaN anywhere).
  bool converged() const noexcept { return primal <= tolerance && dual <= tolerance; }
  /// The larger residual (what an engine drives to zero).
  double worst() const noexcept { return std::max(primal, dual); }
};

/// The range of tolerances the certificate accepts, [min_tolerance, max_tolerance]
/// (docs/reference/certificate.md says why): above 1e-2 "converged" would certify residuals of
/// more than a percent of the forces and snap coordinates by more than a percent of the length
/// scale; below it every positive normal number is accepted (a tolerance under round-off is
/// never reached, and the engines then report stalled, which is true).
inline constexpr double min_tolerance = 1e-300;
inline constexpr double max_tolerance = 1e-2;

/// Empty when tol lies in [min_tolerance, max_tolerance]; otherwise what is wrong with it
/// ("must be in [1e-300, 0.01], got 0.5"), for a message that names the key, flag or argument.
std::string tolerance_problem(double tol);
/// InputError "`what`: must be in [...], got X" (where `where`) unless tol is in range.
void check_tolerance(double tol, const std::string& what, const std::string& where = {});

/// The smallest force scale: it only keeps 0 / 0 out of the dual residual, so that a problem
/// whose forces all vanish (c = 0, a = 0) is solved.
inline constexpr double force_floor = std::numeric_limits<double>::min();

/// The certificate with the point it certifies and the forces it found.
struct CertifiedPoint {
  Eigen::VectorXd a;          ///< the snapped point
  Eigen::VectorXd law_force;  ///< zeta
  Eigen::VectorXd reaction;   ///< lambda
  Certificate certificate;
};

/// Of the values zeta in `law` and lambda in `reaction` (closed intervals, reaction containing
/// 0), those minimising |r + zeta + lambda| with the smallest |lambda|; returns that minimum.
double balance(double r, Interval law, Interval reaction, double* zeta, double* lambda);

/// The certificate of `a` for `p` at tolerance `tol` (steps 1 to 4 above). A point of the wrong
/// size or with a non-finite entry, or a problem without laws, gets infinite residuals. A
/// tolerance outside [min_tolerance, max_tolerance] is an InputError naming "tolerance".
CertifiedPoint certify(const ReducedProblem& p, const Eigen::VectorXd& a, double tol);

/// The numbers only.
Certificate certificate(const ReducedProblem& p, const Eigen::VectorXd& a, double tol);

/// The gradient of the smooth part of the energy at a point, as the certificate reads it.
struct SmoothGradient {
  /// Per coordinate, (S a - c)_i: for a problem that is not condensed (the full-space route),
  /// the entry of the whole system's residual A x - b at the coordinate's unknown.
  Eigen::VectorXd r;
  /// ||.||_inf of the residual of the unknowns that are not coordinates (0 for the reduced
  /// problem, where they are eliminated): a force out of balance like any other.
  double other = 0.0;
  /// The size of the forces: max(||c||_inf, ||S a||_inf) for the reduced problem;
  /// max(||b||_inf, ||A x||_inf) over the whole system.
  double force_size = 0.0;
};

/// The certificate of a point of a problem that is not condensed (hemivem/contact/full_space.hpp):
/// the same four steps with the laws, weights and bounds of `p` (its S and c are not read),
/// the smooth gradient at the snapped coordinates from `gradient` (called once, with the snapped
/// point), the dual residual the larger of the coordinates' and `other`, and the length scale's
/// ||D^-1 c||_inf from `stiffness` and `load` per coordinate (the diagonal of A and b there).
/// With gradient(a) = {S a - c, 0, max(||c||, ||S a||)}, stiffness = diag(S) and load = c this
/// is certify(p, a, tol) exactly.
///
/// With `processes` (a problem distributed over processes, hemivem/row_distribution.hpp) `p`, `a`,
/// `stiffness` and `load` are this process's coordinates, `gradient` is collective, and the
/// scales and residuals are the largest over the processes: every process returns the same
/// certificate, of the whole problem. The call is then collective.
CertifiedPoint certify(const ReducedProblem& p, const Eigen::VectorXd& a, double tol,
                       const std::function<SmoothGradient(const Eigen::VectorXd&)>& gradient,
                       const Eigen::VectorXd& stiffness, const Eigen::VectorXd& load,
                       const RowDistribution* processes = nullptr);

}  // namespace hemivem
