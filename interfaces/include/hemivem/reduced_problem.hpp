// The reduced (condensed) contact problem of DESIGN §3:
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j_i(a_i)   s.t. lower_i <= a_i <= upper_i,
//
// with S dense symmetric positive definite, w > 0 the nodal weights and per coordinate a
// contact law j_i and bounds (+-inf where there is none). Without friction every coordinate is
// a normal displacement with the one law j and the bounds of one constraint: none, a_i <= g_i
// (one-sided) or |a_i| <= g_i (the paper's box (4.6)). With friction (docs/friction.md) the
// coordinates are the normal and the tangential displacements of the contact nodes, each with
// its own law (by index into a short list) and bounds: the coordinate-wise form.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/contact_law.hpp>
#include <hemivem/error.hpp>

namespace hemivem {

enum class ConstraintKind {
  none,       ///< no gap: unconstrained
  one_sided,  ///< a_i <= g_i
  box,        ///< |a_i| <= g_i
  bilateral,  ///< a_i = 0: the normal displacement vanishes (the body slides on Gamma_3); the
              ///< reduced problem then has the tangential displacements only
};
inline std::string to_string(ConstraintKind kind) {
  switch (kind) {
    case ConstraintKind::none:
      return "none";
    case ConstraintKind::one_sided:
      return "one-sided";
    case ConstraintKind::bilateral:
      return "bilateral";
    default:
      return "box";
  }
}
/// "none", "one-sided", "box", "bilateral" (case-insensitive); InputError otherwise.
inline ConstraintKind constraint_kind_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (s == "none") return ConstraintKind::none;
  if (s == "one-sided" || s == "one_sided") return ConstraintKind::one_sided;
  if (s == "box") return ConstraintKind::box;
  if (s == "bilateral") return ConstraintKind::bilateral;
  throw InputError("unknown constraint '" + std::string(name) + "'; expected none, one-sided, box or bilateral");
}

/// The bounds of a normal displacement with gap g under a constraint (+-inf where there is none).
inline double lower_bound(ConstraintKind kind, double g) {
  if (kind == ConstraintKind::bilateral) return 0.0;
  return kind == ConstraintKind::box ? -g : -std::numeric_limits<double>::infinity();
}
inline double upper_bound(ConstraintKind kind, double g) {
  if (kind == ConstraintKind::bilateral) return 0.0;
  return kind == ConstraintKind::none ? std::numeric_limits<double>::infinity() : g;
}

struct ReducedProblem {
  Eigen::MatrixXd S;
  Eigen::VectorXd c;
  Eigen::VectorXd w;
  Eigen::VectorXd g;
  /// The law of every coordinate; in the coordinate-wise form laws[0].
  std::shared_ptr<const ContactLaw> law;
  ConstraintKind constraint = ConstraintKind::one_sided;
  /// lambda_min(S - diag(alpha_i w_i)), alpha_i the curvature bound of coordinate i's law, set
  /// by whoever builds the problem (NaN: unknown). F is strongly convex, and its critical point
  /// unique, when it is positive.
  double uniqueness_margin = std::numeric_limits<double>::quiet_NaN();

  /// The coordinate-wise form (empty: every coordinate has `law` and the bounds of `constraint`
  /// and g). Coordinate i has the law laws[law_index(i)] and the bounds [lo(i), hi(i)] (+-inf
  /// allowed); `constraint` and g are then not used.
  std::vector<std::shared_ptr<const ContactLaw>> laws;
  Eigen::VectorXi law_index;
  Eigen::VectorXd lo, hi;

  Eigen::Index size() const noexcept { return c.size(); }
  bool coordinatewise() const noexcept { return !laws.empty(); }

  /// How many laws, and law k of them (k = law_number(i) for coordinate i).
  int num_laws() const noexcept { return coordinatewise() ? static_cast<int>(laws.size()) : 1; }
  const ContactLaw& law_by_number(int k) const { return coordinatewise() ? *laws[static_cast<std::size_t>(k)] : *law; }
  int law_number(Eigen::Index i) const { return coordinatewise() ? law_index(i) : 0; }
  /// The law of coordinate i.
  const ContactLaw& law_of(Eigen::Index i) const { return law_by_number(law_number(i)); }
  /// True when every law is convex (no DC loop is needed).
  bool all_laws_convex() const {
    for (int k = 0; k < num_laws(); ++k)
      if (!law_by_number(k).is_convex()) return false;
    return true;
  }

  /// F(a).
  double energy(const Eigen::VectorXd& a) const {
    double f = 0.5 * a.dot(S * a) - c.dot(a);
    for (Eigen::Index i = 0; i < a.size(); ++i) f += w(i) * law_of(i).value(LawPart::j, a(i));
    return f;
  }
  /// A subgradient of F2 = sum_i w_i j2_i(a_i), the concave part of F = F1 - F2 (right
  /// derivatives of j2; j2 is convex, so either side is one).
  Eigen::VectorXd subgradient_convex2(const Eigen::VectorXd& a) const {
    Eigen::VectorXd g2(a.size());
    for (Eigen::Index i = 0; i < a.size(); ++i) g2(i) = w(i) * law_of(i).derivative(LawPart::j2, a(i), +1);
    return g2;
  }
  /// The projection onto C.
  Eigen::VectorXd project(const Eigen::VectorXd& a) const {
    Eigen::VectorXd p(a.size());
    for (Eigen::Index i = 0; i < a.size(); ++i) p(i) = std::min(std::max(a(i), lower(i)), upper(i));
    return p;
  }

  /// Lower and upper bound of a_i (+-inf where there is none).
  double lower(Eigen::Index i) const {
    if (coordinatewise()) return lo(i);
    return lower_bound(constraint, constraint == ConstraintKind::box ? g(i) : 0.0);
  }
  double upper(Eigen::Index i) const {
    if (coordinatewise()) return hi(i);
    const bool gapped = constraint == ConstraintKind::one_sided || constraint == ConstraintKind::box;
    return upper_bound(constraint, gapped ? g(i) : 0.0);
  }
  /// The curvature bounds alpha_i of the coordinates' laws (+inf for a concave kink).
  Eigen::VectorXd alphas() const {
    Eigen::VectorXd alpha(size());
    for (Eigen::Index i = 0; i < size(); ++i) alpha(i) = law_of(i).alpha();
    return alpha;
  }
};

/// Checks that the arrays fit together (S n x n, w of size n, g of size n unless there is no
/// constraint; in the coordinate-wise form law_index, lo and hi of size n, every law index in
/// range, lo <= hi, no NaN bound, law == laws[0]) and that there is a law; throws InputError
/// naming `where` otherwise.
inline void check_sizes(const ReducedProblem& p, const std::string& where) {
  const Eigen::Index n = p.size();
  if (!p.law) throw InputError("the reduced problem has no contact law", where);
  const bool coordinatewise = p.coordinatewise();
  if (p.S.rows() != n || p.S.cols() != n || p.w.size() != n ||
      (!coordinatewise && (p.constraint == ConstraintKind::one_sided || p.constraint == ConstraintKind::box) &&
       p.g.size() != n))
    throw InputError("inconsistent sizes in the reduced problem: S " + std::to_string(p.S.rows()) + "x" +
                         std::to_string(p.S.cols()) + ", c " + std::to_string(n) + ", w " + std::to_string(p.w.size()) +
                         ", g " + std::to_string(p.g.size()),
                     where);
  if (!coordinatewise) return;
  if (p.law_index.size() != n || p.lo.size() != n || p.hi.size() != n)
    throw InputError("inconsistent sizes in the reduced problem: " + std::to_string(n) + " coordinates, law_index " +
                         std::to_string(p.law_index.size()) + ", lower bounds " + std::to_string(p.lo.size()) +
                         ", upper bounds " + std::to_string(p.hi.size()),
                     where);
  for (const auto& l : p.laws)
    if (!l) throw InputError("the reduced problem has a null law in its list of laws", where);
  if (p.laws.front() != p.law) throw InputError("the reduced problem's law is not the first of its laws", where);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (p.law_index(i) < 0 || p.law_index(i) >= static_cast<int>(p.laws.size()))
      throw InputError("coordinate " + std::to_string(i) + " has law index " + std::to_string(p.law_index(i)) +
                           ", expected 0.." + std::to_string(p.laws.size() - 1),
                       where);
    if (!(p.lo(i) <= p.hi(i)))
      throw InputError("coordinate " + std::to_string(i) + " has bounds [" + std::to_string(p.lo(i)) + ", " +
                           std::to_string(p.hi(i)) + "]; expected lower <= upper",
                       where);
  }
}

}  // namespace hemivem
