// Loading histories (docs/paths.md): a sequence of load factors t_1 < ... < t_K. Step k is the
// static contact problem at t_k, started from step k - 1's solution and certified on its own.
// With friction the tangential potential acts on the slip of the step, u_tau - u_tau^(k-1);
// a friction bound that depends on the normal contact (FrictionBound: Coulomb's mu p, or
// h(u_nu)) is resolved within each step by a fixed point of Tresca problems. One assembly and
// one condensation serve the whole path: S does not change along it, and under proportional
// loading neither does c but for the factor t, so a step costs no linear solve. Written once
// for plane (dim = 2) and solid (dim = 3) bodies; the plane's names are the <2> instances.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/certificate.hpp>
#include <hemivem/contact/forces.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

/// How the problem's data change along the path.
template <int dim>
struct BasicPathLoading {
  /// The load factors, finite, > 0 and strictly increasing (at least one).
  std::vector<double> t;
  /// Sets the problem's loads, prescribed values, gaps and obstacle to their values at t (the
  /// mesh, the materials, the boundary parts, the laws and which dofs are prescribed stay;
  /// InputError otherwise). Empty: proportional loading, the problem as given being the one at
  /// t = 1: its load vector and its prescribed displacements are multiplied by t, its gaps and
  /// obstacle stay. A step then costs no linear solve; with `update` it costs none when its
  /// load is a combination of loads already condensed (PathOptions::solved_loads), else one
  /// interior solve for the condensed load and one for the displacement.
  std::function<void(double t, BasicContactProblem<dim>& problem)> update;
  /// Whether `update` may change prescribed values, and gaps or obstacles: a step rebuilds
  /// the dof map's prescribed values, and the contact boundary's gaps, only where it may.
  bool updates_prescribed = true;
  bool updates_gaps = true;
  bool proportional() const noexcept { return !update; }
};
using PathLoading = BasicPathLoading<2>;

/// The fixed point on the friction bound of each step (FrictionBound): g <- g + theta (G(g) - g),
/// G(g) the bound the solution of the Tresca problem with bound g implies, accelerated.
struct FixedPointOptions {
  int max_iterations = 100;
  /// theta, in (0, 1]. Halved (down to 1/64) whenever the change of the bound grew in two
  /// iterations in a row: a fixed point that does not contract is damped, and reported as not
  /// converged when it still does not meet the certificate within max_iterations.
  double relaxation = 1.0;
  /// Anderson's acceleration: each bound mixes the last anderson_depth + 1 iterates so that
  /// their combined mismatch G(g) - g is least (bounds below 0 are set to 0); its history is
  /// forgotten when the change of the bound grows. 0: the relaxed iteration alone.
  int anderson_depth = 3;
};

template <int dim>
struct BasicPathStep;

template <int dim>
struct BasicPathOptions {
  MinimizerOptions minimizer;
  FixedPointOptions fixed_point;
  /// A step whose change ||a_k - a_(k-1)||_inf exceeds jump_factor times the change the step
  /// before predicts (scaled by the ratio of the load increments) is a jump: the critical point
  /// the path followed stopped existing and the minimizer found another branch.
  double jump_factor = 10.0;
  /// Steps (1-based) whose full displacement is computed and handed to on_step
  /// (PathStep::u, PathStep::forces); the last step always is. Each costs one interior solve
  /// on the condensed route, nothing on the full-space route.
  std::function<bool(int step)> frame;
  /// At most this many loads are kept condensed (docs/paths.md, "What a step costs"): a step
  /// whose load (the free dofs' right-hand side and the prescribed values) is a combination of
  /// them, within 1e-12 of its norm, is condensed without an interior solve. 0: every step of a
  /// path with an update condenses its own load.
  int solved_loads = 6;
  /// Called after each step; returning false stops the path after it (the solution then holds
  /// the steps done).
  std::function<bool(const BasicPathStep<dim>&)> on_step;
  /// false: BasicPathSolution::steps holds the last step alone, each earlier one is dropped once
  /// on_step has seen it, and the solution's counts say the rest (solved_steps, converged_steps,
  /// jumps, the first failure): the memory of a path then does not grow with its steps.
  bool keep_steps = true;
  /// The full-space route across processes (a Krylov engine with
  /// KrylovSolver::runs_across_processes()): each process of `world` poses and solves its share
  /// of every step (FullSpaceShares, hemivem/contact/pose_share.hpp), its rows distributed by
  /// `distribute` (make_distributed_rows), and runs the path's own work on the whole contact
  /// surface as every other process does; every process gets the whole path. Empty: one process.
  RowDistributor distribute;
  ProcessWorld world;
  /// The order the processes share the vertices along (FullSpaceShares); empty: the mesh's own.
  std::vector<int> vertex_order;
};
using PathOptions = BasicPathOptions<2>;

/// The fixed point of a step with a friction bound that depends on the normal contact.
struct FixedPointReport {
  bool used = false;         ///< false without a FrictionBound (one minimization per step)
  int iterations = 0;        ///< Tresca problems solved
  /// The last change of the bound, max_i |G(g)_i - g_i| over max_i |G(g)_i| (0 when both vanish).
  double change = 0.0;
  double relaxation = 1.0;   ///< theta at the end
  bool converged = false;    ///< the coupled certificate holds (PathStep::certificate)
};

template <int dim>
struct BasicPathStep {
  using Point = Eigen::Matrix<double, dim, 1>;
  int index = 0;  ///< 1-based
  double t = 0.0;
  /// The verdict, as a static solve's: the minimizer's status, demoted to failed when the
  /// fixed point does not hold (the coupled certificate, friction_bound_certificate).
  MinimizerStatus status = MinimizerStatus::failed;
  std::string message;
  Certificate certificate;
  bool may_be_nonunique = false;
  int iterations = 0;  ///< the minimizer's, summed over the fixed point's iterations
  /// The potential energy of the step's problem (its friction term on the slip of the step).
  double energy = 0.0;
  /// The contact nodes: u_nu, the forces, u_tau (the total tangential displacement) and the
  /// friction force and state of the step (stick: no slip in the step).
  std::vector<BasicContactNode<dim>> contact;
  /// The slip of the step, u_tau - u_tau^(k-1), per contact node: along tau in the plane, its
  /// length |u_t - u_t^(k-1)| on a solid's surface (empty without friction; NaN at the nodes of
  /// a frictionless part beside one with friction).
  Eigen::VectorXd slip;
  /// The friction bound g_i of each node at the end of the step (empty without friction; NaN
  /// where slip is).
  Eigen::VectorXd friction_bound;
  BasicContactZone<dim> zone;
  Point contact_force = Point::Zero();  ///< the resultant of the contact forces on the body
  Point applied = Point::Zero();        ///< the resultant of the applied load (tractions, body force)
  FixedPointReport fixed_point;
  double change = 0.0;  ///< ||a_k - a_(k-1)||_inf (a_0 = 0)
  bool jump = false;    ///< PathOptions::jump_factor
  Eigen::VectorXd a;    ///< the contact unknowns (u_nu, then u_tau, as the reduced problem orders them)
  /// A frame's full nodal displacement and balance of forces (PathOptions::frame); empty otherwise.
  Eigen::VectorXd u;
  std::optional<BasicForceBalance<Point>> forces;
  double seconds = 0.0;
  bool converged() const noexcept { return status == MinimizerStatus::converged; }
};
using PathStep = BasicPathStep<2>;

template <int dim>
struct BasicPathSolution {
  /// Every step, or the last alone (BasicPathOptions::keep_steps).
  std::vector<BasicPathStep<dim>> steps;
  int solved_steps = 0;     ///< the steps solved, whether kept or not
  int converged_steps = 0;  ///< of them, those that converged
  /// The last step as a static solve reports it (u, contact, energy, forces, certificate,
  /// stages and timings of the whole path), for every output that reads a solve. When a step
  /// did not converge, its status and message are the first such step's (its index, t, status
  /// and why, and that the steps after it started from its uncertified state), so that the
  /// path is never reported converged past a failed step.
  BasicContactSolution<dim> last;
  bool proportional = true;
  /// The loads condensed along the path, each one interior solve (frames' not counted): 1 on
  /// a proportional path or when every step's load is a multiple of the first's; one per field
  /// when the loads combine fields with coefficients in t; at most one per step otherwise.
  int condensed_loads = 0;
  /// Seconds: assembly, condensation, path (every step), frames (their displacements), total;
  /// on the full-space route posing instead of condensation, and the Krylov engine's
  /// preconditioner and krylov seconds within path.
  std::map<std::string, double> timings;
  /// Every step converged.
  bool converged() const { return solved_steps > 0 && converged_steps == solved_steps; }
  /// The steps that were jumps (BasicPathStep::jump).
  int jumps() const { return jump_count; }
  int jump_count = 0;
};
using PathSolution = BasicPathSolution<2>;

/// The coupled certificate of a step with a friction bound that depends on the normal contact:
/// the Tresca certificate `tresca` of the step's problem solved with bounds `used`, and the
/// mismatch of those bounds against the bounds `implied` by the solution, as a force:
/// dual = max(tresca.dual, max_i w_i |used_i - implied_i| / tresca.force_scale). It holds when
/// the normal conditions hold, every tangential force is within w_i implied_i and equals it
/// (against the slip) where the node slips.
Certificate friction_bound_certificate(const Certificate& tresca, const Eigen::VectorXd& weights,
                                       const Eigen::VectorXd& used, const Eigen::VectorXd& implied);

/// The path of one contact problem, set up by the stages of the static solve
/// (BasicContactSolver::prepare: assembly, contact boundary, supports, condensation).
/// `problem` is changed by the loading's update and must outlive the solver, as must the
/// minimizer. InputError for an unusable path (no step, t not increasing or not positive, an
/// engine across processes) or problem; NumericalError when the factorization fails. A step
/// that does not converge is reported, and the path goes on from it; the path then has not
/// converged (BasicPathSolution::last carries that step's status).
template <int dim>
class BasicPathSolver {
 public:
  BasicPathSolver(BasicContactProblem<dim>& problem, std::unique_ptr<SparseFactorization> factorization,
                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading, BasicPathOptions<dim> options = {});
  /// The path on the full-space route (hemivem/contact/full_space.hpp, docs/full-space.md): one
  /// assembly and one posing serve every step; each step (each iterate of a fixed point on the
  /// friction bound) is a semismooth Newton iteration in the whole space, started from the step
  /// before, its systems solved by `krylov`. The minimizer must be ssn (the route's own iteration;
  /// another is an InputError naming it). A step's load costs no solve and a frame no solve; the
  /// uniqueness margin is not measured (BasicContactSolver's full-space constructor).
  BasicPathSolver(BasicContactProblem<dim>& problem, std::unique_ptr<KrylovSolver> krylov,
                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading, BasicPathOptions<dim> options = {});
  ~BasicPathSolver();
  BasicPathSolver(const BasicPathSolver&) = delete;
  BasicPathSolver& operator=(const BasicPathSolver&) = delete;
  BasicPathSolution<dim> run();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};
using PathSolver = BasicPathSolver<2>;

/// Solves `problem` along `loading` (BasicPathSolver).
template <int dim>
BasicPathSolution<dim> solve_path(BasicContactProblem<dim>& problem, std::unique_ptr<SparseFactorization> factorization,
                                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                  BasicPathOptions<dim> options = {});
/// The same on the full-space route.
template <int dim>
BasicPathSolution<dim> solve_path(BasicContactProblem<dim>& problem, std::unique_ptr<KrylovSolver> krylov,
                                  const NonsmoothMinimizer& minimizer, BasicPathLoading<dim> loading,
                                  BasicPathOptions<dim> options = {});

}  // namespace hemivem
