// The whole solve of a contact problem, in stages (ContactSolver):
//   assembly -> condensation through a SparseFactorization -> ReducedProblem ->
//   NonsmoothMinimizer -> back-substitution -> post-processing,
// running only the stages the problem needs: without a contact boundary one linear solve;
// without gaps no constraint (ConstraintKind::none).
#pragma once

#include <Eigen/Core>

#include <chrono>
#include <map>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/forces.hpp>
#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/supports.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

class ProcessGroup;

/// The problem and mesh types of a dimension.
template <int dim>
struct ContactTypes {
  using Problem = BasicContactProblem<dim>;
  using MeshType = MeshOf<dim>;
};

/// How a contact node touches, in the words of contact.csv, result.json and Python. At a bound
/// of its normal unknown: "at-gap" (u_nu = g: the gap is closed, the node rests on the rigid
/// support behind the foundation or on the obstacle) or "at-minus-gap" (u_nu = -g, the other
/// side of the box constraint). Between its bounds, by the sign of the law's force zeta on it:
/// "in-contact" (zeta > 0: pressed into the foundation, which pushes back), "in-tension"
/// (zeta < 0: an adhesive law holds it) or "separated" (zeta = 0: no force). "tied": held at
/// u_nu = 0 by a bilateral constraint.
enum class ContactState { separated, in_contact, in_tension, at_gap, at_minus_gap, tied };
/// "separated", "in-contact", "in-tension", "at-gap", "at-minus-gap", "tied".
std::string to_string(ContactState state);
/// The state of those words; InputError for any other.
ContactState contact_state_from_string(const std::string& text);
/// The state of a normal unknown `a` with bounds [lo, hi] and the law's force `law_force` on it.
ContactState contact_state(double a, double lo, double hi, double law_force) noexcept;
/// At a bound of its normal unknown or tied: the node's position is the constraint's.
constexpr bool at_a_bound(ContactState s) noexcept {
  return s == ContactState::at_gap || s == ContactState::at_minus_gap || s == ContactState::tied;
}

/// How a node's tangential displacement sits under its friction law: no friction; "stick" at
/// a kink of the law (0 for the shipped laws); "slip"; for the slip-weakening law
/// "slip-weakening" below its slip distance and "slip-kinetic" beyond it.
enum class FrictionState { none, stick, slip, slip_weakening, slip_kinetic };
/// "" (none), "stick", "slip", "slip-weakening", "slip-kinetic".
std::string to_string(FrictionState state);
/// The state of those words; InputError for any other.
FrictionState friction_state_from_string(const std::string& text);

/// One contact node of the solution, with the forces of the certificate
/// (hemivem/certificate.hpp), in a plane (dim = 2) or a solid (dim = 3) body.
template <int dim>
struct BasicContactNode {
  using Point = Eigen::Matrix<double, dim, 1>;
  int vertex = -1;
  /// The index of the node's contact part (BasicContactSolution::contact_parts names it).
  int part = 0;
  /// Two bodies: the vertex of the other body across the contact (u_nu, u_tau and the forces
  /// are then relative: this node's body's less the other's); -1 against a foundation or an
  /// obstacle.
  int partner = -1;
  /// Two bodies: the point of the other body across from the node, as a combination of its
  /// vertices (ContactBoundary::across; `partner` is the one of the largest weight); no vertex
  /// against a foundation or an obstacle.
  Across across;
  Point x = Point::Zero();
  double u_nu = 0.0;       ///< normal displacement a_i
  double law_force = 0.0;  ///< zeta_i in w_i dj(a_i): the force of the contact law
  double reaction = 0.0;   ///< lambda_i: the reaction of the constraint (>= 0 at the upper bound, <= 0 at the lower, 0 off them)
  double weight = 0.0;     ///< w_i, the length (area in 3D) of boundary the node stands for
  Point normal = Point::Zero();  ///< the outward unit normal nu_i
  double gap = 0.0;        ///< g_i, the gap used at the node; NaN where none is (bilateral: u_nu = 0)
  ContactState state = ContactState::separated;
  /// With friction (the part's friction law, or a bilateral constraint): in the plane the
  /// tangential displacement u_tau = u . tau (tau = (-nu_y, nu_x)), the friction force
  /// zeta_tau in w_i dj_tau(u_tau) (the foundation pushes the body by -zeta_tau tau, against
  /// the slip: positive when it resists u_tau > 0) and its state; in a solid, whose friction law
  /// acts on the norm of the tangential displacement, u_tau = |u_t| and friction_force =
  /// |zeta_t| (>= 0). FrictionState::none (everything 0) at a node without friction.
  double u_tau = 0.0;
  double friction_force = 0.0;
  FrictionState friction_state = FrictionState::none;
  /// The same as vectors (x, y[, z]): the tangential displacement u_t = u - u_nu nu and the
  /// friction force zeta_t (the foundation pushes the body by -zeta_t); in the plane u_tau tau
  /// and friction_force tau.
  Point u_tangential = Point::Zero();
  Point friction_vector = Point::Zero();
  /// The contact force zeta_i + lambda_i (a compressive force on the body is positive).
  double force() const noexcept { return law_force + reaction; }
  /// The contact pressure (zeta_i + lambda_i) / w_i.
  double pressure() const noexcept { return force() / weight; }
  /// The force the contact exerts on the node's body: -(zeta_i + lambda_i) nu_i less the friction
  /// force (in the plane zeta_tau tau, tau = (-nu_y, nu_x); on a solid's surface friction_vector).
  Point force_on_body() const {
    if constexpr (dim == 2)
      return -(force() * normal + friction_force * Point(-normal.y(), normal.x()));
    else
      return -(force() * normal + friction_vector);
  }
};
using ContactNode = BasicContactNode<2>;

/// The solution of a contact problem in a plane (dim = 2) or a solid (dim = 3) body.
template <int dim>
struct BasicContactSolution {
  using Point = Eigen::Matrix<double, dim, 1>;
  Eigen::VectorXd u;                    ///< nodal displacements, dim per vertex
  int unknowns = 0;                     ///< free degrees of freedom of the assembled system
  std::vector<BasicContactNode<dim>> contact;  ///< empty without a contact boundary
  /// The names of the contact parts, by BasicContactNode::part (empty without contact).
  std::vector<std::string> contact_parts;
  /// The verdict on the solution: the minimizer's status and certificate, demoted to failed
  /// when the displacement or the energy is not finite; without a contact boundary the status
  /// and certificate of the one linear solve (primal 0, dual its relative residual).
  MinimizerStatus status = MinimizerStatus::failed;
  std::string message;                  ///< why the status is not converged (empty otherwise)
  Certificate certificate;
  /// The minimizer's flag: F may have several critical points (false for the linear solve).
  bool may_be_nonunique = false;
  /// The minimizer's own report (the point a, iterations, evaluations, history, a global
  /// search's critical points), as it returned it; absent without a contact boundary (no
  /// minimizer runs) and on the processes of an engine across processes that do not hold
  /// the results.
  std::optional<MinimizerResult> minimizer;
  /// lambda_min(S - alpha_j W) as measure_uniqueness() reports it (hemivem/uniqueness.hpp):
  /// exactly 0 within round-off; +inf without contact.
  double uniqueness_margin = std::numeric_limits<double>::infinity();
  /// The rigid motions the Dirichlet conditions leave free, in words (a basis); each is held
  /// by the contact alone (hemivem/contact/supports.hpp: a motion that nothing holds is refused
  /// before anything is factorized). Empty when the supports hold the body.
  std::vector<std::string> held_by_contact;
  /// The round-off bound of that margin (0 without contact; NaN where unknown).
  double uniqueness_roundoff = 0.0;
  double energy = 0.0;                  ///< potential energy 1/2 u^T A u - b^T u + sum_i w_i j(u_nu,i) (free dofs)
  /// Reciprocal condition estimate of the matrix the engine factorized (A22 with contact, A
  /// without), where the engine offers one (SparseFactorization::rcond_estimate); NaN
  /// otherwise, and NaN unless asked for (estimate_condition).
  double rcond = std::numeric_limits<double>::quiet_NaN();
  /// Estimate of the 1-norm condition number of the same matrix, independent of the engine
  /// (Condensation::condition_estimate); NaN unless asked for.
  double condition_estimate = std::numeric_limits<double>::quiet_NaN();
  std::map<std::string, double> timings;  ///< seconds: assembly, condensation, minimize, back_substitution, total
  std::vector<std::string> stages;      ///< the stages that ran, in order
  /// The full-space route's Newton iterations, Krylov iterations (summed over the Newton
  /// systems) and preconditioner set-ups, summed over a path's minimizations; absent on the
  /// condensed route.
  std::optional<FullSpaceStatistics> full_space;
  bool converged() const noexcept { return status == MinimizerStatus::converged; }
  /// The minimizer's iterations (0 without a minimizer).
  int iterations() const noexcept { return minimizer ? minimizer->iterations : 0; }
  /// The resultant force of the foundation (or obstacle) on the body: the sum over the
  /// contact nodes of -(zeta_i + lambda_i) nu_i - friction_vector_i.
  /// Zero without contact.
  Point contact_force() const;
  /// The balance of forces (force_balance of u with contact_force()): the applied load, the
  /// reaction of each Dirichlet part, the contact resultant. Zero on the processes of an
  /// engine across processes that do not hold the results.
  BasicForceBalance<Point> forces;
};
using ContactSolution = BasicContactSolution<2>;

/// The friction state of a tangential displacement under its law: stick at a kink of the law
/// (0 for the shipped friction laws; the certificate puts u_tau exactly there), else slip
/// (slip_weakening / slip_kinetic for the slip-weakening law, below / beyond its slip
/// distance).
FrictionState friction_state(const ContactLaw& law, double u_tau);

/// Contact node i of `boundary` at the point m.a of `cond`'s reduced problem, with the forces
/// of m's certificate: its position and geometry, u_nu, the law force and reaction, the state
/// and, with tangential unknowns, u_tau and the friction force and state. `residual` (A u - b
/// on the free dofs) gives the normal force of a bilateral node (NaN without it).
ContactNode contact_node(const Mesh& mesh, const ContactBoundary& boundary, const Condensation& cond,
                         const DofMap& dofs, int i, const MinimizerResult& m, const Eigen::VectorXd* residual);
/// The same for a solid (with friction: the vectors of its one or two tangential slots).
BasicContactNode<3> contact_node(const Mesh3D& mesh, const ContactBoundary& boundary, const Condensation& cond,
                                 const DofMap& dofs, int i, const MinimizerResult& m, const Eigen::VectorXd* residual);

/// The certificate of one linear solve A u = b (no contact): primal 0, dual the relative residual
/// ||A u - b||_inf / max(||b||_inf, ||A u||_inf) (+inf when not finite); `Au` is A u.
Certificate linear_solve_certificate(const Eigen::VectorXd& u, const Eigen::VectorXd& Au, const Eigen::VectorXd& b,
                                     double tolerance);

/// The contact zone: the contact nodes that carry a compressive force (zeta_i + lambda_i > 0).
template <int dim>
struct BasicContactZone {
  using Point = Eigen::Matrix<double, dim, 1>;
  int nodes = 0;                 ///< how many
  double length = 0.0;           ///< the sum of their weights w_i (an area in 3D)
  Point lower = Point::Zero();   ///< the bounding box of their positions (when nodes > 0)
  Point upper = Point::Zero();
};
using ContactZone = BasicContactZone<2>;
template <int dim>
BasicContactZone<dim> contact_zone(const std::vector<BasicContactNode<dim>>& nodes);
template <int dim>
BasicContactZone<dim> contact_zone(const BasicContactSolution<dim>& solution) {
  return contact_zone(solution.contact);
}
/// The resultant of the contact forces of `nodes` on the body (contact_force()).
template <int dim>
Eigen::Matrix<double, dim, 1> contact_resultant(const std::vector<BasicContactNode<dim>>& nodes);
/// The resultant of the forces of foundations and obstacles alone: a contact between two
/// bodies (BasicContactNode::partner) pushes both, and its forces cancel in the sum over the
/// bodies. What the balance of the bodies' forces takes as their contact.
template <int dim>
Eigen::Matrix<double, dim, 1> external_contact_resultant(const std::vector<BasicContactNode<dim>>& nodes);

/// The forces that contact nodes paired with another body put on that body's vertices across
/// from them (BasicContactNode::across): each vertex q_k takes w_k times the opposite of the
/// node's force_on_body(). A support at such a vertex carries them besides its own reaction.
template <int dim>
std::vector<std::pair<int, Eigen::Matrix<double, dim, 1>>> forces_across(const std::vector<BasicContactNode<dim>>& nodes);

/// The balance of the forces on the bodies of `problem` at the displacement `u` with the contact
/// nodes `nodes`: force_balance with the contact of foundations and obstacles
/// (external_contact_resultant) and the forces of pairs of bodies on supported vertices
/// (forces_across).
template <int dim>
BasicForceBalance<Eigen::Matrix<double, dim, 1>> contact_force_balance(const BasicElasticityProblem<dim>& problem,
                                                                       const Eigen::VectorXd& u,
                                                                       const std::vector<BasicContactNode<dim>>& nodes);

/// Demotes a converged `solution` whose displacement or energy is not finite to failed, with
/// the reason as its message (the certificates see the contact unknowns only).
template <int dim>
void require_finite_solution(BasicContactSolution<dim>& solution);

/// The contact boundary of `problem` on the dofs of its assembled system: the nodes of every
/// contact part (contact_parts, make_contact_boundary), normals, weights, gaps (each part's
/// gap, or its obstacle's) and parts; empty without contact edges. InputError for an obstacle
/// whose gaps the box constraint cannot take.
ContactBoundary contact_boundary(const ContactProblem& problem, const DofMap& dofs);


/// What the stages before the condensation (or the posing) make of a problem's contact, from the
/// dof map of its system alone: its contact parts, its contact boundary and the rigid motions its
/// contact alone holds (BasicContactSolution::held_by_contact).
template <int dim>
struct ContactSetUp {
  std::vector<BasicContactPart<dim>> parts;
  ContactBoundary boundary;
  std::vector<std::string> held_by_contact;
};

/// The contact set-up of `problem` on the free dofs of `dofs` (make_dof_map of its Dirichlet
/// conditions), as BasicContactSolver::prepare() makes it, with its InputErrors (every
/// displacement prescribed, the parts, the boundary, a rigid motion that nothing holds), each
/// marked with the part of the problem it is about. A cost of the surface (and of the supports'
/// check), not of the system.
template <int dim>
ContactSetUp<dim> contact_set_up(const BasicContactProblem<dim>& problem, const DofMap& dofs);

/// InputError naming the part for a contact part without a law (both routes pose one per
/// coordinate).
template <int dim>
void require_contact_laws(const std::vector<BasicContactPart<dim>>& parts);

/// The node blocks of the free unknowns of `dofs` (KrylovHints::block_size): `dim` when they come
/// node by node, every component of each node free (in the rotated unknowns too: a contact node's
/// frame acts on its own components); 1 otherwise.
int node_block_size(const DofMap& dofs, int dim);

/// The solve of one contact problem in named stages, as deal.II's step-41 tutorial lays out
/// its obstacle problem: run() calls
///
///   assemble -> condense -> (for each minimizer) minimize -> back_substitute -> post_process
///
/// and, without a contact boundary, assemble -> linear_solve -> post_process (one linear solve,
/// shared by every minimizer). ContactSolution::stages names the stages that ran (the
/// post-processing is not a stage there) and ContactSolution::timings gives their seconds.
/// The free functions solve_contact() below are thin wrappers around it.
///
/// The problem, the options and a system given by the caller must outlive the solver; the
/// factorization is consumed (the condensation keeps A22 for back-substitution). InputError
/// for a problem that cannot be set up (e.g. a body that is not held) and NumericalError when
/// the factorization fails; a minimizer that does not converge is reported in the solution,
/// not thrown.
///
/// A solution is never reported as converged unless every displacement is finite and the
/// certificate holds: a minimizer result that is converged but whose back-substituted
/// displacement is not finite becomes `failed`. Without contact the certificate's dual residual
/// is ||A u - b||_inf / max(||b||_inf, ||A u||_inf) of the one linear solve (primal 0), and the
/// solve is converged when it is finite and below options.tolerance.
///
/// With an engine across processes (hemivem/process_group.hpp: holds_results() false on all
/// but one process) every process runs the same solver on the same problem: assembly runs on
/// every process, the engine's calls are collective, the minimizer and the results (u, contact,
/// energy, margin, the reduced problem) belong to the process holding the results. Elsewhere
/// the solution carries the stages, the timings and the status (shared), nothing else. The
/// work done there alone (the minimizer, the post-processing) runs through
/// ProcessGroup::run_where_results_are: an exception thrown there is thrown on every process
/// (the others get the same kind of error with a message saying so).
///
/// The problem (and a system given to the constructor) are kept by reference and must outlive
/// the solver; the minimizer options are copied.
template <int dim>
class BasicContactSolver {
 public:
  using Problem = typename ContactTypes<dim>::Problem;
  using Solution = BasicContactSolution<dim>;
  using Node = BasicContactNode<dim>;
  /// The "assembly" stage assembles problem.elasticity.
  BasicContactSolver(const Problem& problem, std::unique_ptr<SparseFactorization> factorization,
                     const MinimizerOptions& options);
  /// On a system the caller assembled from problem.elasticity (assemble()), e.g. to condense
  /// one assembly with several engines: no "assembly" stage, and "total" excludes it.
  BasicContactSolver(const Problem& problem, const LinearSystem& system,
                     std::unique_ptr<SparseFactorization> factorization, const MinimizerOptions& options);
  /// The full-space route (hemivem/contact/full_space.hpp): the contact problem minimized over
  /// all free unknowns with `krylov` for its Newton systems, nothing factorized or condensed.
  /// Its stages are "assembly", "posing" (the contact coordinates, laws and bounds) and
  /// "full_space" (the semismooth Newton iteration); run() takes the one minimizer "ssn" (the
  /// route's Newton iteration is ssn's in the whole space; another is an InputError naming it).
  /// The uniqueness margin is not measured (NaN): a solution is called unique only where every
  /// law is convex. There is no reduced problem: export_reduced() leaves its target untouched.
  BasicContactSolver(const Problem& problem, std::unique_ptr<KrylovSolver> krylov, const MinimizerOptions& options);
  BasicContactSolver(const BasicContactSolver&) = delete;
  BasicContactSolver& operator=(const BasicContactSolver&) = delete;
  ~BasicContactSolver();

  /// Adds the solution's condition_estimate (two more solves with five right-hand sides) and rcond.
  BasicContactSolver& estimate_condition(bool on = true) noexcept;
  /// `reduced`, when not null, receives a copy of the reduced problem (for export).
  BasicContactSolver& export_reduced(ReducedProblem* reduced) noexcept;
  /// The minimizer starts from the point of the reduced problem that the full nodal
  /// displacement `u` stands for (Condensation::reduced_point; a warm start, e.g. the previous
  /// step's solution interpolated onto a refined mesh); empty: from zero. `u` must outlive run().
  BasicContactSolver& start_from(const Eigen::VectorXd* u) noexcept;

  /// Runs the stages once: one solution per minimizer, in order (the stages before the
  /// minimizer run once; their timings are repeated in every solution).
  std::vector<Solution> run(std::span<const NonsmoothMinimizer* const> minimizers);

  /// The stages before the minimizer, for a caller that minimizes on its own (a loading path,
  /// hemivem/path/path.hpp): assembly (unless the system was given), the contact parts, the
  /// contact boundary, the supports and, when the boundary has a node, the condensation (on the
  /// full-space route the posing), with the errors of run(). Called instead of run(), once; the
  /// problem's own checks for a static solve (e.g. a friction bound that needs a path) are
  /// run()'s. Then system(), parts(), boundary(), condensation() and prepared() give what the
  /// stages made.
  void prepare();
  /// On the full-space route after prepare(): minimize_full_space (hemivem/contact/full_space.hpp)
  /// of the posed problem from *x (the rotated free unknowns; empty: 0), with the laws, weights
  /// and bounds of `coordinates` and the coordinates' `origin` (a step of a loading path), the
  /// solver's Krylov engine and options, and the body's rigid motions as the preconditioner's
  /// near-null space. InternalError on the condensed route or before prepare().
  MinimizerResult minimize_posed(const ReducedProblem& coordinates, const Eigen::VectorXd& origin, Eigen::VectorXd* x,
                                 FullSpaceStatistics* statistics = nullptr);
  /// True on the full-space route (a Krylov engine).
  bool full_space() const noexcept { return krylov_ != nullptr; }
  /// The assembled system. After run() on the full-space route (a Krylov engine) the solver's
  /// own assembled matrix of one body is given up once the problem is posed (its rotated copy,
  /// condensation()->rotated_matrix(), stands for it): system().A is then empty.
  const LinearSystem& system() const { return *system_; }
  const std::vector<BasicContactPart<dim>>& parts() const noexcept { return parts_; }
  const ContactBoundary& boundary() const noexcept { return boundary_; }
  /// Null when the boundary has no node.
  Condensation* condensation() noexcept { return condensation_.get(); }
  /// What every solution shares: unknowns, contact parts, held_by_contact, the uniqueness
  /// margin, stages and timings of the stages that ran.
  const Solution& prepared() const noexcept { return common_; }

 private:
  using Clock = std::chrono::steady_clock;

  void check_arguments(std::span<const NonsmoothMinimizer* const> minimizers) const;
  // the stages
  void assemble();
  void set_up_contact();
  Eigen::MatrixXd linear_solve();
  void condense();
  void pose();
  void solve_full_space(Solution& solution);
  Eigen::MatrixXd near_null_space() const;
  int node_block_size() const;
  void minimize(const NonsmoothMinimizer& minimizer, Solution& solution) const;
  void back_substitute(Solution& solution) const;
  void post_process(Solution& solution) const;
  // the post-processing of the linear solve
  void post_process_linear(const Eigen::MatrixXd& X);
  void agree_on_status(Solution& solution) const;
  double seconds() const;

  const Problem& problem_;
  MinimizerOptions options_;  // a copy: the caller's may be a temporary
  std::unique_ptr<SparseFactorization> factorization_;  // until condense() hands it on
  const ProcessGroup* processes_ = nullptr;             // the engine's processes
  std::optional<LinearSystem> assembled_;
  bool matrix_posed_ = false;  ///< the full-space route gave assembled_'s matrix up (one body)
  const LinearSystem* system_ = nullptr;
  std::vector<BasicContactPart<dim>> parts_;
  ContactBoundary boundary_;
  std::unique_ptr<Condensation> condensation_;
  std::unique_ptr<KrylovSolver> krylov_;  // the full-space route's engine (null: condensed route)
  std::optional<KrylovHints> hints_;      // its preconditioner's, once posed
  bool estimate_condition_ = false;
  ReducedProblem* reduced_ = nullptr;
  const Eigen::VectorXd* start_u_ = nullptr;
  bool ran_ = false;
  Clock::time_point start_;
  Solution common_;  // what every solution shares: the stages before the minimizer
};
using ContactSolver = BasicContactSolver<2>;

/// Solves `problem` with the given engines: ContactSolver(problem, factorization, options)
/// run with one minimizer. When `reduced` is not null it receives a copy of the reduced
/// problem (for export).
ContactSolution solve_contact(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                              const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                              ReducedProblem* reduced = nullptr);

/// The same for several minimizers sharing one assembly and one condensation: one solution
/// per minimizer, in order. Without a contact boundary the single linear solve is shared.
/// `estimate_condition` adds ContactSolution::condition_estimate (two more solves with five right-hand sides) and rcond.
std::vector<ContactSolution> solve_contact(const ContactProblem& problem,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                           bool estimate_condition = false);

/// The same on a system the caller assembled from problem.elasticity (assemble()), e.g. to
/// condense one assembly with several engines; the solutions then have no "assembly" stage
/// and their "total" excludes it.
std::vector<ContactSolution> solve_contact(const ContactProblem& problem, const LinearSystem& system,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced = nullptr,
                                           bool estimate_condition = false);

}  // namespace hemivem
