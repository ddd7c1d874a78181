// Helpers shared by the smoothing-based engines (nlopt-mma, ceres-active-set): the schedule of
// the continuation on the smoothing scale and the checks of its parameters, the smoothed
// energy F_eps and its gradient, and candidate points snapped onto the bounds.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/smoothed_law.hpp>

namespace hemivem::smoothing {

/// The scales of the continuation stages of a law: one stage (epsilon) when the law has no
/// kink; otherwise epsilon0, reduction * epsilon0, ... down to epsilon, and with epsilon = 0
/// (the law itself) the scales fall to 1e-12 before that last stage.
inline std::vector<double> schedule(const ContactLaw& law, double epsilon, double epsilon0, double reduction) {
  if (law.kinks().empty()) return {epsilon};
  const double floor = epsilon > 0.0 ? epsilon : std::min(1e-12, epsilon0);
  std::vector<double> s;
  for (double e = std::max(epsilon0, floor); e > floor * (1.0 + 1e-12); e *= reduction) s.push_back(e);
  s.push_back(floor);
  if (epsilon == 0.0) s.push_back(0.0);
  return s;
}

/// The checks of the fields the smoothing engines' options share: the continuation and the
/// snapping distance.
inline bool shared_fields_valid(double epsilon, double epsilon0, double reduction, double snap, std::string* error) {
  if (!(epsilon >= 0.0 && std::isfinite(epsilon))) return invalid_field(error, "epsilon", "finite and >= 0", epsilon);
  if (!(epsilon0 > 0.0 && std::isfinite(epsilon0))) return invalid_field(error, "epsilon0", "finite and > 0", epsilon0);
  if (!(reduction > 0.0 && reduction < 1.0)) return invalid_field(error, "reduction", "in (0, 1)", reduction);
  if (!(snap >= 0.0 && snap < 1.0)) return invalid_field(error, "snap", "in [0, 1)", snap);
  return true;
}

/// F_eps(a) = 1/2 a^T S a - c^T a + sum w_i j_eps(a_i) and its gradient.
inline double smoothed_energy(const ReducedProblem& p, const SmoothedLaw& law, const Eigen::VectorXd& a,
                              Eigen::VectorXd* gradient) {
  const Eigen::VectorXd Sa = p.S * a;
  double f = 0.5 * a.dot(Sa) - p.c.dot(a);
  if (gradient) *gradient = Sa - p.c;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    f += p.w(i) * law.value(a(i));
    if (gradient) (*gradient)(i) += p.w(i) * law.derivative(a(i));
  }
  return f;
}

/// F_eps(a) - F_eps(a0) computed without cancellation (the engines minimize it: near a
/// minimizer F_eps changes far below the roundoff of F_eps itself), and the gradient of F_eps.
struct AnchoredEnergy {
  const ReducedProblem* p = nullptr;
  const SmoothedLaw* law = nullptr;
  Eigen::VectorXd a0, g0;  // the anchor and S a0 - c

  AnchoredEnergy(const ReducedProblem& problem, const SmoothedLaw& l, const Eigen::VectorXd& anchor)
      : p(&problem), law(&l), a0(anchor), g0(problem.S * anchor - problem.c) {}

  double operator()(const Eigen::VectorXd& a, Eigen::VectorXd* gradient) const {
    const Eigen::VectorXd d = a - a0;
    const Eigen::VectorXd Sd = p->S * d;
    double f = d.dot(g0) + 0.5 * d.dot(Sd);
    for (Eigen::Index i = 0; i < a.size(); ++i) f += p->w(i) * law->difference(a0(i), a(i));
    if (gradient) {
      *gradient = g0 + Sd;
      for (Eigen::Index i = 0; i < a.size(); ++i) (*gradient)(i) += p->w(i) * law->derivative(a(i));
    }
    return f;
  }
};

/// Nodes within `delta` of a bound that the gradient pushes outward by more than `push`
/// are put on the bound (a free node near a bound has a vanishing gradient and stays).
inline Eigen::VectorXd snap_to_bounds(const ReducedProblem& p, const Eigen::VectorXd& a, const Eigen::VectorXd& gradient,
                                      double delta, double push) {
  Eigen::VectorXd s = p.project(a);
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (s(i) >= p.upper(i) - delta && gradient(i) < -push) s(i) = p.upper(i);
    if (s(i) <= p.lower(i) + delta && gradient(i) > push) s(i) = p.lower(i);
  }
  return s;
}

/// The gradient threshold of snap_to_bounds: well above what a free node shows once the
/// certificate holds.
inline double snap_push(const ReducedProblem& p, const MinimizerOptions& o) {
  return 100.0 * o.tolerance * std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, 1e-300);
}

/// Offers the feasible point P_C(a), then that point with the nodes near a bound pushed onto
/// it (snap_to_bounds, g the smoothed gradient at a), as results of the run; true as soon as
/// one is certified.
inline bool offer_candidates(MinimizerRun& run, const Eigen::VectorXd& a, const Eigen::VectorXd& g, double snap) {
  const ReducedProblem& p = run.problem();
  const Eigen::VectorXd feasible = p.project(a);
  return run.offer(feasible) || run.offer(snap_to_bounds(p, feasible, g, snap, snap_push(p, run.options())));
}

/// The message of a run that ends at the final smoothing scale without a certificate.
inline std::string smoothing_limit_message(double epsilon) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "smoothing scale %.3g reached without a certificate; nodes at a kink of j are certified only as "
                "epsilon -> 0 (error O(epsilon))",
                epsilon);
  return buf;
}

/// A length scale of the unknowns: the largest finite gap (an obstacle's +inf gap bounds
/// nothing), |a| of the start, or |c| / min S_ii.
inline double length_scale(const ReducedProblem& p, const Eigen::VectorXd& a) {
  const double cmax = std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, 1e-300);
  double gmax = 0.0;
  for (Eigen::Index i = 0; i < p.g.size(); ++i)
    if (std::isfinite(p.g(i))) gmax = std::max(gmax, std::abs(p.g(i)));
  return std::max({gmax, a.size() ? a.cwiseAbs().maxCoeff() : 0.0, cmax / std::max(p.S.diagonal().minCoeff(), 1e-300)});
}

/// What a smoothing engine's stages share during one minimize() call: the run, the current
/// point, the length scale of the unknowns and the snapping distance (`snap` times it), and
/// the reason and message of a stop.
struct EngineState {
  MinimizerRun& run;
  const ReducedProblem& p;
  Eigen::VectorXd a;
  double length = 0.0, snap = 0.0;
  MinimizerStatus reason = MinimizerStatus::stalled;
  std::string message;

  EngineState(MinimizerRun& r, double snap_fraction)
      : run(r), p(r.problem()), a(r.start()), length(length_scale(p, a)), snap(snap_fraction * std::max(length, 1e-300)) {}
};

}  // namespace hemivem::smoothing
