// What holds the body: the rigid motions its Dirichlet conditions leave free, and whether the
// contact can stop them. Decided from the mesh and the boundary alone, before anything is
// factorized.
#pragma once

#include <string>

#include <hemivem/sparse_factorization.hpp>
#include <vector>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The free rigid motions of a problem and what holds them.
struct Supports {
  /// The motions (a basis, in words: hemivem/vem/rigid_motions.hpp) that the Dirichlet
  /// conditions leave free and only the contact holds: each moves the normal displacement of
  /// some contact node (held at zero by a bilateral constraint, or by the law and the
  /// constraint) or, with a friction law, a tangential one. A is then singular and S positive
  /// semidefinite (definite when a bilateral constraint holds every one of them); the contact
  /// law or the constraint must provide what the supports do not.
  std::vector<std::string> held_by_contact;
  bool semi_coercive() const noexcept { return !held_by_contact.empty(); }
};

/// The supports of a body meshed by `mesh` with the prescribed components of `dofs`, touching
/// its foundation at `boundary` (empty: no contact). `normal_unknowns`: the normal
/// displacements are unknowns of the contact (false for a bilateral constraint, which holds
/// them at zero as a support does); `tangential_law`: a friction law acts on the tangential
/// displacements. Throws InputError naming every motion that nothing holds: one that moves no
/// contact unknown (a rotation no contact node resists, tangential sliding without friction),
/// or any free motion when there is no contact.
Supports find_supports(const Mesh& mesh, const DofMap& dofs, const ContactBoundary& boundary, bool normal_unknowns,
                       bool tangential_law);

/// The same for a boundary in several parts (ContactBoundary::part): a node has normal
/// unknowns unless its part is bilateral, and a tangential law when its part has friction.
/// `bodies`: the mesh is a process's piece of the mesh of those bodies (BasicRigidMotions,
/// BasicElasticityProblem::piece_bodies), whose free motions are judged of the whole bodies.
Supports find_supports(const Mesh& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                       const std::vector<ContactPart>& parts, const PieceBodies& bodies = {});
/// The same for a solid: six rigid motions per piece of the mesh (cells joined through shared
/// faces), held by the normal displacements of its contact nodes (a solid's contact is
/// frictionless: a motion that moves no contact node along its normal is refused).
Supports find_supports(const Mesh3D& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                       const std::vector<BasicContactPart<3>>& parts, const PieceBodies& bodies = {});

/// The box constraint |u_nu| <= g with an obstacle's gap g: throws InputError unless `gap` (at
/// contact node `node`) is finite and >= 0, naming the node, the contact part `part` (when not
/// empty) and the remedy (contact.constraint = "one-sided"). The plane and the solid call it
/// on each node of a box-constrained contact against an obstacle, before anything is factorized.
void require_box_gap(double gap, int node, const std::string& part = {});

/// Throws InputError when a contact part (named by `names`, in part order) has no contact node
/// left: a support prescribes every one of its nodes' normal displacement (or every
/// component), so the part touches nothing. The plane and the solid call it on the boundary
/// they built, before anything is factorized.
void require_nodes_in_every_part(const ContactBoundary& boundary, const std::vector<std::string>& names);

/// The 1-norm condition estimate ||A||_1 ||A^-1||_1 of a matrix `f` has factorized (7 solves
/// with it), independent of the engine: what the plane's and the solid's linear solves report
/// as condition_estimate.
double factorized_condition_estimate(const SparseMatrix& A, const SparseFactorization& f);

}  // namespace hemivem
