#include <hemivem/support/condition.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace hemivem {

namespace {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

double rcond_or_nan(const SparseFactorization& f) {
  const double r = f.rcond_estimate();
  return r >= 0.0 ? r : std::numeric_limits<double>::quiet_NaN();
}

// Demotes a "converged" solution whose displacement is not finite (the engines' certificates
// see only the contact unknowns; back-substitution could still overflow).
void require_finite(ContactSolution& sol) {
  if (sol.converged() && !sol.u.allFinite()) {
    sol.status = MinimizerStatus::failed;
    sol.message = "the displacement is not finite (NaN or Inf after back-substitution)";
  }
  if (sol.converged() && !std::isfinite(sol.energy)) {
    sol.status = MinimizerStatus::failed;
    sol.message = "the energy of the solution is not finite";
  }
}

void require_ok(const FactorizationResult& r, const SparseFactorization& f, const std::string& what) {
  if (!r.ok())
    throw NumericalError(what + " with " + f.name() + " failed (" + to_string(r.status) + "): " + r.message);
}

}  // namespace

ContactBoundary contact_boundary(const ContactProblem& problem, const DofMap& dofs) {
  const std::vector<ContactPart> parts = contact_parts(problem);
  if (parts.empty()) return ContactBoundary{};
  const ContactBoundary boundary = make_contact_boundary(*problem.elasticity.mesh, parts, dofs);
  for (int i = 0; i < boundary.size(); ++i) {
    const ContactPart& part = parts[static_cast<std::size_t>(boundary.part_of(i))];
    if (part.obstacle && part.constraint == ConstraintKind::box)
      require_box_gap(boundary.gaps(i), boundary.nodes[static_cast<std::size_t>(i)], parts.size() > 1 ? part.name : "");
  }
  return boundary;
}

ConstraintKind constraint_in_effect(const ContactProblem& problem) {
  return problem.constraint == ConstraintKind::bilateral ? ConstraintKind::bilateral
         : problem.gap || problem.obstacle               ? problem.constraint
                                                         : ConstraintKind::none;
}

// ---- ContactSolver ---------------------------------------------------------------------

ContactSolver::ContactSolver(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                             const MinimizerOptions& options)
    : problem_(problem), options_(options), factorization_(std::move(factorization)) {
  if (factorization_) processes_ = &processes_of(*factorization_);
}

ContactSolver::ContactSolver(const ContactProblem& problem, const LinearSystem& system,
                             std::unique_ptr<SparseFactorization> factorization, const MinimizerOptions& options)
    : ContactSolver(problem, std::move(factorization), options) {
  system_ = &system;
}

ContactSolver::~ContactSolver() = default;

ContactSolver& ContactSolver::estimate_condition(bool on) noexcept {
  estimate_condition_ = on;
  return *this;
}

ContactSolver& ContactSolver::export_reduced(ReducedProblem* reduced) noexcept {
  reduced_ = reduced;
  return *this;
}

ContactSolver& ContactSolver::start_from(const Eigen::VectorXd* u) noexcept {
  start_u_ = u;
  return *this;
}

double ContactSolver::seconds() const { return since(start_); }

std::vector<ContactSolution> ContactSolver::run(std::span<const NonsmoothMinimizer* const> minimizers) {
  if (ran_) throw InternalError("ContactSolver::run is called once");
  ran_ = true;
  if (problem_.friction_bound)
    throw InputError("a friction bound that depends on the normal contact (Coulomb's law, or a bound h(u_nu)) "
                     "depends on the solution and is found by a fixed point along a loading path: solve it with "
                     "the path solver (hemivem/path/path.hpp)");
  start_ = Clock::now();
  if (!system_) assemble();
  check_arguments(minimizers);
  common_.unknowns = system_->dofs.num_free();
  if (common_.unknowns == 0)
    throw InputError("the Dirichlet conditions prescribe every displacement of the mesh: there is nothing to solve");
  parts_ = contact_parts(problem_);
  for (const ContactPart& part : parts_) common_.contact_parts.push_back(part.name);
  boundary_ = contact_boundary(problem_, system_->dofs);
  common_.held_by_contact = find_supports(*problem_.elasticity.mesh, system_->dofs, boundary_, parts_).held_by_contact;
  if (boundary_.size() == 0) {
    const Eigen::MatrixXd X = linear_solve();
    common_.may_be_nonunique = false;
    processes_->run_where_results_are([&] { post_process_linear(X); });
    agree_on_status(common_);
    common_.timings["total"] = seconds();
    return std::vector<ContactSolution>(minimizers.size(), common_);
  }
  condense();
  const double before_minimize = seconds();
  std::vector<ContactSolution> solutions;
  for (const NonsmoothMinimizer* minimizer : minimizers) {
    ContactSolution solution = common_;
    const auto t = Clock::now();
    minimize(*minimizer, solution);
    back_substitute(solution);
    processes_->run_where_results_are([&] { post_process(solution); });
    agree_on_status(solution);
    solution.timings["total"] = before_minimize + since(t);
    solutions.push_back(std::move(solution));
  }
  return solutions;
}

void ContactSolver::check_arguments(std::span<const NonsmoothMinimizer* const> minimizers) const {
  if (!factorization_) throw InputError("solve_contact needs a factorization engine");
  if (minimizers.empty()) throw InputError("solve_contact needs at least one minimizer");
  for (const auto* m : minimizers)
    if (!m) throw InputError("solve_contact: a minimizer is null");
  if (std::string why; !options_.is_valid(&why)) throw InputError(why, "MinimizerOptions");
}

void ContactSolver::assemble() {
  const auto t = Clock::now();
  assembled_ = hemivem::assemble(problem_.elasticity);
  system_ = &*assembled_;
  common_.timings["assembly"] = since(t);
  common_.stages.push_back("assembly");
}

// Without a contact node: A u = b, one factorization and one solve. X on the process holding
// the results.
Eigen::MatrixXd ContactSolver::linear_solve() {
  const auto t = Clock::now();
  const LinearSystem& sys = *system_;
  require_ok(factorization_->factorize(sys.A), *factorization_, "factorization");
  Eigen::MatrixXd X;
  require_ok(factorization_->solve(sys.b, &X), *factorization_, "solve");
  common_.timings["linear_solve"] = since(t);
  common_.stages.push_back("linear_solve");
  if (estimate_condition_) {
    common_.rcond = rcond_or_nan(*factorization_);
    common_.condition_estimate = factorized_condition_estimate(sys.A, *factorization_);
  }
  return X;
}

Certificate linear_solve_certificate(const Eigen::VectorXd& u, const Eigen::VectorXd& Au, const Eigen::VectorXd& b,
                                     double tolerance) {
  const double scale = std::max({b.cwiseAbs().maxCoeff(), Au.cwiseAbs().maxCoeff(), force_floor});
  const double residual = (Au - b).cwiseAbs().maxCoeff();
  Certificate c;
  c.tolerance = tolerance;
  c.primal = 0.0;
  c.dual = residual == 0.0 ? 0.0 : (std::isfinite(residual) ? residual / scale : std::numeric_limits<double>::infinity());
  c.length_scale = u.cwiseAbs().maxCoeff();
  c.force_scale = scale;
  return c;
}

// The displacement, the energy and the certificate of the linear solve: the relative
// residual ||A u - b|| / max(||b||, ||A u||) is its dual part.
void ContactSolver::post_process_linear(const Eigen::MatrixXd& X) {
  ContactSolution& s = common_;
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
  s.forces = force_balance(problem_.elasticity, s.u, Vec2::Zero());
  require_finite(s);
}

// The static condensation onto the contact unknowns (the reduced problem), its uniqueness
// margin and, when asked, the conditioning of the interior block.
void ContactSolver::condense() {
  for (const ContactPart& part : parts_)
    if (!part.law)
      throw InputError(parts_.size() == 1 ? std::string("the contact boundary has no contact law")
                                          : "contact part '" + part.name + "' has no contact law");
  const auto t = Clock::now();
  condensation_ = std::make_unique<Condensation>(*system_, boundary_, std::move(factorization_),
                                                 part_conditions(parts_), !common_.held_by_contact.empty());
  common_.timings["condensation"] = since(t);
  common_.stages.push_back("condensation");
  if (estimate_condition_) {
    common_.rcond = rcond_or_nan(condensation_->factorization());
    common_.condition_estimate = condensation_->condition_estimate();
    // S carries the condensation's round-off: the margin's bound grows with kappa(A22)
    processes_->run_where_results_are([&] { condensation_->widen_uniqueness_roundoff(common_.condition_estimate); });
  }
  common_.uniqueness_margin = condensation_->uniqueness_margin();
  common_.uniqueness_roundoff = condensation_->reduced().uniqueness_roundoff;
  processes_->run_where_results_are([&] {
    if (reduced_) *reduced_ = condensation_->reduced();
  });
}

// The reduced problem is solved where it lives.
void ContactSolver::minimize(const NonsmoothMinimizer& minimizer, ContactSolution& solution) const {
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
  solution.timings["minimize"] = since(t);
  solution.stages.push_back("minimize");
}

void ContactSolver::back_substitute(ContactSolution& solution) const {
  const auto t = Clock::now();
  solution.u = condensation_->back_substitute(solution.minimizer ? solution.minimizer->a : Eigen::VectorXd());
  solution.timings["back_substitution"] = since(t);
  solution.stages.push_back("back_substitution");
}

// The contact table, the potential energy and the balance of forces of the solution.
void ContactSolver::post_process(ContactSolution& solution) const {
  const LinearSystem& sys = *system_;
  const MinimizerResult& m = *solution.minimizer;
  Eigen::VectorXd uf(sys.dofs.num_free());
  for (int k = 0; k < sys.dofs.num_free(); ++k) uf(k) = solution.u(sys.dofs.free_dofs[static_cast<std::size_t>(k)]);
  const Eigen::VectorXd Au = sys.A * uf;
  const Eigen::VectorXd residual = Au - sys.b;
  for (int i = 0; i < boundary_.size(); ++i) solution.contact.push_back(contact_node(i, m, residual));
  // the potential energy of the discrete problem (F(a) differs from it by a constant)
  const ReducedProblem& rp = condensation_->reduced();
  solution.energy = 0.5 * uf.dot(Au) - uf.dot(sys.b);
  for (Eigen::Index i = 0; i < m.a.size(); ++i) solution.energy += rp.w(i) * rp.law_of(i).value(m.a(i));
  solution.forces = force_balance(problem_.elasticity, solution.u, solution.contact_force());
  require_finite(solution);
}

ContactNode ContactSolver::contact_node(int i, const MinimizerResult& m, const Eigen::VectorXd& residual) const {
  return hemivem::contact_node(*problem_.elasticity.mesh, boundary_, *condensation_, system_->dofs, i, m, &residual);
}

ContactNode contact_node(const Mesh& mesh, const ContactBoundary& boundary, const Condensation& cond,
                         const DofMap& dofs, int i, const MinimizerResult& m, const Eigen::VectorXd* residual) {
  const ReducedProblem& rp = cond.reduced();
  const bool forces = m.law_force.size() == m.a.size() && m.reaction.size() == m.a.size();
  ContactNode node;
  node.vertex = boundary.nodes[static_cast<std::size_t>(i)];
  node.part = boundary.part_of(i);
  node.x = mesh.vertex(node.vertex);
  node.weight = boundary.weights(i);
  node.normal = boundary.normals[static_cast<std::size_t>(i)];
  // no gap is used where u_nu = 0 is imposed (bilateral)
  node.gap = cond.normal_coordinate(i) >= 0 ? boundary.gaps(i) : std::numeric_limits<double>::quiet_NaN();
  if (const int k = cond.normal_coordinate(i); k >= 0) {
    node.u_nu = m.a(k) + cond.origin()(k);
    node.law_force = forces ? m.law_force(k) : 0.0;
    node.reaction = forces ? m.reaction(k) : 0.0;
    node.state = m.a(k) == rp.upper(k) ? "upper" : (m.a(k) == rp.lower(k) ? "lower" : "free");
  } else {
    // u_nu = 0 imposed: the normal force is what holds the node there, the normal part of
    // the residual A u - b at its dofs (NaN where a dof of the node is prescribed or the
    // residual is not given)
    node.state = "bilateral";
    const int dx = dofs.free_index[static_cast<std::size_t>(2 * node.vertex)];
    const int dy = dofs.free_index[static_cast<std::size_t>(2 * node.vertex + 1)];
    node.reaction = residual && dx >= 0 && dy >= 0 ? -Vec2((*residual)(dx), (*residual)(dy)).dot(node.normal)
                                                   : std::numeric_limits<double>::quiet_NaN();
  }
  if (const int k = cond.tangential_coordinate(i); k >= 0) {
    node.u_tau = m.a(k);
    node.friction_force = forces ? m.law_force(k) + m.reaction(k) : 0.0;
    node.friction_state = friction_state(rp.law_of(k), node.u_tau);
  }
  return node;
}

// Collective: every process takes the final status of the process holding the results.
void ContactSolver::agree_on_status(ContactSolution& solution) const {
  solution.status = static_cast<MinimizerStatus>(processes_->share(static_cast<int>(solution.status)));
}

// ---- the free functions -----------------------------------------------------------------

std::vector<ContactSolution> solve_contact(const ContactProblem& problem, const LinearSystem& system,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced,
                                           bool estimate_condition) {
  ContactSolver solver(problem, system, std::move(factorization), options);
  return solver.estimate_condition(estimate_condition).export_reduced(reduced).run(minimizers);
}

std::vector<ContactSolution> solve_contact(const ContactProblem& problem,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced,
                                           bool estimate_condition) {
  ContactSolver solver(problem, std::move(factorization), options);
  return solver.estimate_condition(estimate_condition).export_reduced(reduced).run(minimizers);
}

ContactSolution solve_contact(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                              const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                              ReducedProblem* reduced) {
  const NonsmoothMinimizer* one[] = {&minimizer};
  return std::move(solve_contact(problem, std::move(factorization), std::span<const NonsmoothMinimizer* const>(one),
                                 options, reduced)
                       .front());
}

std::string friction_state(const ContactLaw& law, double u_tau) {
  const std::vector<double> kinks = law.kinks();
  if (std::binary_search(kinks.begin(), kinks.end(), u_tau)) return "stick";
  if (law.name() == "slip-weakening") {
    const std::vector<double> b = law.breakpoints();  // -slip, 0, slip
    return std::abs(u_tau) < b.back() ? "slip-weakening" : "slip-kinetic";
  }
  return "slip";
}

Vec2 contact_resultant(std::span<const ContactNode> nodes) {
  Vec2 total = Vec2::Zero();
  for (const auto& n : nodes) total -= n.force() * n.normal + n.friction_force * Vec2(-n.normal.y(), n.normal.x());
  return total;
}

Vec2 ContactSolution::contact_force() const { return contact_resultant(contact); }

ContactZone contact_zone(std::span<const ContactNode> nodes) {
  ContactZone zone;
  for (const auto& n : nodes) {
    if (!(n.force() > 0.0)) continue;
    zone.lower = zone.nodes == 0 ? n.x : zone.lower.cwiseMin(n.x);
    zone.upper = zone.nodes == 0 ? n.x : zone.upper.cwiseMax(n.x);
    ++zone.nodes;
    zone.length += n.weight;
  }
  return zone;
}

ContactZone contact_zone(const ContactSolution& solution) { return contact_zone(solution.contact); }

}  // namespace hemivem
