// Boundary conditions, loads and the global assembly of the VEM elasticity system.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <array>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/sparse_factorization.hpp>
#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/vem/element.hpp>
#include <hemivem/vem/problem.hpp>

namespace hemivem {

/// Global degrees of freedom: 2*v + c for component c of vertex v.
struct DofMap {
  std::vector<int> free_index;  ///< per global dof: index among the free dofs, or -1 if prescribed
  std::vector<int> free_dofs;   ///< global dof of each free dof
  Eigen::VectorXd prescribed;   ///< per global dof: prescribed value (0 for free dofs)
  int num_free() const noexcept { return static_cast<int>(free_dofs.size()); }
  int num_dofs() const noexcept { return static_cast<int>(free_index.size()); }
  /// Full vector of nodal displacements from the free values.
  Eigen::VectorXd expand(const Eigen::VectorXd& free_values) const;
};

/// The reduced system A u_f = b (prescribed dofs eliminated, their values lifted into b).
struct LinearSystem {
  MovableSparseMatrix A;  ///< symmetric, both triangles stored
  Eigen::VectorXd b;
  DofMap dofs;
};

/// The rows of the reduced system A u_f = b (assemble()) that belong to some vertices, assembled
/// from the cells that hold one of them alone (a process's share of a system distributed by
/// rows). The free dofs are numbered vertex by vertex (in dof order, or along a vertex order) and
/// the vertices are consecutive in that numbering, so that their free dofs are the contiguous
/// range first, ..., first + owned - 1: the owned free dofs.
struct SystemRows {
  DofMap dofs;             ///< the whole problem's
  Eigen::Index first = 0;  ///< the free index of the first owned free dof
  Eigen::Index owned = 0;  ///< how many free dofs are owned
  /// A's rows and columns: the free dofs of the owned vertices and of every vertex of a cell
  /// holding one, increasing; the owned ones are unknowns[at], ..., unknowns[at + owned - 1].
  std::vector<int> unknowns;
  Eigen::Index at = 0;
  /// The entries of assemble()'s A in the owned rows and in the owned columns, its pattern and
  /// its values there to the bit; no entry between two unknowns that are not owned. The owned
  /// columns are kept besides the rows because A is symmetric within round-off only (in the
  /// plane), and a symmetric product with the owned unknowns (the rotation Q^T A Q of the
  /// full-space route) reads both.
  MovableSparseMatrix A;
  /// The owned rows of assemble()'s b (body force, tractions, prescribed values lifted), to the bit.
  Eigen::VectorXd b;
};

/// The global stiffness of all 2*num_vertices dofs (symmetric, both triangles stored).
/// Cost linear in the number of elements.
SparseMatrix assemble_stiffness(const Mesh& mesh, const MaterialTable& materials,
                                Stabilization stabilization = Stabilization::two_mu);

/// The load vector of all dofs: body force through Pi^nabla_1 (3.13) and tractions.
Eigen::VectorXd assemble_load(const Mesh& mesh, const VectorField& body_force,
                              const std::vector<TractionLoad>& tractions);

/// (K u)_d on the dofs d with rows[d] != 0 (0 elsewhere), K the global stiffness of all
/// 2*num_vertices dofs (assemble_stiffness): computed from the elements that hold such a dof
/// only, without storing K. `u` and `rows` have one entry per dof.
Eigen::VectorXd apply_stiffness(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                                const Eigen::VectorXd& u, const std::vector<char>& rows);

/// The entries of assemble_load(mesh, body_force, tractions) at the dofs of the vertices
/// `vertices` (increasing, distinct): 2 per vertex (3 in a solid), in their order, the same bits,
/// at the memory of those entries alone (a process's own vertices of a piece of the mesh, whatever
/// the whole mesh's size). InputError for a vertex out of range or out of order.
Eigen::VectorXd assemble_load_at(const Mesh& mesh, const VectorField& body_force,
                                 const std::vector<TractionLoad>& tractions, std::span<const int> vertices);

/// The entries of apply_stiffness(mesh, materials, stabilization, u, flags) at the dofs of the
/// vertices `vertices` (increasing, distinct), `rows` flagging those dofs (one flag per dof of
/// them, in their order): (K u) where flagged, 0 elsewhere, the same bits, computed from the cells
/// holding a flagged dof alone and held for those dofs alone. `u` has one entry per dof of the
/// mesh. InputError as assemble_load_at() and for vectors of other sizes.
Eigen::VectorXd apply_stiffness_at(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                                   const Eigen::VectorXd& u, std::span<const int> vertices,
                                   const std::vector<char>& rows);

/// The degrees-of-freedom map of a problem's Dirichlet conditions, its free dofs in dof order.
DofMap make_dof_map(const Mesh& mesh, const std::vector<DirichletCondition>& dirichlet);
/// The same with the free dofs numbered vertex by vertex along `vertex_order` (each vertex's in
/// the order of their components): a permutation of the mesh's vertices, InputError otherwise.
/// A compact order (hemivem/mesh/vertex_order.hpp) gives each of a split of the free dofs into
/// ranges a compact part of the mesh.
DofMap make_dof_map(const Mesh& mesh, const std::vector<DirichletCondition>& dirichlet,
                    const std::vector<int>& vertex_order);

/// Assembles the reduced system of a problem. Throws InputError, before any assembly, when
/// the body is not held (no Dirichlet edge, or Dirichlet edges of zero total length).
LinearSystem assemble(const ElasticityProblem& problem);

/// The rows of assemble(problem) of the vertices first_vertex, ..., end_vertex - 1 (SystemRows),
/// from the cells that hold one of them: the cost of those cells and of the load's tractions, and
/// memory for their rows besides the dof map. InputError as assemble(), and for a range of
/// vertices outside the mesh.
SystemRows assemble_rows(const ElasticityProblem& problem, int first_vertex, int end_vertex);
/// The same of the vertices vertex_order[first], ..., vertex_order[end - 1] of the system whose
/// free dofs are numbered along `vertex_order` (make_dof_map with it; SystemRows::dofs is that
/// map): the rows and columns of assemble(problem) permuted into that numbering, their values to
/// the bit. InputError as assemble_rows() and make_dof_map().
SystemRows assemble_rows(const ElasticityProblem& problem, const std::vector<int>& vertex_order, int first, int end);

/// The load of the free dofs of `dofs` (LinearSystem::b): f - K u_p on them, u_p the
/// prescribed values of `dofs` (which must be make_dof_map of the problem's Dirichlet parts;
/// their values may differ). Costs the load vector and the element matrices of the elements
/// holding a nonzero prescribed value: a new load on an assembled matrix.
Eigen::VectorXd assemble_rhs(const ElasticityProblem& problem, const DofMap& dofs);
/// The same written into `b` (num_free() entries; InternalError otherwise), a part of a larger
/// vector if need be: a loading path's step assembles its load where it keeps it.
void assemble_rhs(const ElasticityProblem& problem, const DofMap& dofs, Eigen::Ref<Eigen::VectorXd> b);

/// Per element: the P1 projection Pi u_h of the full nodal vector u.
std::vector<LinearField> project_solution(const Mesh& mesh, const Eigen::VectorXd& u);

}  // namespace hemivem
