// The template of the staged contact solver (hemivem/contact/solver.hpp), instantiated for
// the plane in solver.cpp and for the solid in contact3d.cpp, each with its Kernels: the
// pieces of the solve that differ by dimension (assembly, the contact boundary, the supports,
// the balance of forces).
#pragma once

#include <hemivem/contact/solver.hpp>
#include <hemivem/contact/full_space.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/support/condition.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace hemivem {

namespace detail {

/// The pieces of BasicContactSolver<dim> that differ by dimension: a specialization per
/// dimension with static check(problem), assemble(problem), parts(problem),
/// boundary(problem, parts, dofs), held_by_contact(problem, dofs, boundary, parts) and
/// balance(problem, u, contact).
template <int dim>
struct Kernels;


inline double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

inline double rcond_or_nan(const SparseFactorization& f) {
  const double r = f.rcond_estimate();
  return r >= 0.0 ? r : std::numeric_limits<double>::quiet_NaN();
}

template <class Engine>
void require_ok(const FactorizationResult& r, const Engine& f, const std::string& what) {
  if (!r.ok())
    throw NumericalError(what + " with " + f.name() + " failed (" + to_string(r.status) + "): " + r.message);
}


}  // namespace detail

// Demotes a "converged" solution whose displacement is not finite (the engines' certificates
// see only the contact unknowns; back-substitution could still overflow).
template <int dim>
void require_finite_solution(BasicContactSolution<dim>& sol) {
  if (sol.converged() && !sol.u.allFinite()) {
    sol.status = MinimizerStatus::failed;
    sol.message = "the displacement is not finite (NaN or Inf after back-substitution)";
  }
  if (sol.converged() && !std::isfinite(sol.energy)) {
    sol.status = MinimizerStatus::failed;
    sol.message = "the energy of the solution is not finite";
  }
}


// ---- ContactSolver ---------------------------------------------------------------------

template <int dim>
BasicContactSolver<dim>::BasicContactSolver(const Problem& problem, std::unique_ptr<SparseFactorization> factorization,
                                            const MinimizerOptions& options)
    : problem_(problem), options_(options), factorization_(std::move(factorization)) {
  if (factorization_) processes_ = &processes_of(*factorization_);
}

template <int dim>
BasicContactSolver<dim>::BasicContactSolver(const Problem& problem, const LinearSystem& system,
                                            std::unique_ptr<SparseFactorization> factorization,
                                            const MinimizerOptions& options)
    : BasicContactSolver(problem, std::move(factorization), options) {
  system_ = &system;
}

template <int dim>
BasicContactSolver<dim>::BasicContactSolver(const Problem& problem, std::unique_ptr<KrylovSolver> krylov,
                                            const MinimizerOptions& options)
    : problem_(problem), options_(options), krylov_(std::move(krylov)) {
  static const SingleProcess single;
  processes_ = &single;
}

template <int dim>
BasicContactSolver<dim>::~BasicContactSolver() = default;

template <int dim>
BasicContactSolver<dim>& BasicContactSolver<dim>::estimate_condition(bool on) noexcept {
  estimate_condition_ = on;
  return *this;
}

template <int dim>
BasicContactSolver<dim>& BasicContactSolver<dim>::export_reduced(ReducedProblem* reduced) noexcept {
  reduced_ = reduced;
  return *this;
}

template <int dim>
BasicContactSolver<dim>& BasicContactSolver<dim>::start_from(const Eigen::VectorXd* u) noexcept {
  start_u_ = u;
  return *this;
}

template <int dim>
double BasicContactSolver<dim>::seconds() const {
  return detail::since(start_);
}

template <int dim>
auto BasicContactSolver<dim>::run(std::span<const NonsmoothMinimizer* const> minimizers) -> std::vector<Solution> {
  if (ran_) throw InternalError("ContactSolver::run is called once");
  ran_ = true;
  start_ = Clock::now();
  detail::Kernels<dim>::check(problem_);
  const double setup = seconds();
  if (!system_) assemble();
  check_arguments(minimizers);
  const auto ts = Clock::now();
  set_up_contact();
  common_.timings["setup"] = setup + detail::since(ts);
  if (boundary_.size() == 0) {
    const Eigen::MatrixXd X = linear_solve();
    common_.may_be_nonunique = false;
    const auto tp = Clock::now();
    processes_->run_where_results_are([&] { post_process_linear(X); });
    agree_on_status(common_);
    common_.timings["post_process"] = detail::since(tp);
    common_.timings["total"] = seconds();
    return std::vector<Solution>(minimizers.size(), common_);
  }
  if (krylov_) {
    pose();
    Solution solution = common_;
    solve_full_space(solution);
    solution.timings["total"] = seconds();
    return {std::move(solution)};
  }
  condense();
  const double before_minimize = seconds();
  std::vector<Solution> solutions;
  for (const NonsmoothMinimizer* minimizer : minimizers) {
    Solution solution = common_;
    const auto t = Clock::now();
    minimize(*minimizer, solution);
    back_substitute(solution);
    const auto tp = Clock::now();
    processes_->run_where_results_are([&] { post_process(solution); });
    agree_on_status(solution);
    solution.timings["post_process"] = detail::since(tp);
    solution.timings["total"] = before_minimize + detail::since(t);
    solutions.push_back(std::move(solution));
  }
  return solutions;
}

template <int dim>
void BasicContactSolver<dim>::prepare() {
  if (ran_) throw InternalError("ContactSolver::prepare is called once, instead of run");
  ran_ = true;
  if (!factorization_ && !krylov_) throw InputError("solve_contact needs a factorization engine");
  if (!problem_.elasticity.mesh) throw InputError("the elasticity problem has no mesh");
  start_ = Clock::now();
  if (!system_) assemble();
  const auto ts = Clock::now();
  set_up_contact();
  common_.timings["setup"] = detail::since(ts);
  if (boundary_.size() > 0) krylov_ ? pose() : condense();
  common_.timings["total"] = seconds();
}

template <int dim>
MinimizerResult BasicContactSolver<dim>::minimize_posed(const ReducedProblem& coordinates, const Eigen::VectorXd& origin,
                                                        Eigen::VectorXd* x, FullSpaceStatistics* statistics) {
  if (!krylov_ || !condensation_) throw InternalError("minimize_posed needs the full-space route, posed");
  if (!hints_) hints_.emplace(near_null_space(), node_block_size());
  return hemivem::minimize_full_space(*condensation_, coordinates, origin, *krylov_, *hints_, options_, x, statistics);
}

// ---- the stages before the condensation, on the dof map alone ---------------------------------

template <int dim>
ContactSetUp<dim> contact_set_up(const BasicContactProblem<dim>& problem, const DofMap& dofs) {
  if (dofs.num_free() == 0)
    throw InputError("the Dirichlet conditions prescribe every displacement of the mesh: there is nothing to solve")
        .mark_about(ProblemPart::supports);
  ContactSetUp<dim> s;
  s.parts = about(ProblemPart::contact, [&] { return detail::Kernels<dim>::parts(problem); });
  s.boundary = about(ProblemPart::contact, [&] { return detail::Kernels<dim>::boundary(problem, s.parts, dofs); });
  s.held_by_contact = about(ProblemPart::supports, [&] {
    return detail::Kernels<dim>::held_by_contact(problem, dofs, s.boundary, s.parts);
  });
  return s;
}

template <int dim>
void require_contact_laws(const std::vector<BasicContactPart<dim>>& parts) {
  for (const auto& part : parts)
    if (!part.law)
      throw InputError(parts.size() == 1 ? std::string("the contact boundary has no contact law")
                                         : "contact part '" + part.name + "' has no contact law");
}

// The unknowns, the contact parts, the contact boundary and the rigid motions the contact holds.
template <int dim>
void BasicContactSolver<dim>::set_up_contact() {
  common_.unknowns = system_->dofs.num_free();
  ContactSetUp<dim> contact = contact_set_up(problem_, system_->dofs);
  parts_ = std::move(contact.parts);
  for (const auto& part : parts_) common_.contact_parts.push_back(part.name);
  boundary_ = std::move(contact.boundary);
  common_.held_by_contact = std::move(contact.held_by_contact);
}

template <int dim>
void BasicContactSolver<dim>::check_arguments(std::span<const NonsmoothMinimizer* const> minimizers) const {
  if (!factorization_ && !krylov_) throw InputError("solve_contact needs a factorization engine");
  if (minimizers.empty()) throw InputError("solve_contact needs at least one minimizer");
  for (const auto* m : minimizers)
    if (!m) throw InputError("solve_contact: a minimizer is null");
  if (krylov_ && (minimizers.size() != 1 || minimizers.front()->name() != "ssn"))
    throw InputError("the full-space route (linear engine " + krylov_->name() +
                     ") runs its own semismooth Newton iteration, the minimizer ssn: minimizer " +
                     minimizers.front()->name() + (minimizers.size() > 1 ? " and others need" : " needs") +
                     " a linear engine that factorizes");
  if (std::string why; !options_.is_valid(&why)) throw InputError(why, "MinimizerOptions");
}

template <int dim>
void BasicContactSolver<dim>::assemble() {
  const auto t = Clock::now();
  assembled_ = detail::Kernels<dim>::assemble(problem_);
  system_ = &*assembled_;
  common_.timings["assembly"] = detail::since(t);
  common_.stages.push_back("assembly");
}

// Without a contact node: A u = b, one factorization and one solve (on the full-space route
// one Krylov solve to the certificate's tolerance). X on the process holding the results.
template <int dim>
Eigen::MatrixXd BasicContactSolver<dim>::linear_solve() {
  const auto t = Clock::now();
  const LinearSystem& sys = *system_;
  if (krylov_) {
    detail::require_ok(krylov_->compute(sys.A, KrylovHints(near_null_space(), node_block_size())), *krylov_,
                       "preconditioner");
    Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.b.size());
    // the certificate's residual is in the max norm: ||r||_inf / ||b||_inf <= sqrt(n) ||r||_2 / ||b||_2
    const double rtol = std::max(1e-14, options_.tolerance / std::sqrt(static_cast<double>(std::max<Eigen::Index>(1, x.size()))));
    const KrylovSolveResult r = krylov_->solve(sys.b, &x, rtol, 10000);
    if (!r.ok())
      throw NumericalError("solve with " + krylov_->name() + " failed (" + to_string(r.status) + "): " + r.message);
    common_.timings["linear_solve"] = detail::since(t);
    common_.stages.push_back("linear_solve");
    return x;
  }
  detail::require_ok(factorization_->factorize(sys.A), *factorization_, "factorization");
  Eigen::MatrixXd X;
  detail::require_ok(factorization_->solve(sys.b, &X), *factorization_, "solve");
  common_.timings["linear_solve"] = detail::since(t);
  common_.stages.push_back("linear_solve");
  if (estimate_condition_) {
    common_.rcond = detail::rcond_or_nan(*factorization_);
    common_.condition_estimate = factorized_condition_estimate(sys.A, *factorization_);
  }
  return X;
}

// The displacement, the energy and the certificate of the linear solve: the relative
// residual ||A u - b|| / max(||b||, ||A u||) is its dual part.
template <int dim>
void BasicContactSolver<dim>::post_process_linear(const Eigen::MatrixXd& X) {
  Solution& s = common_;
  const LinearSystem& sys = *system_;
  const Eigen::VectorXd uf = X.col(0);
  s.u = sys.dofs.expand(uf);
  const Eigen::VectorXd Au = sys.A * uf;
  s.energy = 0.5 * uf.dot(Au) - uf.dot(sys.b);
  s.certificate = linear_solve_certificate(uf, Au, sys.b, options_.tolerance);
  if (uf.allFinite() && s.certificate.converged()) {
    s.status = MinimizerStatus::converged;
  } else {
    s.status = MinimizerStatus::failed;
    s.message = uf.allFinite() ? "the linear solve's relative residual is above the tolerance"
                               : "the linear solve gave a displacement that is not finite";
  }
  s.forces = detail::Kernels<dim>::balance(problem_, s.u, BasicContactSolution<dim>::Point::Zero());
  require_finite_solution(s);
}

// The static condensation onto the contact unknowns (the reduced problem), its uniqueness
// margin and, when asked, the conditioning of the interior block.
template <int dim>
void BasicContactSolver<dim>::condense() {
  require_contact_laws(parts_);
  const auto t = Clock::now();
  condensation_ = about(ProblemPart::contact, [&] {
    return std::make_unique<Condensation>(*system_, boundary_, std::move(factorization_), part_conditions(parts_),
                                          !common_.held_by_contact.empty());
  });
  common_.timings["condensation"] = detail::since(t);
  common_.stages.push_back("condensation");
  if (estimate_condition_) {
    const auto tc = Clock::now();
    common_.rcond = detail::rcond_or_nan(condensation_->factorization());
    common_.condition_estimate = condensation_->condition_estimate();
    common_.timings["condition"] = detail::since(tc);
    // S carries the condensation's round-off: the margin's bound grows with kappa(A22)
    processes_->run_where_results_are([&] { condensation_->widen_uniqueness_roundoff(common_.condition_estimate); });
  }
  common_.uniqueness_margin = condensation_->uniqueness_margin();
  common_.uniqueness_roundoff = condensation_->reduced().uniqueness_roundoff;
  processes_->run_where_results_are([&] {
    if (reduced_) *reduced_ = condensation_->reduced();
  });
}

// The full-space route's posing: the coordinates, laws and bounds of the reduced problem and
// the rotated system, nothing factorized.
template <int dim>
void BasicContactSolver<dim>::pose() {
  require_contact_laws(parts_);
  const auto t = Clock::now();
  condensation_ = about(ProblemPart::contact, [&] {
    return std::make_unique<Condensation>(*system_, boundary_, part_conditions(parts_), Condensation::PoseOnly{});
  });
  if (!common_.held_by_contact.empty()) {
    // a semi-coercive problem: its free motions, for the existence proof and the Newton systems
    const Eigen::MatrixXd nodal =
        BasicRigidMotions<dim>(*problem_.elasticity.mesh, system_->dofs, problem_.elasticity.piece_bodies).nodal();
    Eigen::MatrixXd rotated(system_->dofs.num_free(), nodal.cols());
    for (Eigen::Index k = 0; k < nodal.cols(); ++k) rotated.col(k) = condensation_->rotated_free(nodal.col(k));
    condensation_->set_free_motions(std::move(rotated));
  }
  // one body's assembled matrix, the solver's own, is the posed rotated one: given up
  if (assembled_ && !condensation_->joins_bodies()) {
    SparseMatrix().swap(assembled_->A);
    matrix_posed_ = true;
  }
  common_.timings["posing"] = detail::since(t);
  common_.stages.push_back("posing");
  common_.uniqueness_margin = std::numeric_limits<double>::quiet_NaN();
  common_.uniqueness_roundoff = std::numeric_limits<double>::quiet_NaN();
}

// The rigid motions of the whole mesh (translations, rotations about its centroid) in the free
// unknowns (rotated once the problem is posed): the near-null space of the elasticity operator
// for the preconditioner.
template <int dim>
Eigen::MatrixXd BasicContactSolver<dim>::near_null_space() const {
  const int nv = problem_.elasticity.mesh->num_vertices();
  const MeshRigidMotions<dim> motions(*problem_.elasticity.mesh);
  Eigen::MatrixXd N(system_->dofs.num_free(), motions.count);
  for (int k = 0; k < motions.count; ++k) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dim) * nv);
    for (int v = 0; v < nv; ++v) u.segment<dim>(dim * v) = motions.at(k, v);
    // prescribed components are not unknowns: the free ones, in the contact nodes' frames once posed
    if (condensation_) {
      N.col(k) = condensation_->rotated_free(u);
    } else {
      N.col(k) = system_->dofs.free_part(u);
    }
  }
  return N;
}

// dim when the free unknowns come node by node (hemivem::node_block_size).
template <int dim>
int BasicContactSolver<dim>::node_block_size() const {
  return hemivem::node_block_size(system_->dofs, dim);
}

template <int dim>
void BasicContactSolver<dim>::solve_full_space(Solution& solution) {
  const auto t = Clock::now();
  Eigen::VectorXd x;
  if (start_u_ && start_u_->size() > 0) x = condensation_->rotated_free(*start_u_);
  FullSpaceStatistics stats;
  MinimizerResult m = minimize_posed(condensation_->reduced(), condensation_->origin(), &x, &stats);
  solution.status = m.status;
  solution.message = m.message;
  solution.certificate = m.certificate;
  solution.may_be_nonunique = m.may_be_nonunique;
  solution.u = condensation_->displacement_of(std::move(x));
  solution.minimizer = std::move(m);
  solution.timings["full_space"] = detail::since(t);
  solution.timings["preconditioner"] = stats.preconditioner_seconds;
  solution.timings["krylov"] = stats.krylov_seconds;
  solution.full_space = stats;
  solution.stages.push_back("full_space");
  const auto tp = Clock::now();
  post_process(solution);
  agree_on_status(solution);
  solution.timings["post_process"] = detail::since(tp);
}

// The reduced problem is solved where it lives.
template <int dim>
void BasicContactSolver<dim>::minimize(const NonsmoothMinimizer& minimizer, Solution& solution) const {
  const auto t = Clock::now();
  processes_->run_where_results_are([&] {
    const Eigen::VectorXd start =
        start_u_ && start_u_->size() > 0 ? condensation_->reduced_point(*start_u_) : Eigen::VectorXd();
    MinimizerResult m = minimizer.minimize(condensation_->reduced(), start, options_);
    solution.status = m.status;
    solution.message = m.message;
    solution.certificate = m.certificate;
    solution.may_be_nonunique = m.may_be_nonunique;
    solution.minimizer = std::move(m);
  });
  solution.timings["minimize"] = detail::since(t);
  solution.stages.push_back("minimize");
}

template <int dim>
void BasicContactSolver<dim>::back_substitute(Solution& solution) const {
  const auto t = Clock::now();
  solution.u = condensation_->back_substitute(solution.minimizer ? solution.minimizer->a : Eigen::VectorXd());
  solution.timings["back_substitution"] = detail::since(t);
  solution.stages.push_back("back_substitution");
}

// The contact table, the potential energy and the balance of forces of the solution.
template <int dim>
void BasicContactSolver<dim>::post_process(Solution& solution) const {
  const LinearSystem& sys = *system_;
  const MinimizerResult& m = *solution.minimizer;
  const Eigen::VectorXd uf = sys.dofs.free_part(solution.u);
  const Eigen::VectorXd Au = matrix_posed_ ? condensation_->unrotated_product(uf) : Eigen::VectorXd(sys.A * uf);
  const Eigen::VectorXd residual = Au - sys.b;
  for (int i = 0; i < boundary_.size(); ++i)
    solution.contact.push_back(
        hemivem::contact_node(*problem_.elasticity.mesh, boundary_, *condensation_, system_->dofs, i, m, &residual));
  // the potential energy of the discrete problem (F(a) differs from it by a constant)
  const ReducedProblem& rp = condensation_->reduced();
  solution.energy = 0.5 * uf.dot(Au) - uf.dot(sys.b);
  solution.energy = rp.law_energy(m.a, solution.energy);
  solution.forces = contact_force_balance<dim>(problem_.elasticity, solution.u, solution.contact);
  require_finite_solution(solution);
}

// Collective: every process takes the final status of the process holding the results.
template <int dim>
void BasicContactSolver<dim>::agree_on_status(Solution& solution) const {
  solution.status = static_cast<MinimizerStatus>(processes_->share(static_cast<int>(solution.status)));
}

}  // namespace hemivem
