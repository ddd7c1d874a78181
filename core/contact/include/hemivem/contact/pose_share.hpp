// A process's share of the full-space route's posed problem (hemivem/contact/full_space.hpp),
// posed from its own rows alone: the whole system is never assembled, rotated or held.
//
// A process owning the vertices first_vertex, ..., end_vertex - 1 of the mesh owns their free
// dofs, a contiguous range of the free unknowns (free dofs are numbered in dof order, and the
// rotation into the contact nodes' frames acts within each node). It assembles the cells that
// hold one of its vertices (assemble_rows: its rows and their mirrored columns), rotates them as
// the whole posing rotates the whole system (Condensation::rotated_part), and takes its
// coordinates from the posing of the contact surface (Condensation::CoordinatesOnly), which every
// process computes whole: the contact boundary, the frames, the coordinates, laws, weights, bounds
// and origins are a cost of the surface, as are the dof map and the traction loads. The result is
// share_of(posed, layout_of(posed, first, owned)) of the whole posed problem, to the bit.
#pragma once

#include <Eigen/Core>

#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/row_distribution.hpp>

namespace hemivem {

/// One process's share of the posed problem and what its Krylov engine is told of it.
struct PosedShare {
  /// Its rows: first (the free index of its first free dof), owned, global (every free unknown)
  /// and its ghosts, the free unknowns of other processes its rows read (from its cells).
  RowLayout layout;
  /// Its rows of the rotated system (matrix.rows() == layout.owned, local columns) and load, and
  /// the coordinates, tied unknowns and groups of its nodes.
  FullSpaceShare share;
  /// Its rows of the preconditioner's near-null space: the mesh's rigid motions
  /// (MeshRigidMotions) in the rotated free unknowns, BasicContactSolver's to the bit.
  Eigen::MatrixXd near_null_space;
  /// The node blocks of the whole problem's unknowns (node_block_size).
  int block_size = 1;
};

/// The share of the vertices first_vertex, ..., end_vertex - 1 of `problem`'s posed problem (as
/// BasicContactSolver::prepare() poses it on the full-space route), at the cost of the cells
/// holding those vertices and of the contact surface. A range whose vertices own no free dof
/// gives an empty share.
///
/// InputError for what prepare() and its posing refuse (with the same messages), for a range of
/// vertices outside the mesh, for a problem without a contact node (nothing to pose: its rows
/// are assemble_rows'), and for two bodies joined at their contact (a part against another body),
/// which are posed with their whole system, in one process only.
template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, int first_vertex, int end_vertex);

}  // namespace hemivem
