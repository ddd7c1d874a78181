// The reduced (condensed) contact problem (docs/tutorial/example-4.1.md, the reduced problem):
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j_i(a_i)   s.t. lo_i <= a_i <= hi_i,
//
// with S dense symmetric positive semidefinite (definite unless a rigid motion of the body is
// left free by its supports: hemivem/existence.hpp), w > 0 the nodal weights and per coordinate a
// contact law j_i (by index into a short list of laws) and bounds (+-inf where there is none).
// Without friction every coordinate is a normal displacement with one law and the bounds of
// one constraint: none, a_i <= g_i (one-sided) or |a_i| <= g_i (the paper's box (4.6));
// ReducedProblem::uniform() builds that case and uniform_form() recognises it. With friction
// (docs/friction.md) the coordinates are the normal and the tangential displacements of the
// contact nodes, each with its own law and bounds. A solid's isotropic friction acts on the
// Euclidean norm of a node's two tangential displacements: such pairs of coordinates form a
// group (CoordinateGroup) whose law is a law of the pair's norm.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/contact_law.hpp>

namespace hemivem {

enum class ConstraintKind {
  none,       ///< no gap: unconstrained
  one_sided,  ///< a_i <= g_i
  box,        ///< |a_i| <= g_i
  bilateral,  ///< a_i = 0: the normal displacement vanishes (the body slides on Gamma_3); the
              ///< reduced problem then has the tangential displacements only
};
/// "none", "one-sided", "box", "bilateral".
std::string to_string(ConstraintKind kind);
/// The names of to_string (case-insensitive, "one_sided" too); InputError otherwise.
ConstraintKind constraint_kind_from_string(std::string_view name);

/// The bounds of a normal displacement with gap g under a constraint (+-inf where there is none).
inline double lower_bound(ConstraintKind kind, double g) {
  if (kind == ConstraintKind::bilateral) return 0.0;
  return kind == ConstraintKind::box ? -g : -std::numeric_limits<double>::infinity();
}
inline double upper_bound(ConstraintKind kind, double g) {
  if (kind == ConstraintKind::bilateral) return 0.0;
  return kind == ConstraintKind::none ? std::numeric_limits<double>::infinity() : g;
}

/// A problem whose coordinates share one law and the bounds of one constraint with gaps g
/// (g is zero where the constraint has no gap: none, bilateral).
struct UniformForm {
  std::shared_ptr<const ContactLaw> law;
  ConstraintKind constraint = ConstraintKind::none;
  Eigen::VectorXd g;
};

/// Two coordinates whose law acts on their Euclidean norm (isotropic friction in a solid's
/// tangent plane): F has w j(|(a_first, a_second)|) for them instead of a term per coordinate.
/// Both have the same law and weight and no bounds, and the law rises from 0
/// (j'(0+), j1'(0+) and j2'(0+) >= 0, as for every even law), so that j(|v|) has the DC split
/// j1(|v|) - j2(|v|) and the curvature bound alpha of j (check_sizes checks all of it).
/// The Clarke subdifferential of j(|v|) is {s v/|v| : s in [j'(r-), j'(r+)]} at v != 0,
/// r = |v|, and the disc of radius j'(0+) at v = 0.
struct CoordinateGroup {
  Eigen::Index first = 0;
  Eigen::Index second = 0;
};

struct ReducedProblem {
  Eigen::MatrixXd S;
  Eigen::VectorXd c;
  Eigen::VectorXd w;
  /// Coordinate i has the law laws[law_index(i)] and the bounds [lo(i), hi(i)] (+-inf allowed).
  std::vector<std::shared_ptr<const ContactLaw>> laws;
  Eigen::VectorXi law_index;
  Eigen::VectorXd lo, hi;
  /// The groups of coordinates with a law of their norm (none in the plane and without friction).
  std::vector<CoordinateGroup> groups;
  /// lambda_min(S - diag(alpha_i w_i)), alpha_i the curvature bound of coordinate i's law, set
  /// by whoever builds the problem (NaN: unknown), as measure_uniqueness()
  /// (hemivem/uniqueness.hpp) reports it: exactly 0 within round-off. F is strongly convex, and
  /// its critical point unique, when it is positive.
  double uniqueness_margin = std::numeric_limits<double>::quiet_NaN();
  /// The round-off bound of that margin (UniquenessMargin::roundoff; NaN: unknown).
  double uniqueness_roundoff = std::numeric_limits<double>::quiet_NaN();

  /// Every coordinate with `law` and the bounds of `constraint` and the gaps g (g is read for
  /// one-sided and box only and may be empty otherwise). The sizes are not checked here
  /// (check_sizes() does), but g must have c's size where it is read: InputError otherwise.
  static ReducedProblem uniform(Eigen::MatrixXd S, Eigen::VectorXd c, Eigen::VectorXd w,
                                std::shared_ptr<const ContactLaw> law, ConstraintKind constraint,
                                const Eigen::VectorXd& g = {});

  /// The problem as uniform() would build it (law 0, the constraint and g), or nothing when
  /// its coordinates differ in law or kind of bound or form groups: how files and reports
  /// describe it.
  std::optional<UniformForm> uniform_form() const;
  /// True when the problem has no uniform form (its bounds and laws are per coordinate).
  bool coordinatewise() const { return !uniform_form().has_value(); }

  Eigen::Index size() const noexcept { return c.size(); }
  /// How many laws, and law k of them.
  int num_laws() const noexcept { return static_cast<int>(laws.size()); }
  const ContactLaw& law_by_number(int k) const { return *laws[static_cast<std::size_t>(k)]; }
  /// The law of coordinate i.
  const ContactLaw& law_of(Eigen::Index i) const { return law_by_number(law_index(i)); }
  /// Lower and upper bound of a_i (+-inf where there is none).
  double lower(Eigen::Index i) const { return lo(i); }
  double upper(Eigen::Index i) const { return hi(i); }

  /// Per coordinate the index of its group in `groups`, -1 for a coordinate on its own.
  Eigen::VectorXi group_of() const;
  /// True when every law is convex (no DC loop is needed).
  bool all_laws_convex() const;
  /// F(a).
  double energy(const Eigen::VectorXd& a) const;
  /// The laws' part of F(a), sum_i w_i j_i(a_i) over single coordinates and w j(|a_G|) over
  /// groups, added term by term to `onto`.
  double law_energy(const Eigen::VectorXd& a, double onto = 0.0) const;
  /// A subgradient of F2 = sum_i w_i j2_i(a_i) (and w j2(|a_G|) per group), the concave part of
  /// F = F1 - F2 (right derivatives of j2; j2 is convex, so either side is one; 0 for a group at
  /// the origin).
  Eigen::VectorXd subgradient_convex2(const Eigen::VectorXd& a) const;
  /// The projection onto C.
  Eigen::VectorXd project(const Eigen::VectorXd& a) const;
  /// The curvature bounds alpha_i of the coordinates' laws (+inf for a concave kink).
  Eigen::VectorXd alphas() const;
};

/// Checks that the arrays fit together (S n x n, w, law_index, lo and hi of size n, at least
/// one law and none null, every law index in range, lo <= hi, no NaN bound) and that every group
/// is one (two distinct coordinates in range, in no other group, of one law and one weight,
/// without bounds, its law rising from 0); throws InputError naming `where` otherwise.
/// A minimizer that cannot take groups refuses a problem with them by name
/// (InputError "ENGINE does not take groups of coordinates ...").
void check_sizes(const ReducedProblem& p, const std::string& where);

/// |(a_first, a_second)|: the norm of group g's coordinates in a.
inline double group_norm(const Eigen::VectorXd& a, const CoordinateGroup& g) {
  return std::hypot(a(g.first), a(g.second));
}

}  // namespace hemivem
