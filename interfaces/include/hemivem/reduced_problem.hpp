// The reduced (condensed) contact problem of DESIGN §3:
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t. a in C,
//
// with S dense symmetric positive definite (N1 x N1), w > 0 the nodal weights, g >= 0
// the gaps, j the contact law and C one of: no constraint, a_i <= g_i (one-sided), or
// |a_i| <= g_i (the paper's box (4.6)).
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <limits>
#include <memory>
#include <string>
#include <string_view>

#include <hemivem/contact_law.hpp>
#include <hemivem/error.hpp>

namespace hemivem {

enum class ConstraintKind {
  none,       ///< no gap: unconstrained
  one_sided,  ///< a_i <= g_i
  box,        ///< |a_i| <= g_i
};
inline std::string to_string(ConstraintKind kind) {
  switch (kind) {
    case ConstraintKind::none:
      return "none";
    case ConstraintKind::one_sided:
      return "one-sided";
    default:
      return "box";
  }
}
/// "none", "one-sided", "box" (case-insensitive); InputError otherwise.
inline ConstraintKind constraint_kind_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (s == "none") return ConstraintKind::none;
  if (s == "one-sided" || s == "one_sided") return ConstraintKind::one_sided;
  if (s == "box") return ConstraintKind::box;
  throw InputError("unknown constraint '" + std::string(name) + "'; expected none, one-sided or box");
}

struct ReducedProblem {
  Eigen::MatrixXd S;
  Eigen::VectorXd c;
  Eigen::VectorXd w;
  Eigen::VectorXd g;
  std::shared_ptr<const ContactLaw> law;
  ConstraintKind constraint = ConstraintKind::one_sided;
  /// lambda_min(S - alpha_j W), set by whoever builds the problem (NaN: unknown). F is
  /// strongly convex, and its critical point unique, when it is positive.
  double uniqueness_margin = std::numeric_limits<double>::quiet_NaN();

  Eigen::Index size() const noexcept { return c.size(); }

  /// F(a).
  double energy(const Eigen::VectorXd& a) const {
    double f = 0.5 * a.dot(S * a) - c.dot(a);
    for (Eigen::Index i = 0; i < a.size(); ++i) f += w(i) * law->value(LawPart::j, a(i));
    return f;
  }
  /// A subgradient of F2 = sum_i w_i j2(a_i), the concave part of F = F1 - F2 (right
  /// derivatives of j2; j2 is convex, so either side is one).
  Eigen::VectorXd subgradient_convex2(const Eigen::VectorXd& a) const {
    Eigen::VectorXd g(a.size());
    for (Eigen::Index i = 0; i < a.size(); ++i) g(i) = w(i) * law->derivative(LawPart::j2, a(i), +1);
    return g;
  }
  /// The projection onto C.
  Eigen::VectorXd project(const Eigen::VectorXd& a) const {
    Eigen::VectorXd p(a.size());
    for (Eigen::Index i = 0; i < a.size(); ++i) p(i) = std::min(std::max(a(i), lower(i)), upper(i));
    return p;
  }

  /// Lower and upper bound of a_i (+-inf where there is none).
  double lower(Eigen::Index i) const {
    return constraint == ConstraintKind::box ? -g(i) : -std::numeric_limits<double>::infinity();
  }
  double upper(Eigen::Index i) const {
    return constraint == ConstraintKind::none ? std::numeric_limits<double>::infinity() : g(i);
  }
};

/// Checks that the arrays fit together (S n x n, w of size n, g of size n unless there is no
/// constraint) and that there is a law; throws InputError naming `where` otherwise.
inline void check_sizes(const ReducedProblem& p, const std::string& where) {
  const Eigen::Index n = p.size();
  if (!p.law) throw InputError("the reduced problem has no contact law", where);
  if (p.S.rows() != n || p.S.cols() != n || p.w.size() != n ||
      (p.constraint != ConstraintKind::none && p.g.size() != n))
    throw InputError("inconsistent sizes in the reduced problem: S " + std::to_string(p.S.rows()) + "x" +
                         std::to_string(p.S.cols()) + ", c " + std::to_string(n) + ", w " + std::to_string(p.w.size()) +
                         ", g " + std::to_string(p.g.size()),
                     where);
}

}  // namespace hemivem
