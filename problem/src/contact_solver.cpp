#include <hemivem/contact_solver.hpp>
#include <hemivem/error.hpp>

#include <chrono>
#include <cmath>

namespace hemivem {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

ContactSolution solve_contact(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                              const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                              ReducedProblem* reduced) {
  if (!factorization) throw InputError("solve_contact needs a factorization engine");
  const auto t_start = Clock::now();
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
    const Eigen::VectorXd uf = X.col(0);
    sol.u = sys.dofs.expand(uf);
    sol.energy = 0.5 * uf.dot(sys.A * uf) - uf.dot(sys.b);
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
  if (reduced) *reduced = rp;

  t = Clock::now();
  sol.minimizer = minimizer.minimize(rp, Eigen::VectorXd(), options);
  sol.timings["minimize"] = since(t);
  sol.stages.push_back("minimize");

  t = Clock::now();
  sol.u = cond.back_substitute(sol.minimizer.a);
  sol.timings["back_substitution"] = since(t);
  sol.stages.push_back("back_substitution");

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
