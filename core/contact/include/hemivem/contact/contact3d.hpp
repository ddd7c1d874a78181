// Contact of a three-dimensional body (docs/three-dimensions.md): the contact boundary a union
// of planar boundary faces, frictionless, with the normal laws, constraints, gaps and obstacles
// of the plane problem. The reduced problem, the engines and the certificate are those of 2D.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/forces.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/sparse_factorization.hpp>
#include <hemivem/vem/assembly3d.hpp>

namespace hemivem {

/// Gamma_3 of a polyhedral mesh from boundary faces. The weight of a node is its share of the
/// contact area: each face is cut into the triangles (centroid, z_i, z_{i+1}) and each triangle
/// gives half its area to each of its two vertices on the face's boundary, so that the weights
/// of a face sum to its area (exact for constants; positive on faces star-shaped about their
/// centroid; |f|/n on a regular n-gon, |f|/4 on a rectangle). The normal of a node is the
/// weighted mean of the outward unit normals of its faces (by those shares), normalised.
/// Nodes whose displacement is prescribed (on Gamma_1) are excluded; a node with prescribed
/// components is kept when they are all tangential (|nu . e_c| <= tangential_tolerance: a
/// symmetry plane meeting Gamma_3) and its normal is then made exactly perpendicular to them; a
/// prescribed normal component is an InputError. Gaps: `gap` at the node (finite, >= 0), or
/// obstacle->gap(x, nu) with an obstacle (anything but NaN).
ContactBoundary make_contact_boundary_3d(const Mesh3D& mesh, const std::vector<int>& faces, const DofMap& dofs,
                                         const std::function<double(const Vec3&)>& gap,
                                         const Obstacle3D* obstacle = nullptr);

struct ContactProblem3D {
  ElasticityProblem3D elasticity;        ///< mesh, materials, loads and Gamma_1
  std::vector<int> contact_faces;         ///< Gamma_3 (boundary face ids)
  std::function<double(const Vec3&)> gap;  ///< g >= 0 at a point of Gamma_3 (empty: no gap given)
  std::optional<Obstacle3D> obstacle;     ///< a rigid obstacle instead of `gap`
  std::shared_ptr<const ContactLaw> law;  ///< the normal law
  ConstraintKind constraint = ConstraintKind::box;
  bool law_from_surface = false;
  std::string contact_name = "contact";
};

/// One contact node of a 3D solution (ContactNode without friction).
struct ContactNode3D {
  int vertex = -1;
  Vec3 x = Vec3::Zero();
  double u_nu = 0.0;
  double law_force = 0.0;
  double reaction = 0.0;
  double weight = 0.0;  ///< w_i, the area the node stands for
  Vec3 normal = Vec3::Zero();
  double gap = 0.0;
  std::string state;    ///< "upper", "lower", "free" or "bilateral"
  double force() const noexcept { return law_force + reaction; }
  double pressure() const noexcept { return force() / weight; }
};

/// The balance of forces of a 3D solution (force_balance in 3D: the reaction of each Dirichlet
/// condition the sum of K u - f over the dofs it prescribes, the last condition owning a dof).
ForceBalance3D force_balance_3d(const ElasticityProblem3D& problem, const Eigen::VectorXd& u, const Vec3& contact);

struct ContactSolution3D {
  Eigen::VectorXd u;  ///< nodal displacements, 3 per vertex
  int unknowns = 0;
  std::vector<ContactNode3D> contact;
  MinimizerStatus status = MinimizerStatus::failed;
  std::string message;
  Certificate certificate;
  bool may_be_nonunique = false;
  std::optional<MinimizerResult> minimizer;
  double uniqueness_margin = std::numeric_limits<double>::infinity();
  double uniqueness_roundoff = 0.0;
  /// Reciprocal condition estimate of the matrix the engine factorized (A22 with contact, A
  /// without), where the engine offers one; NaN otherwise and unless asked for
  /// (estimate_condition), as ContactSolution::rcond.
  double rcond = std::numeric_limits<double>::quiet_NaN();
  /// Estimate of the 1-norm condition number of the same matrix, independent of the engine
  /// (Condensation::condition_estimate); NaN unless asked for, as ContactSolution::condition_estimate.
  double condition_estimate = std::numeric_limits<double>::quiet_NaN();
  double energy = 0.0;
  std::map<std::string, double> timings;
  std::vector<std::string> stages;
  ForceBalance3D forces;
  bool converged() const noexcept { return status == MinimizerStatus::converged; }
  int iterations() const noexcept { return minimizer ? minimizer->iterations : 0; }
  /// The resultant of the obstacle's (foundation's) forces on the body: -sum (zeta_i + lambda_i) nu_i.
  Vec3 contact_force() const;
};

/// Solves a 3D contact problem with the stages of ContactSolver: assembly, condensation (one
/// factorization), one minimization per minimizer, back-substitution, post-processing; without
/// contact faces one linear solve. The supports must hold the body (InputError naming the rigid
/// motions they leave free: a three-dimensional body held by its contact alone is refused).
/// InputError for a problem that cannot be set up, NumericalError when the factorization fails.
/// `estimate_condition` adds ContactSolution3D::condition_estimate (7 more solves) and rcond,
/// and widens the uniqueness margin's round-off bound by the estimate, as solve_contact does.
std::vector<ContactSolution3D> solve_contact_3d(const ContactProblem3D& problem,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                                bool estimate_condition = false);
ContactSolution3D solve_contact_3d(const ContactProblem3D& problem, std::unique_ptr<SparseFactorization> factorization,
                                   const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                                   ReducedProblem* reduced = nullptr, bool estimate_condition = false);
/// The same on a system the caller assembled from problem.elasticity (assemble_3d), e.g. to
/// condense one assembly with several engines: no "assembly" stage, and "total" excludes it.
std::vector<ContactSolution3D> solve_contact_3d(const ContactProblem3D& problem, const LinearSystem& system,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                                bool estimate_condition = false);

/// The rigid motions of a 3D body that prescribed dofs leave free, in words (empty when held).
std::vector<std::string> free_rigid_motions_3d(const Mesh3D& mesh, const DofMap& dofs);

}  // namespace hemivem
