// A process's share of the full-space route's posed problem (hemivem/contact/full_space.hpp),
// posed from its own rows alone: the whole system is never assembled, rotated or held.
//
// A process owning the vertices first_vertex, ..., end_vertex - 1 of the mesh owns their free
// dofs, a contiguous range of the free unknowns (free dofs are numbered in dof order, and the
// rotation into the contact nodes' frames acts within each node). Given a vertex order, the free
// dofs are numbered along it and a process owns a range of its positions instead: a compact
// part of a mesh whose own order is not (hemivem/mesh/vertex_order.hpp). It assembles the cells that
// hold one of its vertices (assemble_rows: its rows and their mirrored columns), rotates them as
// the whole posing rotates the whole system (Condensation::rotate_part), and takes its
// coordinates from the posing of the contact surface (Condensation::CoordinatesOnly), which every
// process computes whole: the contact boundary, the frames, the coordinates, laws, weights, bounds
// and origins are a cost of the surface, as are the dof map and the traction loads. The result is
// share_of(posed, layout_of(posed, first, owned)) of the whole posed problem, to the bit.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/krylov_solver.hpp>
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
/// Two bodies joined at their contact (a part against another body, hemivem/contact/joining.hpp)
/// are posed in the coordinates relative at their pairs, each process joining its own rows. The
/// joining reads, besides them, the row and load of each pair's node across from one of its
/// vertices (assembled from that node's cells) and the unknowns across from each node among its
/// unknowns: a surface's worth, whatever the split.
///
/// Where a pair's node is free and a vertex across from it prescribed, the joined load takes
/// the system's columns at that node (Joining::shifts_load), which every process assembles from
/// the node's cells.
///
/// InputError for what prepare() and its posing refuse (with the same messages), for a range of
/// vertices outside the mesh, and for a problem without a contact node (nothing to pose: its
/// rows are assemble_rows').
template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, int first_vertex, int end_vertex);
/// The same of the vertices vertex_order[first], ..., vertex_order[end - 1], the free unknowns
/// numbered along `vertex_order` (make_dof_map with it): the share of the whole posed problem in
/// that numbering, the values of its rows the same to the bit. InputError as pose_share() and
/// for an order that is not a permutation of the mesh's vertices.
template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, const std::vector<int>& vertex_order, int first,
                      int end);

/// The vertices process `rank` of `size` owns on the full-space route across processes: the
/// mesh's vertices split evenly in their order, [first, end), or the positions [first, end) of
/// a vertex order. A generated box numbers its vertices layer by layer, so that each process
/// owns a slab; a mesh made whole on every process (a Gmsh file's, an adaptive solve's refined
/// mesh) is split along hilbert_vertex_order (hemivem/mesh/vertex_order.hpp).
std::pair<int, int> vertex_share(int num_vertices, int rank, int size);

/// How the processes make the distribution of their posed rows: collective, as
/// make_distributed_rows (hemivem/krylov_solver.hpp), which is the one the command passes.
using RowDistributor = std::function<std::unique_ptr<RowDistribution>(RowLayout)>;

/// The full-space route across processes for a sequence of solves of one problem (the steps of a
/// loading path, hemivem/path/path.hpp): each process poses its share once (pose_share) and the
/// coordinates of the whole contact surface (Condensation::CoordinatesOnly: its frames, laws,
/// bounds and origins); each solve takes the whole problem's load and the coordinates' laws,
/// weights, bounds and origins of the moment, and gives every process the whole point found,
/// its residual and energy. Every member function but the accessors is collective: the
/// processes make the same calls in the same order.
template <int dim>
class FullSpaceShares {
 public:
  /// Poses the share of process world.rank (vertex_share, along `vertex_order` unless it is
  /// empty) and distributes the rows by `distribute`; `krylov` is kept by reference and must
  /// outlive this. The errors of pose_share: a process whose posing fails throws its error, and
  /// every other, before the rows are distributed, an InputError with its message
  /// (on_every_process, hemivem/every_process.hpp), so that none waits for it.
  FullSpaceShares(const BasicContactProblem<dim>& problem, KrylovSolver& krylov, ProcessWorld world,
                  const RowDistributor& distribute, const std::vector<int>& vertex_order = {});
  ~FullSpaceShares();
  FullSpaceShares(const FullSpaceShares&) = delete;
  FullSpaceShares& operator=(const FullSpaceShares&) = delete;

  /// The posed coordinates of the whole contact surface (Condensation::set_gaps changes their
  /// bounds; a new load goes through set_load() here, which the share's rows take too).
  Condensation& posed() noexcept;
  const Condensation& posed() const noexcept;
  /// The whole problem's dof map (held once, by posed() for one body): the numbering of its
  /// free dofs, and the problem's prescribed values until set_load() gives others.
  const DofMap& dofs() const noexcept;
  const ContactSetUp<dim>& contact() const noexcept;
  /// The distribution of the rows (its collectives: sum, max, all_gather).
  const RowDistribution& distribution() const noexcept;
  /// The seconds this process's posing took, as a solve's stages: "assembly" (its rows),
  /// "setup" (the contact surface: parts, nodes, gaps) and "posing" (the rotation of its rows,
  /// the coordinates and the distribution of the rows).
  const std::map<std::string, double>& timings() const noexcept;

  /// A new load of the whole problem, as Condensation::set_load takes it: posed() and this
  /// process's rows take it. Of one body only this process's rows of `b` are rotated
  /// (Condensation::rotated_part) and posed() keeps no rotated load; two joined bodies' load is
  /// joined and rotated whole. Not collective.
  void set_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed);
  /// t times the load the shares were posed with (the load and prescribed values of the
  /// problem given to the constructor): a proportional loading's step. Of one body this
  /// process's rows and posed()'s prescribed values are scaled, and no vector of the whole
  /// problem is made; two joined bodies gather the whole load and set t times it (set_load).
  /// The same bits as set_load() of t times the whole load and prescribed values. Collective.
  void scale_load(double t);
  /// Whether the load of the moment is zero in every row, exactly (its rotated rows on every
  /// process). Collective.
  bool load_is_zero() const;

  /// The resultant of the applied load (tractions, body force) of `at`, the shares' problem
  /// with its loads of the moment: each process sums its own vertices (vertex_share; a piece of
  /// the mesh, hemivem/mesh/box_piece.hpp, holds every cell of them) and the sums are added in
  /// the order of the processes, the same on every process. Collective.
  PointOf<dim> applied(const BasicElasticityProblem<dim>& at) const;
  /// contact_force_balance (hemivem/contact/solver.hpp) of the whole problem `at` with the
  /// whole displacement u and contact nodes, summed as applied() is: exact on a piece of the
  /// mesh. InputError on every process alike when one finds it. Collective.
  BasicForceBalance<PointOf<dim>> balance(const BasicElasticityProblem<dim>& at, const Eigen::VectorXd& u,
                                          const std::vector<BasicContactNode<dim>>& contact) const;

  /// Whether the contact table reads the residual: a contact node without a normal coordinate
  /// (a bilateral node) takes its normal force from it (contact_node), so the residual of the
  /// whole problem is gathered; else no process needs it. The same on every process.
  bool contact_reads_residual() const;

  /// What a solve gives every process: the point of the whole problem, its unknowns in the
  /// process's own rows (distribution().all_gather() makes the whole vectors where a caller
  /// needs them).
  struct Point {
    /// The minimizer's result of the whole problem: its certificate, verdict and counts, and
    /// every coordinate's value a, law force and reaction.
    MinimizerResult result;
    Eigen::VectorXd x;         ///< the rotated free unknowns x~ of this process's own rows
    Eigen::VectorXd residual;  ///< A~ x~ - b~, rotated, of this process's own rows
    /// 1/2 x~.A~ x~ - x~.b~ of the whole problem, and for two bodies whose joined load is
    /// shifted the part the joined system leaves out (Condensation::shift_energy): 1/2 u.A u -
    /// u.b of the free dofs.
    double quadratic = 0.0;
  };
  /// minimize_full_space() of the whole problem with the coordinates' laws, weights, bounds and
  /// groups of `coordinates` (posed().reduced() with any of them changed; its S and c are not
  /// read) and their `origin`, from the rotated unknowns `start`: every one, or this process's
  /// own (distribution().layout()'s owned rows); empty: from 0.
  Point minimize(const ReducedProblem& coordinates, const Eigen::VectorXd& origin, const MinimizerOptions& options,
                 const Eigen::VectorXd& start = Eigen::VectorXd(), FullSpaceStatistics* statistics = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Collective over the processes of `world`: the full-space route of BasicContactSolver (a
/// Krylov engine with the semismooth Newton iteration, nothing condensed), each process posing
/// and solving the share of its vertices (vertex_share, pose_share; along `vertex_order` unless
/// it is empty), the rows distributed by `distribute`. Then the processes' results are gathered
/// (the rotated unknowns, the contact coordinates' values and forces, and the residual where a
/// bilateral node's normal force needs it), and every process
/// returns the whole solution as BasicContactSolver::run() reports it (the displacement, the
/// contact table, the potential energy, the balance of forces, the certificate and verdict of the
/// whole problem), the same on each: what follows a solve (an error estimate, the marking of an
/// adaptive solve) then decides alike on every process. `start_u`, when not empty, is the nodal
/// displacement the iteration starts from (BasicContactSolver::start_from); its process's rows
/// rotated, it is given back before the solve (a caller that needs it no more moves it in). Its stages and
/// timings are those of the route in one process: assembly (this process's rows), posing (with
/// the timing setup, FullSpaceShares::timings), full_space, then post_process (gathering and
/// making the results) and release (`krylov` released, KrylovSolver::release, once the point is
/// found and before the whole results are made; then the shares given back).
/// uniqueness_margin is NaN, as on the route in one process. With one process this is that
/// route on one share holding every row.
///
/// A solid's friction (groups of two coordinates) runs across processes as in one: each process
/// turns its rows into the frames of its own groups' motions and its ghost columns into those of
/// the groups of other processes it reads (their owners send the frames).
///
/// InputError (on every process alike) for what pose_share refuses; NumericalError for a Krylov
/// engine's failure.
template <int dim>
BasicContactSolution<dim> solve_full_space_shares(const BasicContactProblem<dim>& problem, KrylovSolver& krylov,
                                                  ProcessWorld world, const RowDistributor& distribute,
                                                  const MinimizerOptions& options,
                                                  Eigen::VectorXd start_u = Eigen::VectorXd(),
                                                  const std::vector<int>& vertex_order = {});

}  // namespace hemivem
