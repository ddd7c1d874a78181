// Does the reduced problem have a solution? (hemivem/reduced_problem.hpp)
//
//   min F(a) = 1/2 a^T S a - c^T a + sum_i w_i j_i(a_i)   s.t. lo <= a <= hi.
//
// S is symmetric positive semidefinite. When it is definite, F grows quadratically in every
// direction and has a minimizer. When it has a null space N (a body whose rigid motion is
// left free by its supports and held by its contact only), along a direction d of N the
// energy changes at the asymptotic rate
//
//   phi(d) = -c^T d + sum_i w_i j_inf,i(d_i),   j_inf(t) = t j'(+inf) for t > 0, |t| (-j'(-inf)) for t < 0,
//
// (j_inf the recession function of the law: its slope far from the origin, +inf where the
// law grows faster than linearly), over the directions the bounds allow (d_i <= 0 where a_i
// has an upper bound, d_i >= 0 where it has a lower one); a group of coordinates
// (ReducedProblem::groups) adds w j'(+inf) |d_G| instead of a term per coordinate. If phi(d) < 0 for such a d, F is
// unbounded below along d: the load pushes the body away from its support and there is no
// solution. If phi(d) > 0 for every such d != 0 the law or the constraint stops every free
// motion and F has a minimizer.
//
// The test is exact for a null space of dimension at most 3 (the rigid motions of a plane
// body) and laws that are polynomials of degree <= 3 beyond their outermost breakpoints (the
// shipped laws) without groups; for a larger null space, and with groups (whose term is not
// linear in d on any cell), a finite set of directions is tried. Only the null
// space of S is examined: a law whose curvature far from the origin is negative enough to
// overcome S's is not.
#pragma once

#include <Eigen/Core>

#include <string>

#include <hemivem/contact_law.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

/// lim j'(r) for r -> +inf (side > 0) or r -> -inf (side < 0): +-inf when j' grows without
/// bound (a law with positive curvature there has +inf on the right and -inf on the left).
double asymptotic_slope(const ContactLaw& law, int side);

/// The eigenvalues of S at most this fraction of its largest |eigenvalue| are taken as zero.
inline constexpr double null_space_tolerance = 1e-10;

/// An orthonormal basis (the columns, possibly none) of the eigenvectors of the symmetric S
/// whose eigenvalues are at most relative_tolerance times S's largest |eigenvalue|; every
/// direction when S = 0.
Eigen::MatrixXd null_space(const Eigen::MatrixXd& S, double relative_tolerance = null_space_tolerance);

/// What check_existence() found.
struct Existence {
  /// False when F is unbounded below on C: there is no solution.
  bool bounded = true;
  /// True when phi > 0 along every allowed direction of S's null space (or it has none): a
  /// minimizer exists. False when bounded but some allowed null direction costs nothing.
  bool coercive = true;
  /// The dimension of S's null space.
  int null_dimension = 0;
  /// When unbounded: the direction d (a null vector of S allowed by the bounds, ||d||_inf = 1)
  /// along which F decreases without bound; empty otherwise.
  Eigen::VectorXd direction;
  /// phi(direction) (-inf when a law falls faster than linearly); NaN when bounded.
  double slope = 0.0;
  /// When unbounded: the sentence that says so (for a minimizer's message); empty otherwise.
  std::string message;
};

/// The verdict for `p` given an orthonormal basis of S's null space (the columns of
/// null_basis, n rows; no columns: S is definite, bounded). InputError for a basis with the
/// wrong number of rows.
Existence check_existence(const ReducedProblem& p, const Eigen::MatrixXd& null_basis);

/// The same with S's null space computed: a Cholesky factorization whose pivots are all
/// above round-off shows S definite at once; otherwise null_space(p.S).
Existence check_existence(const ReducedProblem& p);

}  // namespace hemivem
