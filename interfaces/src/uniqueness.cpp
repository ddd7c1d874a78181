#include <hemivem/uniqueness.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace hemivem {

UniquenessMargin measure_uniqueness(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, const Eigen::VectorXd& alpha) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  UniquenessMargin m;
  m.roundoff = 0.0;
  if (S.rows() == 0) {
    m.margin = m.computed = inf;
    return m;
  }
  for (Eigen::Index i = 0; i < alpha.size(); ++i)
    if (std::isinf(alpha(i))) {
      m.margin = m.computed = -inf;
      return m;
    }
  const Eigen::VectorXd aw = alpha.cwiseProduct(w);
  Eigen::MatrixXd M = S;
  M.diagonal() -= aw;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M, Eigen::EigenvaluesOnly);
  m.computed = eig.eigenvalues()(0);
  const double norm_s = S.cwiseAbs().colwise().sum().maxCoeff();
  m.roundoff = static_cast<double>(S.rows()) * std::numeric_limits<double>::epsilon() *
               (norm_s + aw.cwiseAbs().maxCoeff());
  m.margin = std::abs(m.computed) <= m.roundoff ? 0.0 : m.computed;
  return m;
}

UniquenessMargin measure_uniqueness(const ReducedProblem& p) { return measure_uniqueness(p.S, p.w, p.alphas()); }

double uniqueness_margin(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, double alpha) {
  return uniqueness_margin(S, w, Eigen::VectorXd::Constant(w.size(), alpha));
}

double uniqueness_margin(const Eigen::MatrixXd& S, const Eigen::VectorXd& w, const Eigen::VectorXd& alpha) {
  return measure_uniqueness(S, w, alpha).margin;
}

bool margin_agrees(double given, const UniquenessMargin& computed) {
  if (given == computed.margin || given == computed.computed) return true;
  if (!std::isfinite(given) || !std::isfinite(computed.computed)) return false;
  return std::abs(given - computed.computed) <= computed.roundoff + 1e-8 * std::abs(computed.computed);
}

std::string uniqueness_verdict(double margin) {
  if (std::isnan(margin)) return "unknown";
  return margin > 0.0 ? "unique" : (margin == 0.0 ? "zero" : "negative");
}

std::string uniqueness_meaning(double margin) {
  if (std::isnan(margin)) return "the margin is unknown: uniqueness is not proved";
  if (margin > 0.0) return "F is strongly convex, so the solution is unique";
  if (margin == 0.0)
    return "F is convex but not strongly convex along some direction, so uniqueness is not proved";
  return "F may be nonconvex: several critical points are possible, this is one of them";
}

void set_uniqueness_margin(ReducedProblem& p) {
  const UniquenessMargin m = measure_uniqueness(p);
  p.uniqueness_margin = m.margin;
  p.uniqueness_roundoff = m.roundoff;
}

void widen_uniqueness_roundoff(ReducedProblem& p, double kappa) {
  if (!(kappa > 0.0) || !std::isfinite(kappa) || p.S.size() == 0) return;
  const double extra = std::numeric_limits<double>::epsilon() * kappa * p.S.cwiseAbs().colwise().sum().maxCoeff();
  if (!(extra > p.uniqueness_roundoff)) return;
  p.uniqueness_roundoff = extra;
  if (std::isfinite(p.uniqueness_margin) && std::abs(p.uniqueness_margin) <= extra) p.uniqueness_margin = 0.0;
}

}  // namespace hemivem
