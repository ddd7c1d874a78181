// Helpers shared by the smoothing-based engines (nlopt-mma, ceres-active-set): the schedule of
// the continuation on the smoothing scale and the checks of its parameters, the smoothed
// energy F_eps and its gradient, and candidate points snapped onto the bounds.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/minimizer_run.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/smoothed_law.hpp>

namespace hemivem::smoothing {

/// Whether a law of the problem has a kink, or a group's law of its norm one (at 0 where
/// j'(0+) > 0: the EvenExtension's kinks); smoothing changes the problem only then.
inline bool has_kinks(const ReducedProblem& p) {
  for (int k = 0; k < p.num_laws(); ++k)
    if (!p.law_by_number(k).kinks().empty()) return true;
  for (const CoordinateGroup& g : p.groups)
    if (!EvenExtension(p.laws[static_cast<std::size_t>(p.law_index(g.first))]).kinks().empty()) return true;
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

/// The laws of a problem smoothed at one scale: at(i) is coordinate i's; a group's law of its
/// norm is the smoothed EvenExtension of its law, of_group(g), taken at r = |v| >= 0.
class SmoothedLaws {
 public:
  SmoothedLaws(const ReducedProblem& p, double epsilon) : p_(&p) {
    for (int k = 0; k < p.num_laws(); ++k)
      laws_.emplace_back(p.laws[static_cast<std::size_t>(k)], epsilon);
    if (p.groups.empty()) return;
    group_laws_.resize(laws_.size());
    grouped_.assign(static_cast<std::size_t>(p.size()), 0);
    for (const CoordinateGroup& g : p.groups) {
      const auto k = static_cast<std::size_t>(p.law_index(g.first));
      if (!group_laws_[k]) group_laws_[k].emplace(std::make_shared<const EvenExtension>(p.laws[k]), epsilon);
      grouped_[static_cast<std::size_t>(g.first)] = grouped_[static_cast<std::size_t>(g.second)] = 1;
    }
  }
  const SmoothedLaw& at(Eigen::Index i) const { return laws_[static_cast<std::size_t>(p_->law_index(i))]; }
  /// The smoothed law of group g's norm.
  const SmoothedLaw& of_group(const CoordinateGroup& g) const {
    return *group_laws_[static_cast<std::size_t>(p_->law_index(g.first))];
  }
  /// True when coordinate i belongs to a group (its law term is the group's).
  bool grouped(Eigen::Index i) const { return !grouped_.empty() && grouped_[static_cast<std::size_t>(i)]; }
  /// The number of kinks smoothed, over all laws and the laws of the groups' norms.
  int kinks() const {
    int k = 0;
    for (const auto& l : laws_) k += l.kinks();
    for (const auto& l : group_laws_)
      if (l) k += l->kinks();
    return k;
  }

 private:
  const ReducedProblem* p_;
  std::vector<SmoothedLaw> laws_;
  std::vector<std::optional<SmoothedLaw>> group_laws_;  // by law number, for the laws of groups
  std::vector<char> grouped_;                           // per coordinate (empty without groups)
};

/// w j_eps(|v|) of group g at the point a (v = (a_first, a_second)), and its gradient added to
/// *gradient: w j_eps'(|v|) v / |v|, 0 at v = 0 (j_eps' vanishes there: EvenExtension).
inline double group_term(const ReducedProblem& p, const SmoothedLaws& law, const CoordinateGroup& g,
                         const Eigen::VectorXd& a, Eigen::VectorXd* gradient) {
  const double r = group_norm(a, g), w = p.w(g.first);
  const SmoothedLaw& j = law.of_group(g);
  if (gradient && r > 0.0) {
    const double s = w * j.derivative(r) / r;
    (*gradient)(g.first) += s * a(g.first);
    (*gradient)(g.second) += s * a(g.second);
  }
  return w * j.value(r);
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

/// F_eps(a) = 1/2 a^T S a - c^T a + sum w_i j_eps(a_i) (+ w j_eps(|a_G|) per group) and its
/// gradient.
inline double smoothed_energy(const ReducedProblem& p, const SmoothedLaws& law, const Eigen::VectorXd& a,
                              Eigen::VectorXd* gradient) {
  const Eigen::VectorXd Sa = p.S * a;
  double f = 0.5 * a.dot(Sa) - p.c.dot(a);
  if (gradient) *gradient = Sa - p.c;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (law.grouped(i)) continue;
    f += p.w(i) * law.at(i).value(a(i));
    if (gradient) (*gradient)(i) += p.w(i) * law.at(i).derivative(a(i));
  }
  for (const CoordinateGroup& g : p.groups) f += group_term(p, law, g, a, gradient);
  return f;
}

/// j_eps(|v|) - j_eps(|v0|) for group g's pair v in a and v0 in a0, without cancellation: the
/// mean of j_eps' over [|v0|, |v|] (SmoothedLaw::difference) times |v| - |v0|, the latter as
/// (v - v0).(v + v0) / (|v| + |v0|) (near a minimizer |v| - |v0| is far below the round-off of
/// the norms themselves).
inline double group_difference(const SmoothedLaw& j, const CoordinateGroup& g, const Eigen::VectorXd& a0,
                               const Eigen::VectorXd& a) {
  const double r0 = group_norm(a0, g), r = group_norm(a, g);
  if (r + r0 == 0.0) return 0.0;
  const double dr = ((a(g.first) - a0(g.first)) * (a(g.first) + a0(g.first)) +
                     (a(g.second) - a0(g.second)) * (a(g.second) + a0(g.second))) /
                    (r + r0);
  if (r == r0) return j.derivative(r) * dr;
  return j.difference(r0, r) / (r - r0) * dr;
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
    for (Eigen::Index i = 0; i < a.size(); ++i)
      if (!law->grouped(i)) f += p->w(i) * law->at(i).difference(a0(i), a(i));
    for (const CoordinateGroup& g : p->groups)
      f += p->w(g.first) * group_difference(law->of_group(g), g, a0, a);
    if (gradient) {
      *gradient = g0 + Sd;
      for (Eigen::Index i = 0; i < a.size(); ++i)
        if (!law->grouped(i)) (*gradient)(i) += p->w(i) * law->at(i).derivative(a(i));
      for (const CoordinateGroup& g : p->groups) group_term(*p, *law, g, a, gradient);
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
/// certificate decides). A group whose norm lies inside the window of a kink of its norm's law
/// is scaled onto it, v = 0 for the kink at 0, and both its coordinates are marked.
inline Eigen::VectorXd snap_to_kinks(const ReducedProblem& p, const SmoothedLaws& law, const Eigen::VectorXd& a,
                                     std::vector<char>* on_kink) {
  Eigen::VectorXd s = a;
  on_kink->assign(static_cast<std::size_t>(a.size()), 0);
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (law.grouped(i)) continue;
    for (const auto& w : law.at(i).windows())
      if (w.kink && a(i) > w.lo && a(i) < w.hi && w.breakpoint >= p.lower(i) && w.breakpoint <= p.upper(i)) {
        s(i) = w.breakpoint;
        (*on_kink)[static_cast<std::size_t>(i)] = 1;
      }
  }
  for (const CoordinateGroup& g : p.groups) {
    const double r = group_norm(a, g);
    for (const auto& w : law.of_group(g).windows()) {
      if (!w.kink || w.breakpoint < 0.0 || !(r > w.lo && r < w.hi)) continue;
      const double scale = w.breakpoint == 0.0 ? 0.0 : w.breakpoint / r;
      s(g.first) = scale * a(g.first);
      s(g.second) = scale * a(g.second);
      (*on_kink)[static_cast<std::size_t>(g.first)] = (*on_kink)[static_cast<std::size_t>(g.second)] = 1;
    }
  }
  return s;
}

/// Nodes stuck on a kink (marked in *on_kink) whose force c_i - (S a)_i lies outside the
/// kink's interval w_i [j'(b-), j'(b+)] by more than `slack` are let go (unmarked): the
/// nonsmooth problem moves them off the kink. A stuck group is let go when its force
/// f = (c - S a)_G leaves w times the Clarke subdifferential of j(|v|) by more than `slack`: at
/// v = 0 when |f| > w j'(0+) + slack; at |v| = b > 0 when f's component along v leaves
/// w [j'(b-), j'(b+)] or its component across v exceeds `slack`. True when any was.
inline bool release_from_kinks(const ReducedProblem& p, const Eigen::VectorXd& a, double slack,
                               std::vector<char>* on_kink) {
  bool released = false;
  const Eigen::VectorXi group_of = p.groups.empty() ? Eigen::VectorXi() : p.group_of();
  for (const CoordinateGroup& g : p.groups) {
    if (!(*on_kink)[static_cast<std::size_t>(g.first)]) continue;
    const Eigen::Vector2d force(p.c(g.first) - p.S.row(g.first).dot(a), p.c(g.second) - p.S.row(g.second).dot(a));
    const ContactLaw& j = p.law_of(g.first);
    const double w = p.w(g.first), r = group_norm(a, g);
    bool leaves = false;
    if (r == 0.0) {
      leaves = force.norm() > w * j.derivative(LawPart::j, 0.0, +1) + slack;
    } else {
      const Eigen::Vector2d e = Eigen::Vector2d(a(g.first), a(g.second)) / r;
      const double along = force.dot(e), across = (force - along * e).norm();
      const double lo = w * j.derivative(LawPart::j, r, -1), hi = w * j.derivative(LawPart::j, r, +1);
      leaves = along > hi + slack || along < lo - slack || across > slack;
    }
    if (leaves) {
      (*on_kink)[static_cast<std::size_t>(g.first)] = (*on_kink)[static_cast<std::size_t>(g.second)] = 0;
      released = true;
    }
  }
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!(*on_kink)[static_cast<std::size_t>(i)] || (group_of.size() && group_of(i) >= 0)) continue;
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

/// Groups that the force at v = 0 keeps there, |(c - S a)_G + S_GG v_G| <= w j'(0+) (stuck in the
/// nonsmooth problem, the other coordinates held), are put at v = 0 in *a and marked in *held
/// (both coordinates); the other groups are left alone. Nothing happens without groups.
inline void hold_stuck_groups(const ReducedProblem& p, Eigen::VectorXd* a, std::vector<char>* held) {
  if (p.groups.empty()) return;
  const Eigen::VectorXd force = p.c - p.S * *a;
  std::vector<const CoordinateGroup*> stuck;
  for (const CoordinateGroup& g : p.groups) {
    const double v1 = (*a)(g.first), v2 = (*a)(g.second);
    const double f1 = force(g.first) + p.S(g.first, g.first) * v1 + p.S(g.first, g.second) * v2;
    const double f2 = force(g.second) + p.S(g.second, g.first) * v1 + p.S(g.second, g.second) * v2;
    if (std::hypot(f1, f2) <= p.w(g.first) * p.law_of(g.first).derivative(LawPart::j, 0.0, +1)) stuck.push_back(&g);
  }
  for (const CoordinateGroup* g : stuck) {
    (*a)(g->first) = (*a)(g->second) = 0.0;
    (*held)[static_cast<std::size_t>(g->first)] = (*held)[static_cast<std::size_t>(g->second)] = 1;
  }
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
