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

#include <hemivem/minimizer_run.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/smoothed_law.hpp>

namespace hemivem::smoothing {

/// Whether a law of the problem has a kink (smoothing changes the problem only then).
inline bool has_kinks(const ReducedProblem& p) {
  for (int k = 0; k < p.num_laws(); ++k)
    if (!p.law_by_number(k).kinks().empty()) return true;
  return false;
}

/// The scales of the continuation stages of a problem: one stage (epsilon) when no law has a
/// kink; otherwise epsilon0, reduction * epsilon0, ... down to epsilon, and with epsilon = 0
/// (the laws themselves) the scales fall to 1e-12 before that last stage.
inline std::vector<double> schedule(const ReducedProblem& p, double epsilon, double epsilon0, double reduction) {
  if (!has_kinks(p)) return {epsilon};
  const double floor = epsilon > 0.0 ? epsilon : std::min(1e-12, epsilon0);
  std::vector<double> s;
  for (double e = std::max(epsilon0, floor); e > floor * (1.0 + 1e-12); e *= reduction) s.push_back(e);
  s.push_back(floor);
  if (epsilon == 0.0) s.push_back(0.0);
  return s;
}

/// The laws of a problem smoothed at one scale: at(i) is coordinate i's.
class SmoothedLaws {
 public:
  SmoothedLaws(const ReducedProblem& p, double epsilon) : p_(&p) {
    for (int k = 0; k < p.num_laws(); ++k)
      laws_.emplace_back(p.laws[static_cast<std::size_t>(k)], epsilon);
  }
  const SmoothedLaw& at(Eigen::Index i) const { return laws_[static_cast<std::size_t>(p_->law_index(i))]; }
  /// The number of kinks smoothed, over all laws.
  int kinks() const {
    int k = 0;
    for (const auto& l : laws_) k += l.kinks();
    return k;
  }

 private:
  const ReducedProblem* p_;
  std::vector<SmoothedLaw> laws_;
};

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
inline double smoothed_energy(const ReducedProblem& p, const SmoothedLaws& law, const Eigen::VectorXd& a,
                              Eigen::VectorXd* gradient) {
  const Eigen::VectorXd Sa = p.S * a;
  double f = 0.5 * a.dot(Sa) - p.c.dot(a);
  if (gradient) *gradient = Sa - p.c;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    f += p.w(i) * law.at(i).value(a(i));
    if (gradient) (*gradient)(i) += p.w(i) * law.at(i).derivative(a(i));
  }
  return f;
}

/// F_eps(a) - F_eps(a0) computed without cancellation (the engines minimize it: near a
/// minimizer F_eps changes far below the roundoff of F_eps itself), and the gradient of F_eps.
struct AnchoredEnergy {
  const ReducedProblem* p = nullptr;
  const SmoothedLaws* law = nullptr;
  Eigen::VectorXd a0, g0;  // the anchor and S a0 - c

  AnchoredEnergy(const ReducedProblem& problem, const SmoothedLaws& l, const Eigen::VectorXd& anchor)
      : p(&problem), law(&l), a0(anchor), g0(problem.S * anchor - problem.c) {}

  double operator()(const Eigen::VectorXd& a, Eigen::VectorXd* gradient) const {
    const Eigen::VectorXd d = a - a0;
    const Eigen::VectorXd Sd = p->S * d;
    double f = d.dot(g0) + 0.5 * d.dot(Sd);
    for (Eigen::Index i = 0; i < a.size(); ++i) f += p->w(i) * law->at(i).difference(a0(i), a(i));
    if (gradient) {
      *gradient = g0 + Sd;
      for (Eigen::Index i = 0; i < a.size(); ++i) (*gradient)(i) += p->w(i) * law->at(i).derivative(a(i));
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

/// Nodes strictly inside the rounding window of a kink of their law are put on the kink, and
/// marked in *on_kink: where the smoothed problem holds a node within epsilon of a kink, the
/// nonsmooth one sticks it there (the Clarke interval at the kink takes up the force; the
/// certificate decides).
inline Eigen::VectorXd snap_to_kinks(const ReducedProblem& p, const SmoothedLaws& law, const Eigen::VectorXd& a,
                                     std::vector<char>* on_kink) {
  Eigen::VectorXd s = a;
  on_kink->assign(static_cast<std::size_t>(a.size()), 0);
  for (Eigen::Index i = 0; i < a.size(); ++i)
    for (const auto& w : law.at(i).windows())
      if (w.kink && a(i) > w.lo && a(i) < w.hi && w.breakpoint >= p.lower(i) && w.breakpoint <= p.upper(i)) {
        s(i) = w.breakpoint;
        (*on_kink)[static_cast<std::size_t>(i)] = 1;
      }
  return s;
}

/// Nodes stuck on a kink (marked in *on_kink) whose force c_i - (S a)_i lies outside the
/// kink's interval w_i [j'(b-), j'(b+)] by more than `slack` are let go (unmarked): the
/// nonsmooth problem moves them off the kink. True when any was.
inline bool release_from_kinks(const ReducedProblem& p, const Eigen::VectorXd& a, double slack,
                               std::vector<char>* on_kink) {
  bool released = false;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!(*on_kink)[static_cast<std::size_t>(i)]) continue;
    const double force = p.c(i) - p.S.row(i).dot(a);
    const ContactLaw& j = p.law_of(i);
    const double lo = p.w(i) * j.derivative(LawPart::j, a(i), -1), hi = p.w(i) * j.derivative(LawPart::j, a(i), +1);
    if (force > hi + slack || force < lo - slack) {
      (*on_kink)[static_cast<std::size_t>(i)] = 0;
      released = true;
    }
  }
  return released;
}

/// How often the stuck nodes are solved for and let go (release_from_kinks) at most.
inline constexpr int kink_rounds = 8;

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

/// A length scale of the unknowns: the largest finite bound (an obstacle's +inf gap bounds
/// nothing), |a| of the start, or |c| / min S_ii.
inline double length_scale(const ReducedProblem& p, const Eigen::VectorXd& a) {
  const double cmax = std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, 1e-300);
  double gmax = 0.0;
  for (Eigen::Index i = 0; i < p.size(); ++i)
    for (double b : {p.lower(i), p.upper(i)})
      if (std::isfinite(b)) gmax = std::max(gmax, std::abs(b));
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
