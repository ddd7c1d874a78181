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

/// Global degrees of freedom: dim*v + c for component c of vertex v (dim = 2 in the plane, 3 in a
/// solid); each is free or prescribed. The free dofs are numbered in dof order, or vertex by
/// vertex along a vertex order (make_dof_map). The map holds the prescribed dofs alone, with the
/// order where one is given: its memory is that of the supports, not of the mesh (a process of a
/// run across processes holds no array of the whole problem's dofs for it). Looking a dof or a
/// free index up costs a binary search among the prescribed dofs.
class DofMap {
 public:
  /// No dofs.
  DofMap() = default;
  /// `num_dofs` dofs of `components` per vertex, of which `prescribed_dofs` (increasing,
  /// distinct) are prescribed with `values` (in their order); the free dofs numbered in dof order,
  /// or along `vertex_order` (a permutation of the num_dofs / components vertices, checked by
  /// make_dof_map) when it is not empty. InternalError for inconsistent sizes or dofs.
  DofMap(int num_dofs, int components, std::vector<int> prescribed_dofs, Eigen::VectorXd values,
         std::vector<int> vertex_order = {});

  int num_dofs() const noexcept { return num_dofs_; }
  int num_free() const noexcept { return num_dofs_ - num_prescribed(); }
  int num_prescribed() const noexcept { return static_cast<int>(prescribed_.size()); }
  /// The index of `dof` among the free dofs, or -1 where it is prescribed (0 <= dof < num_dofs()).
  int free_index(int dof) const;
  /// The dof of the free index f (0 <= f < num_free()).
  int free_dof(int f) const;
  /// Whether `dof` is prescribed.
  bool is_prescribed(int dof) const;
  /// The prescribed value of `dof`, 0 for a free dof.
  double prescribed_value(int dof) const;
  /// The prescribed dofs, increasing, and their values in that order.
  const std::vector<int>& prescribed_dofs() const noexcept { return prescribed_; }
  const Eigen::VectorXd& prescribed_values() const noexcept { return values_; }
  /// New values of the prescribed dofs, in the order of prescribed_dofs(); InternalError for
  /// another count.
  void set_prescribed_values(Eigen::VectorXd values);
  /// The values of `all` (one per dof) at the prescribed dofs, in their order.
  Eigen::VectorXd prescribed_part(const Eigen::VectorXd& all) const;
  /// The prescribed values of every dof, 0 at the free ones: a vector of the whole problem's dofs.
  Eigen::VectorXd prescribed() const;
  /// The free index of every dof (free_index()): a table of the whole problem's dofs, for a loop
  /// over the whole mesh that holds vectors of its size anyway.
  std::vector<int> free_index_table() const;
  /// Full vector of nodal displacements from the free values.
  Eigen::VectorXd expand(const Eigen::VectorXd& free_values) const;
  /// The free values of `u` (one per dof), in the free dofs' order: expand()'s inverse.
  /// InputError for another size.
  Eigen::VectorXd free_part(const Eigen::VectorXd& u) const;

 private:
  /// The position of `dof` in the free dofs' numbering order (dof order, or along the vertex
  /// order), counting the prescribed ones; and the dof at such a position.
  int slot_of(int dof) const;
  int dof_at(int slot) const;
  /// visit(dof, f) for every free dof, f its free index, in the order of the free indices.
  template <class Visit>
  void for_each_free(Visit&& visit) const {
    const std::vector<int>& slots = order_.empty() ? prescribed_ : slots_;
    std::size_t j = 0;
    int f = 0;
    for (int slot = 0; slot < num_dofs_; ++slot) {
      if (j < slots.size() && slots[j] == slot)
        ++j;
      else
        visit(dof_at(slot), f++);
    }
  }

  int num_dofs_ = 0;
  int components_ = 1;
  std::vector<int> prescribed_;  ///< increasing
  Eigen::VectorXd values_;       ///< of prescribed_, in its order
  std::vector<int> slots_;       ///< slot_of each prescribed dof, increasing (prescribed_ without an order)
  std::vector<int> order_;       ///< the vertex order, empty for dof order
  std::vector<int> position_;    ///< each vertex's position in order_ (empty without one)
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
