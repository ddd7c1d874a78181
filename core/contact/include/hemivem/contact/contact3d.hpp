// Contact of a three-dimensional body (docs/three-dimensions.md): the contact boundary a union
// of planar boundary faces, with the normal laws, constraints, gaps and obstacles of the plane
// problem and friction laws of the norm of the tangential displacement (docs/friction.md). The
// reduced problem, the engines and the certificate are those of 2D; a node's two tangential
// displacements are a group of the reduced problem.
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
#include <hemivem/contact/solver.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/sparse_factorization.hpp>
#include <hemivem/vem/assembly3d.hpp>

namespace hemivem {

/// One part of the contact boundary of a solid (BasicContactPart: boundary faces, gap or
/// obstacle, normal law, constraint, friction).
using ContactPart3D = BasicContactPart<3>;

/// Gamma_3 of a polyhedral mesh from the boundary faces of its contact parts. The weight of a
/// node is its share of the contact area: each face is cut into the triangles (centroid, z_i,
/// z_{i+1}) and each triangle gives half its area to each of its two vertices on the face's
/// boundary, so that the weights of a face sum to its area (exact for constants; positive on
/// faces star-shaped about their centroid; |f|/n on a regular n-gon, |f|/4 on a rectangle). The
/// normal of a node is the weighted mean of the outward unit normals of its faces (by those
/// shares), normalised. The nodes of every part form one boundary, in vertex order; a node
/// where two parts meet belongs to the part listed first (ContactBoundary::part), its normal
/// and weight still from all its contact faces and its gap from its own part. A face in two
/// parts is an InputError naming both.
/// Nodes whose displacement is prescribed (on Gamma_1) are excluded; a node with prescribed
/// components is kept when they are all tangential (|nu . e_c| <= tangential_tolerance), or
/// nearly so on a symmetry plane (all its contact faces on one side of the plane through it
/// normal to e_c, |nu . e_c| <= symmetry_tolerance: a curved Gamma_3 meeting the plane), and its
/// normal is then made exactly perpendicular to them; an oblique or normal prescribed component
/// is an InputError. Gaps: the part's `gap` at the node (finite,
/// >= 0; 0 without one), or its obstacle's gap(x, nu) (anything but NaN).
ContactBoundary make_contact_boundary(const Mesh3D& mesh, const std::vector<ContactPart3D>& parts, const DofMap& dofs);
/// The same for one part: `faces` with `gap`, or `obstacle`.
ContactBoundary make_contact_boundary(const Mesh3D& mesh, const std::vector<int>& faces, const DofMap& dofs,
                                         const std::function<double(const Vec3&)>& gap,
                                         const Obstacle3D* obstacle = nullptr);

/// A contact problem of a solid (BasicContactProblem<3>: the elasticity problem and the
/// contact boundary in parts, each with its faces, gap or obstacle, law and constraint).
using ContactProblem3D = BasicContactProblem<3>;

/// The faces of every contact part of `problem`, part after part.
std::vector<int> contact_faces(const ContactProblem3D& problem);

/// The contact boundary of `problem` on the dofs of its assembled system
/// (make_contact_boundary of its parts); InputError for an obstacle with a defect, and for
/// a gap the box constraint cannot take.
ContactBoundary contact_boundary(const ContactProblem3D& problem, const DofMap& dofs);

/// One contact node of a 3D solution.
using ContactNode3D = BasicContactNode<3>;

/// The balance of forces of a 3D solution (force_balance in 3D: the reaction of each Dirichlet
/// condition the sum of K u - f over the dofs it prescribes, the last condition owning a dof).
ForceBalance3D force_balance(const ElasticityProblem3D& problem, const Eigen::VectorXd& u, const Vec3& contact,
                             const std::vector<std::pair<int, Vec3>>& at_vertices = {});

using ContactSolution3D = BasicContactSolution<3>;

/// The solver of a solid: BasicContactSolver<3>, the stages of the plane's ContactSolver.
using ContactSolver3D = BasicContactSolver<3>;

/// Solves a 3D contact problem with ContactSolver3D: assembly, condensation (one
/// factorization), one minimization per minimizer, back-substitution, post-processing; without
/// contact faces one linear solve. A rigid motion the supports leave free must move some contact
/// node along its normal (or, with friction, its tangent plane), relative to its partner across
/// a contact between two bodies: the contact then holds it (Supports); InputError naming the
/// motions nothing holds.
/// InputError for a problem that cannot be set up, NumericalError when the factorization fails.
/// `estimate_condition` adds ContactSolution3D::condition_estimate (two more solves with five right-hand sides) and rcond,
/// and widens the uniqueness margin's round-off bound by the estimate, as solve_contact does.
std::vector<ContactSolution3D> solve_contact(const ContactProblem3D& problem,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                                bool estimate_condition = false);
ContactSolution3D solve_contact(const ContactProblem3D& problem, std::unique_ptr<SparseFactorization> factorization,
                                   const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                                   ReducedProblem* reduced = nullptr, bool estimate_condition = false);
/// The same on a system the caller assembled from problem.elasticity (assemble), e.g. to
/// condense one assembly with several engines: no "assembly" stage, and "total" excludes it.
std::vector<ContactSolution3D> solve_contact(const ContactProblem3D& problem, const LinearSystem& system,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                                bool estimate_condition = false);

}  // namespace hemivem
