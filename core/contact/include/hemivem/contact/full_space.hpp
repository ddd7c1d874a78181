// The full-space route (docs/full-space.md): the contact problem minimized over all free
// unknowns at once, without a factorization. Each Newton system is solved by a preconditioned
// Krylov method (hemivem/krylov_solver.hpp), so that memory and time grow with the unknowns, not
// with a factor's fill or the square of the contact surface.
//
//   min E(x) = 1/2 x^T A x - b^T x + sum_k w_k j_k(a_k),  a_k = x_{row(k)} - origin_k in [lo_k, hi_k],
//
// over the rotated free unknowns x of a posed problem (Condensation::PoseOnly: the same
// coordinates, laws, weights and bounds as the reduced problem, whose F(a) is the minimum of E
// over the other unknowns). The method is the projected semismooth Newton method of the ssn engine
// in the whole space: per coordinate its knots (bounds and kinks of its law), a piece box between
// neighbouring knots on the side of descent, coordinates on a knot held where the one-sided
// derivatives say so, an epsilon-active set sent exactly onto knots; the Newton system is
// A + diag(w_k max(j_k'', 0)) on the moving coordinates (a law's negative curvature left out, so
// that every system is positive definite and CG applies), the held unknowns eliminated; the step
// is backtracked along the projection arc with Armijo's rule on E. E decreases monotonically, so
// the iteration reaches a critical point from any start; where every law is convex it is the
// unique minimizer. Krylov solves are inexact (their tolerance follows the certificate's residual
// down to 1e-12); the verdict is the certificate's (hemivem/certificate.hpp) at the point returned,
// computed from the true residual of the whole system.
#pragma once

#include <Eigen/Core>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/row_distribution.hpp>

#include <vector>

namespace hemivem {

/// What a full-space solve did besides the certificate.
struct FullSpaceStatistics {
  int newton_iterations = 0;
  int krylov_iterations = 0;           ///< summed over the Newton systems
  int preconditioner_setups = 0;
  double preconditioner_seconds = 0.0;  ///< the Krylov engine's compute()
  double krylov_seconds = 0.0;          ///< its solve()
  /// The counts and seconds of `other` added to these (a sequence of solves: a loading path).
  FullSpaceStatistics& operator+=(const FullSpaceStatistics& other) noexcept {
    newton_iterations += other.newton_iterations;
    krylov_iterations += other.krylov_iterations;
    preconditioner_setups += other.preconditioner_setups;
    preconditioner_seconds += other.preconditioner_seconds;
    krylov_seconds += other.krylov_seconds;
    return *this;
  }
};

/// The certificate of the rotated unknowns x of `posed` (Condensation::PoseOnly) at tolerance
/// `tol`: certify() of the reduced problem's coordinates with the smooth gradient read from the
/// residual A x - b of the whole system (the rows of tied unknowns are reactions and not counted).
CertifiedPoint certify_full_space(const Condensation& posed, const Eigen::VectorXd& x, double tol);

/// Minimizes E over the rotated free unknowns of `posed` from *x (its size: start; otherwise 0;
/// the coordinates projected onto their bounds first) with `krylov` for the Newton systems and
/// `hints` for its preconditioner (the rigid motions in the rotated unknowns, or no columns; the
/// unknowns' node blocks). `krylov` is left computed on a matrix of this call only: compute() it
/// again before another solve().
/// Returns the minimizer's report at the point it ends on (a, the forces and the certificate;
/// objective E there) and leaves that point in *x. Groups of coordinates (a solid's isotropic
/// friction) move as the ssn engine moves them (hemivem/group_motion.hpp), each Newton system
/// solved with a group's two unknowns in the frame of its motion.
MinimizerResult minimize_full_space(const Condensation& posed, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics = nullptr);

/// The same with the coordinates' laws, weights and bounds of `coordinates` (posed.reduced()
/// with any of them changed: a step of a loading path, hemivem/path/path.hpp; its S and c are not
/// read) and the origin of each coordinate, a_k = x_row(k) - origin(k), instead of the posed
/// problem's. InternalError when their sizes are not the posed problem's coordinates'.
MinimizerResult minimize_full_space(const Condensation& posed, const ReducedProblem& coordinates,
                                    const Eigen::VectorXd& origin, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics = nullptr);

/// One process's share of a posed problem distributed by rows (hemivem/row_distribution.hpp):
/// the rows it owns of the rotated whole system and the coordinates whose unknowns they are.
/// Every coordinate, tied unknown and group belongs to the process that owns its row(s).
struct FullSpaceShare {
  /// the owned rows, local columns (owned rows, then the layout's ghosts); moved without a copy
  MovableSparseMatrix matrix;
  Eigen::VectorXd load;  ///< the owned rows of the load
  /// The laws, weights, bounds and groups of this process's coordinates (S and c are not read).
  ReducedProblem coordinates;
  std::vector<int> coordinate_rows;  ///< each coordinate's local row
  Eigen::VectorXd origin;            ///< each coordinate's origin
  std::vector<int> tied_rows;        ///< the local rows of tied unknowns (their reactions are not residuals)
  /// Each coordinate's number in the whole problem (of the posed problem it was taken from).
  std::vector<Eigen::Index> coordinate_numbers;
  /// The owned rows of the posed problem's free motions (Condensation::free_motions()) of a
  /// semi-coercive problem (no columns: the supports hold the body). Across processes each
  /// process gathers the whole contact surface's components of them to prove that E is bounded
  /// below (the existence check reads the whole surface).
  Eigen::MatrixXd free_motions;
};

/// The layout of rows first, ..., first + owned - 1 of `posed`'s rotated unknowns, its ghosts the
/// other unknowns those rows read.
RowLayout layout_of(const Condensation& posed, Eigen::Index first, Eigen::Index owned);
/// The share of `posed` (held whole by this process) of the rows of `layout`; InternalError for a
/// layout of other rows or one that splits a group's two unknowns.
FullSpaceShare share_of(const Condensation& posed, const RowLayout& layout);

/// The coordinates, origins, groups and tied rows of `posed` whose rows are first, ..., first +
/// owned - 1, put into `share` (empty there): its coordinates, coordinate_rows, origin, tied_rows
/// and coordinate_numbers. InternalError for rows that split a group's two unknowns.
void share_coordinates(const Condensation& posed, Eigen::Index first, Eigen::Index owned, FullSpaceShare& share);
/// The laws, weights, bounds and origins of the share's coordinates (share.coordinate_numbers)
/// set to those of the whole problem's `coordinates` and `origin` (posed.reduced() and
/// posed.origin() with any of them changed, as a step of a path changes them).
void set_share_coordinates(const ReducedProblem& coordinates, const Eigen::VectorXd& origin, FullSpaceShare& share);

/// Collective over `rows`: certify_full_space() of the whole problem whose shares the processes
/// hold, at their owned rows x; every process gets the same certificate and its own coordinates.
CertifiedPoint certify_full_space(const FullSpaceShare& share, const RowDistribution& rows, const Eigen::VectorXd& x,
                                  double tol);

/// Collective over hints.rows (the distribution whose layout `share` was made for; null: one
/// process holding the whole problem): minimize_full_space() of the problem whose shares the
/// processes hold. *x holds the owned rows. The certificate, energy, counts and verdict are the
/// whole problem's, the same on every process; the coordinates, forces and x are this process's.
MinimizerResult minimize_full_space(const FullSpaceShare& share, KrylovSolver& krylov, const KrylovHints& hints,
                                    const MinimizerOptions& options, Eigen::VectorXd* x,
                                    FullSpaceStatistics* statistics = nullptr);

/// minimize_full_space() of `share` with its matrix lent to the iteration: on several processes,
/// with an engine that distributes the system (KrylovSolver::runs_across_processes()), each Newton
/// matrix is written into share.matrix for the engine's compute() and solve(), and the values it
/// changed (those of the contact rows and columns) are restored to the bit right after the solve,
/// instead of a second matrix of the share's size; the engine may read share.matrix where it lies.
/// share.matrix is as it was whenever the call returns or throws. In one process it is
/// minimize_full_space().
MinimizerResult minimize_full_space_in_place(FullSpaceShare& share, KrylovSolver& krylov, const KrylovHints& hints,
                                             const MinimizerOptions& options, Eigen::VectorXd* x,
                                             FullSpaceStatistics* statistics = nullptr);

}  // namespace hemivem
