// The certificate of a point of the reduced problem (DESIGN §3): a primal and a dual
// residual, each dimensionless, decided by this one implementation for every engine, for
// the command's reports and for `check`.
//
//   1. Scales. D = diag(S); the length scale
//        l = max(||a||_inf, max |bound| over the finite bounds, ||D^-1 c||_inf)
//      and, after step 3, the force scale
//        f = max(||c||_inf, ||S a||_inf, ||zeta||_inf, force_floor).
//   2. Snap. Every coordinate within tol * l of one of its bounds or of a kink of the law
//      (ContactLaw::kinks of the coordinate's law) is put exactly there (the nearer one; a bound before a kink at the
//      same distance). The snapped point is the one reported and certified.
//   3. Forces. Per coordinate the law force zeta_i in w_i [j'(a_i-), j'(a_i+)] and the reaction
//      lambda_i of the constraint (0 off the bounds, >= 0 at an upper bound, <= 0 at a lower
//      one, free where both bounds coincide) minimise |(S a - c)_i + zeta_i + lambda_i|; of the
//      minimisers the one with the smallest |lambda_i| is taken. The contact force of node i
//      is zeta_i + lambda_i.
//   4. primal = ||dist(a, C)||_inf / l, dual = ||S a - c + zeta + lambda||_inf / f;
//      converged <=> primal <= tol and dual <= tol.
//
// Both numbers are unchanged when S, c and w j are multiplied by one factor (a change of the
// unit of force) and when lengths are (a, g, the kinks and c / S by one factor, j' by it too:
// a change of the unit of length). A residual of exactly zero is zero whatever the scales (so
// a = 0 solves a problem with c = 0 and no law force at 0).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <hemivem/reduced_problem.hpp>

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
inline double balance(double r, Interval law, Interval reaction, double* zeta, double* lambda) {
  *zeta = law.nearest(-r);
  *lambda = reaction.nearest(-r - *zeta);
  return std::abs(r + *zeta + *lambda);
}

/// The certificate of `a` for `p` at tolerance `tol` (DESIGN §3). A point of the wrong size or
/// with a non-finite entry gets infinite residuals.
inline CertifiedPoint certify(const ReducedProblem& p, const Eigen::VectorXd& a, double tol) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  CertifiedPoint out;
  out.certificate.tolerance = tol;
  const Eigen::Index n = p.size();
  if (a.size() != n || !a.allFinite() || !p.law) return out;
  out.a = a;
  out.law_force = Eigen::VectorXd::Zero(n);
  out.reaction = Eigen::VectorXd::Zero(n);
  if (n == 0) {
    out.certificate.primal = out.certificate.dual = 0.0;
    out.certificate.length_scale = out.certificate.force_scale = 0.0;
    return out;
  }
  // 1. the length scale
  double ell = a.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (double b : {p.lower(i), p.upper(i)})
      if (std::isfinite(b)) ell = std::max(ell, std::abs(b));
    const double d = p.S(i, i);
    ell = std::max(ell, d > 0.0 ? std::abs(p.c(i)) / d : (p.c(i) == 0.0 ? 0.0 : inf));
  }
  // 2. snapping onto bounds and kinks (of each coordinate's law)
  std::vector<std::vector<double>> kinks_of(static_cast<std::size_t>(p.num_laws()));
  for (int k = 0; k < p.num_laws(); ++k) kinks_of[static_cast<std::size_t>(k)] = p.law_by_number(k).kinks();
  const double window = tol * ell;
  Eigen::VectorXd& x = out.a;
  double primal = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = p.lower(i), hi = p.upper(i);
    double target = x(i), distance = inf;
    for (double b : {lo, hi}) {
      const double d = std::abs(x(i) - b);
      if (std::isfinite(b) && d <= window && d < distance) target = b, distance = d;
    }
    const std::vector<double>& kinks = kinks_of[static_cast<std::size_t>(p.law_number(i))];
    const auto k = std::lower_bound(kinks.begin(), kinks.end(), x(i));
    for (auto it : {k, k == kinks.begin() ? k : k - 1}) {
      if (it == kinks.end()) continue;
      const double d = std::abs(x(i) - *it);
      if (d <= window && d < distance && *it >= lo && *it <= hi) target = *it, distance = d;
    }
    x(i) = target;
    primal = std::max(primal, std::max(lo - x(i), x(i) - hi));
  }
  // 3. forces
  const Eigen::VectorXd Sa = p.S * x;
  double worst = 0.0, zeta_max = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = p.lower(i), hi = p.upper(i);
    const Interval dj = p.law_of(i).clarke(x(i));
    const Interval law{p.w(i) * dj.lo, p.w(i) * dj.hi};
    const Interval reaction{x(i) == lo ? -inf : 0.0, x(i) == hi ? inf : 0.0};
    worst = std::max(worst, balance(Sa(i) - p.c(i), law, reaction, &out.law_force(i), &out.reaction(i)));
    zeta_max = std::max(zeta_max, std::abs(out.law_force(i)));
  }
  const double f = std::max({p.c.cwiseAbs().maxCoeff(), Sa.cwiseAbs().maxCoeff(), zeta_max, force_floor});
  // 4. the residuals (exactly zero stays zero, also where a scale vanishes)
  Certificate& c = out.certificate;
  c.length_scale = ell;
  c.force_scale = f;
  c.primal = primal <= 0.0 ? 0.0 : primal / ell;
  c.dual = worst == 0.0 ? 0.0 : worst / f;
  if (std::isnan(c.primal)) c.primal = inf;
  if (std::isnan(c.dual)) c.dual = inf;
  return out;
}

/// The numbers only.
inline Certificate certificate(const ReducedProblem& p, const Eigen::VectorXd& a, double tol) {
  return certify(p, a, tol).certificate;
}

}  // namespace hemivem
