// The reduced (condensed) contact problem of DESIGN §3:
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j(a_i)   s.t. a in C,
//
// with S dense symmetric positive definite (N1 x N1), w > 0 the nodal weights, g >= 0
// the gaps, j the contact law and C one of: no constraint, a_i <= g_i (one-sided), or
// |a_i| <= g_i (the paper's box (4.6)).
#pragma once

#include <Eigen/Core>

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

  Eigen::Index size() const noexcept { return c.size(); }

  /// F(a).
  double energy(const Eigen::VectorXd& a) const {
    double f = 0.5 * a.dot(S * a) - c.dot(a);
    for (Eigen::Index i = 0; i < a.size(); ++i) f += w(i) * law->value(LawPart::j, a(i));
    return f;
  }
  /// Lower and upper bound of a_i (+-inf where there is none).
  double lower(Eigen::Index i) const {
    return constraint == ConstraintKind::box ? -g(i) : -std::numeric_limits<double>::infinity();
  }
  double upper(Eigen::Index i) const {
    return constraint == ConstraintKind::none ? std::numeric_limits<double>::infinity() : g(i);
  }
};

}  // namespace hemivem
