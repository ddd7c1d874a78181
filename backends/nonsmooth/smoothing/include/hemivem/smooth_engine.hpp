// Helpers shared by the smoothing-based engines (nlopt-mma, ceres-active-set): parameters of
// the continuation on the smoothing scale, the smoothed energy F_eps and its gradient, the
// start, and candidate points certified on the unsmoothed problem.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/smoothed_law.hpp>

namespace hemivem::smoothing {

/// The continuation parameters common to both engines (absolute scales, in units of a).
struct Continuation {
  double epsilon = 1e-9;   ///< final smoothing scale (0: the law itself in the last stage)
  double epsilon0 = 1e-3;  ///< initial smoothing scale (raised to epsilon if smaller)
  double reduction = 0.1;  ///< epsilon_{k+1} = reduction * epsilon_k

  /// The scales of the stages: one stage (epsilon) when the law has no kink.
  std::vector<double> schedule(const ContactLaw& law) const {
    if (SmoothedLaw(std::shared_ptr<const ContactLaw>(&law, [](const ContactLaw*) {}), 0.0).kinks() == 0)
      return {epsilon};
    // epsilon = 0 (the law itself): the scales fall to 1e-12 before the last stage
    const double floor = epsilon > 0.0 ? epsilon : std::min(1e-12, epsilon0);
    std::vector<double> s;
    for (double e = std::max(epsilon0, floor); e > floor * (1.0 + 1e-12); e *= reduction) s.push_back(e);
    s.push_back(floor);
    if (epsilon == 0.0) s.push_back(0.0);
    return s;
  }
};

/// Reads the engine's parameters: the continuation names plus `extra` (name -> default,
/// overwritten in place); any other name is an InputError. Also validates the options.
inline Continuation read_parameters(const MinimizerOptions& o, std::map<std::string, double>& extra,
                                    const std::string& engine) {
  std::string error;
  if (!o.is_valid(&error)) throw InputError(error, engine);
  Continuation c;
  for (const auto& [name, value] : o.parameters) {
    if (name == "epsilon")
      c.epsilon = value;
    else if (name == "epsilon0")
      c.epsilon0 = value;
    else if (name == "reduction")
      c.reduction = value;
    else if (auto it = extra.find(name); it != extra.end())
      it->second = value;
    else {
      std::string names = "epsilon, epsilon0, reduction";
      for (const auto& e : extra) names += ", " + e.first;
      throw InputError("unknown parameter '" + name + "'; expected one of: " + names, engine);
    }
  }
  if (!(c.epsilon >= 0.0) || !std::isfinite(c.epsilon)) throw InputError("epsilon must be finite and >= 0", engine);
  if (!(c.epsilon0 > 0.0) || !std::isfinite(c.epsilon0)) throw InputError("epsilon0 must be finite and > 0", engine);
  if (!(c.reduction > 0.0 && c.reduction < 1.0)) throw InputError("reduction must lie in (0, 1)", engine);
  return c;
}

/// The projected start (zero when empty); InputError for a wrong size or non-finite entries.
inline Eigen::VectorXd projected_start(const ReducedProblem& p, const Eigen::VectorXd& start, const std::string& engine) {
  if (start.size() == 0) return p.project(Eigen::VectorXd::Zero(p.size()));
  if (start.size() != p.size())
    throw InputError("start has size " + std::to_string(start.size()) + ", the problem " + std::to_string(p.size()), engine);
  if (!start.allFinite()) throw InputError("start is not finite", engine);
  return p.project(start);
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

/// The message of a run that ends at the final smoothing scale without a certificate.
inline std::string smoothing_limit_message(double epsilon) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "smoothing scale %.3g reached without a certificate; nodes at a kink of j are certified only as "
                "epsilon -> 0 (error O(epsilon))",
                epsilon);
  return buf;
}

inline bool certified(const Certificate& c, const MinimizerOptions& o) {
  return c.residual <= o.tolerance && c.feasibility <= o.feasibility_tolerance;
}

/// Number of nodes exactly at a bound.
inline int count_active(const ReducedProblem& p, const Eigen::VectorXd& a) {
  int n = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) n += (a(i) == p.upper(i) || a(i) == p.lower(i)) ? 1 : 0;
  return n;
}

/// Appends the record of x to result.history (iteration = ++result.iterations) and returns the
/// callback's verdict (true: go on).
inline bool record_iteration(const ReducedProblem& p, const MinimizerOptions& o, double seconds,
                             const Eigen::VectorXd& x, MinimizerResult& result) {
  IterationRecord r;
  r.iteration = ++result.iterations;
  r.energy = p.energy(x);
  const Certificate c = certificate(p, x);
  r.residual = c.residual;
  r.feasibility = c.feasibility;
  r.active = count_active(p, x);
  r.seconds = seconds;
  result.history.push_back(r);
  return !o.callback || o.callback(r);
}

/// A length scale of the unknowns: the largest gap, |a| of the start, or |c| / min S_ii.
inline double length_scale(const ReducedProblem& p, const Eigen::VectorXd& a) {
  const double cmax = std::max(p.c.size() ? p.c.cwiseAbs().maxCoeff() : 0.0, 1e-300);
  return std::max({p.g.size() ? p.g.cwiseAbs().maxCoeff() : 0.0, a.size() ? a.cwiseAbs().maxCoeff() : 0.0,
                   cmax / std::max(p.S.diagonal().minCoeff(), 1e-300)});
}

/// Keeps the best point seen: certified points first, then the smallest residual.
struct BestPoint {
  Eigen::VectorXd a;
  Certificate cert;
  bool ok = false;
  /// Offers a (feasible) point; true when it is certified.
  bool offer(const ReducedProblem& p, const MinimizerOptions& o, const Eigen::VectorXd& x) {
    const Certificate c = certificate(p, x);
    const bool good = certified(c, o);
    if (a.size() == 0 || (good && !ok) || (good == ok && c.residual < cert.residual)) {
      a = x;
      cert = c;
      ok = good;
    }
    return good;
  }
};

class Clock {
 public:
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace hemivem::smoothing
