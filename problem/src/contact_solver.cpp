#include <hemivem/contact_solver.hpp>
#include <hemivem/error.hpp>

#include <chrono>
#include <cmath>
#include <exception>
#include <string>

namespace hemivem {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// What the process holding the results tells the others after the minimizer: a
// MinimizerStatus (>= 0) or the kind of exception it threw.
constexpr int kThrewInputError = -1;
constexpr int kThrewNumericalError = -2;
constexpr int kThrewOther = -3;

[[noreturn]] void rethrow_elsewhere(int outcome) {
  const std::string what = "the minimizer failed on the process holding the results (it reports the error)";
  if (outcome == kThrewInputError) throw InputError(what);
  if (outcome == kThrewNumericalError) throw NumericalError(what);
  throw Error(what);
}
}  // namespace

ContactSolution solve_contact(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                              const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                              ReducedProblem* reduced) {
  if (!factorization) throw InputError("solve_contact needs a factorization engine");
  const auto t_start = Clock::now();
  const bool holds = factorization->holds_results();
  ContactSolution sol;
  auto t = Clock::now();
  const LinearSystem sys = assemble(problem.elasticity);
  sol.timings["assembly"] = since(t);
  sol.stages.push_back("assembly");
  sol.unknowns = sys.dofs.num_free();
  const Mesh& mesh = *problem.elasticity.mesh;

  ContactBoundary boundary;
  if (!problem.contact_edges.empty()) {
    boundary = make_contact_boundary(mesh, problem.contact_edges, sys.dofs, problem.gap ? problem.gap : [](const Vec2&) { return 0.0; });
  }

  if (boundary.size() == 0) {
    // No contact node: one linear solve.
    t = Clock::now();
    if (auto r = factorization->factorize(sys.A); !r.ok())
      throw NumericalError("factorization with " + factorization->name() + " failed (" + to_string(r.status) + "): " + r.message);
    Eigen::MatrixXd X;
    if (auto r = factorization->solve(sys.b, &X); !r.ok())
      throw NumericalError("solve with " + factorization->name() + " failed (" + to_string(r.status) + "): " + r.message);
    sol.timings["linear_solve"] = since(t);
    sol.stages.push_back("linear_solve");
    if (holds) {
      const Eigen::VectorXd uf = X.col(0);
      sol.u = sys.dofs.expand(uf);
      sol.energy = 0.5 * uf.dot(sys.A * uf) - uf.dot(sys.b);
    }
    sol.minimizer.status = MinimizerStatus::converged;
    sol.minimizer.certificate = {0.0, 0.0};
    sol.minimizer.may_be_nonunique = false;
    sol.timings["total"] = since(t_start);
    return sol;
  }

  if (!problem.law) throw InputError("the contact boundary has no contact law");
  const ConstraintKind constraint = problem.gap ? problem.constraint : ConstraintKind::none;
  t = Clock::now();
  const Condensation cond(sys, boundary, std::move(factorization), problem.law, constraint);
  sol.timings["condensation"] = since(t);
  sol.stages.push_back("condensation");
  sol.uniqueness_margin = cond.uniqueness_margin();
  const ReducedProblem& rp = cond.reduced();
  if (reduced && holds) *reduced = rp;

  // The reduced problem is solved where it lives; the others learn the status, or that it threw.
  t = Clock::now();
  int outcome = 0;
  std::exception_ptr failure;
  if (holds) {
    try {
      sol.minimizer = minimizer.minimize(rp, Eigen::VectorXd(), options);
      outcome = static_cast<int>(sol.minimizer.status);
    } catch (const InputError&) {
      failure = std::current_exception();
      outcome = kThrewInputError;
    } catch (const NumericalError&) {
      failure = std::current_exception();
      outcome = kThrewNumericalError;
    } catch (...) {
      failure = std::current_exception();
      outcome = kThrewOther;
    }
  }
  outcome = cond.factorization().share(outcome);
  if (failure) std::rethrow_exception(failure);
  if (outcome < 0) rethrow_elsewhere(outcome);
  if (!holds) sol.minimizer.status = static_cast<MinimizerStatus>(outcome);
  sol.timings["minimize"] = since(t);
  sol.stages.push_back("minimize");

  t = Clock::now();
  sol.u = cond.back_substitute(sol.minimizer.a);
  sol.timings["back_substitution"] = since(t);
  sol.stages.push_back("back_substitution");
  if (!holds) {
    sol.timings["total"] = since(t_start);
    return sol;
  }

  const Eigen::VectorXd& a = sol.minimizer.a;
  const Eigen::VectorXd xi = rp.least_norm_subgradient(a);
  for (int i = 0; i < boundary.size(); ++i) {
    ContactNode node;
    node.vertex = boundary.nodes[static_cast<std::size_t>(i)];
    node.x = mesh.vertex(node.vertex);
    node.u_nu = a(i);
    node.multiplier = -xi(i);
    const double tol = 1e-12 * std::max(1.0, std::abs(rp.upper(i)));
    node.state = std::abs(a(i) - rp.upper(i)) <= tol ? "upper" : (std::abs(a(i) - rp.lower(i)) <= tol ? "lower" : "free");
    if (node.state == "free") node.multiplier = 0.0;
    sol.contact.push_back(node);
  }
  // the potential energy of the discrete problem (F(a) differs from it by a constant)
  Eigen::VectorXd uf(sys.dofs.num_free());
  for (int k = 0; k < sys.dofs.num_free(); ++k) uf(k) = sol.u(sys.dofs.free_dofs[static_cast<std::size_t>(k)]);
  sol.energy = 0.5 * uf.dot(sys.A * uf) - uf.dot(sys.b);
  for (int i = 0; i < boundary.size(); ++i) sol.energy += rp.w(i) * rp.law->value(a(i));
  sol.timings["total"] = since(t_start);
  return sol;
}

}  // namespace hemivem
