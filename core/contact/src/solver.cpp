#include <hemivem/support/condition.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

namespace hemivem {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

namespace {

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

double rcond_or_nan(const SparseFactorization& f) {
  const double r = f.rcond_estimate();
  return r >= 0.0 ? r : std::numeric_limits<double>::quiet_NaN();
}

// Demotes a "converged" result whose displacement is not finite (the engines' certificates
// see only the contact unknowns; back-substitution could still overflow).
void require_finite(ContactSolution& sol) {
  if (sol.minimizer.converged() && !sol.u.allFinite()) {
    sol.minimizer.status = MinimizerStatus::failed;
    sol.minimizer.message = "the displacement is not finite (NaN or Inf after back-substitution)";
  }
  if (sol.minimizer.converged() && !std::isfinite(sol.energy)) {
    sol.minimizer.status = MinimizerStatus::failed;
    sol.minimizer.message = "the energy of the solution is not finite";
  }
}

}  // namespace

ContactBoundary contact_boundary(const ContactProblem& problem, const DofMap& dofs) {
  ContactBoundary boundary;
  if (problem.contact_edges.empty()) return boundary;
  boundary = make_contact_boundary(*problem.elasticity.mesh, problem.contact_edges, dofs,
                                   problem.gap ? problem.gap : [](const Vec2&) { return 0.0; },
                                   problem.obstacle ? &*problem.obstacle : nullptr);
  if (problem.obstacle && problem.constraint == ConstraintKind::box)
    for (int i = 0; i < boundary.size(); ++i)
      if (!(std::isfinite(boundary.gaps(i)) && boundary.gaps(i) >= 0.0))
        throw InputError("the box constraint |u_nu| <= g needs a finite gap >= 0, but the obstacle gives " +
                         std::to_string(boundary.gaps(i)) + " at contact node " +
                         std::to_string(boundary.nodes[static_cast<std::size_t>(i)]) +
                         "; set contact.constraint = \"one-sided\" with an obstacle");
  return boundary;
}

ConstraintKind constraint_in_effect(const ContactProblem& problem) {
  return problem.constraint == ConstraintKind::bilateral ? ConstraintKind::bilateral
         : problem.gap || problem.obstacle               ? problem.constraint
                                                         : ConstraintKind::none;
}

std::vector<ContactSolution> solve_contact(const ContactProblem& problem, const LinearSystem& sys,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced,
                                           bool estimate_condition) {
  if (!factorization) throw InputError("solve_contact needs a factorization engine");
  if (minimizers.empty()) throw InputError("solve_contact needs at least one minimizer");
  for (const auto* m : minimizers)
    if (!m) throw InputError("solve_contact: a minimizer is null");
  if (std::string why; !options.is_valid(&why)) throw InputError(why, "MinimizerOptions");
  const auto t_start = Clock::now();
  const bool holds = processes_of(*factorization).holds_results();
  ContactSolution shared;
  auto t = Clock::now();
  shared.unknowns = sys.dofs.num_free();
  const Mesh& mesh = *problem.elasticity.mesh;

  const ContactBoundary boundary = contact_boundary(problem, sys.dofs);

  if (boundary.size() == 0) {
    // No contact node: one linear solve.
    t = Clock::now();
    if (auto r = factorization->factorize(sys.A); !r.ok())
      throw NumericalError("factorization with " + factorization->name() + " failed (" + to_string(r.status) + "): " + r.message);
    Eigen::MatrixXd X;
    if (auto r = factorization->solve(sys.b, &X); !r.ok())
      throw NumericalError("solve with " + factorization->name() + " failed (" + to_string(r.status) + "): " + r.message);
    shared.timings["linear_solve"] = since(t);
    shared.stages.push_back("linear_solve");
    if (estimate_condition) {
      shared.rcond = rcond_or_nan(*factorization);
      auto apply = [&](const Eigen::VectorXd& x) {
        Eigen::MatrixXd y;
        if (!factorization->solve(x, &y).ok() || y.cols() != 1) return Eigen::VectorXd();
        return Eigen::VectorXd(y.col(0));
      };
      shared.condition_estimate = norm1(sys.A) * estimate_norm1_symmetric(static_cast<int>(sys.A.rows()), apply);
    }
    auto& m = shared.minimizer;
    m.may_be_nonunique = false;
    if (holds) {
      const Eigen::VectorXd uf = X.col(0);
      shared.u = sys.dofs.expand(uf);
      const Eigen::VectorXd Au = sys.A * uf;
      shared.energy = 0.5 * uf.dot(Au) - uf.dot(sys.b);
      const double scale = std::max({sys.b.cwiseAbs().maxCoeff(), Au.cwiseAbs().maxCoeff(), force_floor});
      const double residual = (Au - sys.b).cwiseAbs().maxCoeff();
      Certificate& c = m.certificate;
      c.tolerance = options.tolerance;
      c.primal = 0.0;
      c.dual = residual == 0.0 ? 0.0 : (std::isfinite(residual) ? residual / scale : std::numeric_limits<double>::infinity());
      c.length_scale = uf.cwiseAbs().maxCoeff();
      c.force_scale = scale;
      if (uf.allFinite() && c.converged()) {
        m.status = MinimizerStatus::converged;
      } else {
        m.status = MinimizerStatus::failed;
        m.message = uf.allFinite() ? "the linear solve's relative residual is above the tolerance"
                                   : "the linear solve gave a displacement that is not finite";
      }
      require_finite(shared);
    }
    m.status = static_cast<MinimizerStatus>(processes_of(*factorization).share(static_cast<int>(m.status)));
    shared.timings["total"] = since(t_start);
    return std::vector<ContactSolution>(minimizers.size(), shared);
  }

  if (!problem.law) throw InputError("the contact boundary has no contact law");
  const ConstraintKind constraint = constraint_in_effect(problem);
  t = Clock::now();
  const Condensation cond(sys, boundary, std::move(factorization), problem.law, constraint, problem.friction);
  shared.timings["condensation"] = since(t);
  shared.stages.push_back("condensation");
  shared.uniqueness_margin = cond.uniqueness_margin();
  if (estimate_condition) {
    shared.rcond = rcond_or_nan(cond.factorization());
    shared.condition_estimate = cond.condition_estimate();
  }
  const ReducedProblem& rp = cond.reduced();
  if (reduced && holds) *reduced = rp;
  const double before_minimize = since(t_start);

  std::vector<ContactSolution> solutions;
  for (const NonsmoothMinimizer* minimizer : minimizers) {
    ContactSolution sol = shared;
    const auto t_own = Clock::now();
    // The reduced problem is solved where it lives; the others learn the status, or that it threw.
    t = Clock::now();
    int outcome = 0;
    std::exception_ptr failure;
    if (holds) {
      try {
        sol.minimizer = minimizer->minimize(rp, Eigen::VectorXd(), options);
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
    outcome = processes_of(cond.factorization()).share(outcome);
    if (failure) std::rethrow_exception(failure);
    if (outcome < 0) rethrow_elsewhere(outcome);
    sol.timings["minimize"] = since(t);
    sol.stages.push_back("minimize");

    t = Clock::now();
    sol.u = cond.back_substitute(sol.minimizer.a);
    sol.timings["back_substitution"] = since(t);
    sol.stages.push_back("back_substitution");
    if (!holds) {
      // the final status (after the checks below on the process holding the results)
      sol.minimizer.status = static_cast<MinimizerStatus>(processes_of(cond.factorization()).share(0));
      sol.timings["total"] = before_minimize + since(t_own);
      solutions.push_back(std::move(sol));
      continue;
    }

    const MinimizerResult& m = sol.minimizer;
    const bool forces = m.law_force.size() == m.a.size() && m.reaction.size() == m.a.size();
    Eigen::VectorXd uf(sys.dofs.num_free());
    for (int k = 0; k < sys.dofs.num_free(); ++k) uf(k) = sol.u(sys.dofs.free_dofs[static_cast<std::size_t>(k)]);
    const Eigen::VectorXd Au = sys.A * uf;
    for (int i = 0; i < boundary.size(); ++i) {
      ContactNode node;
      node.vertex = boundary.nodes[static_cast<std::size_t>(i)];
      node.x = mesh.vertex(node.vertex);
      node.weight = boundary.weights(i);
      node.normal = boundary.normals[static_cast<std::size_t>(i)];
      node.gap = boundary.gaps(i);
      if (const int k = cond.normal_coordinate(i); k >= 0) {
        node.u_nu = m.a(k);
        node.law_force = forces ? m.law_force(k) : 0.0;
        node.reaction = forces ? m.reaction(k) : 0.0;
        node.state = m.a(k) == rp.upper(k) ? "upper" : (m.a(k) == rp.lower(k) ? "lower" : "free");
      } else {
        // u_nu = 0 imposed: the normal force is what holds the node there, the normal part of
        // the residual A u - b at its dofs (NaN where a dof of the node is prescribed)
        node.state = "bilateral";
        const int dx = sys.dofs.free_index[static_cast<std::size_t>(2 * node.vertex)];
        const int dy = sys.dofs.free_index[static_cast<std::size_t>(2 * node.vertex + 1)];
        node.reaction = dx >= 0 && dy >= 0 ? -Vec2(Au(dx) - sys.b(dx), Au(dy) - sys.b(dy)).dot(node.normal)
                                           : std::numeric_limits<double>::quiet_NaN();
      }
      if (const int k = cond.tangential_coordinate(i); k >= 0) {
        node.u_tau = m.a(k);
        node.friction_force = forces ? m.law_force(k) + m.reaction(k) : 0.0;
        node.friction_state = friction_state(rp.law_of(k), node.u_tau);
      }
      sol.contact.push_back(node);
    }
    const Eigen::VectorXd& a = m.a;
    // the potential energy of the discrete problem (F(a) differs from it by a constant)
    sol.energy = 0.5 * uf.dot(Au) - uf.dot(sys.b);
    for (Eigen::Index i = 0; i < a.size(); ++i) sol.energy += rp.w(i) * rp.law_of(i).value(a(i));
    require_finite(sol);
    processes_of(cond.factorization()).share(static_cast<int>(sol.minimizer.status));
    sol.timings["total"] = before_minimize + since(t_own);
    solutions.push_back(std::move(sol));
  }
  return solutions;
}

std::vector<ContactSolution> solve_contact(const ContactProblem& problem,
                                           std::unique_ptr<SparseFactorization> factorization,
                                           std::span<const NonsmoothMinimizer* const> minimizers,
                                           const MinimizerOptions& options, ReducedProblem* reduced,
                                           bool estimate_condition) {
  const auto t = Clock::now();
  const LinearSystem sys = assemble(problem.elasticity);
  const double seconds = since(t);
  auto solutions = solve_contact(problem, sys, std::move(factorization), minimizers, options, reduced, estimate_condition);
  for (auto& s : solutions) {
    s.timings["assembly"] = seconds;
    s.timings["total"] += seconds;
    s.stages.insert(s.stages.begin(), "assembly");
  }
  return solutions;
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

Vec2 ContactSolution::contact_force() const {
  Vec2 total = Vec2::Zero();
  for (const auto& n : contact) total -= n.force() * n.normal + n.friction_force * Vec2(-n.normal.y(), n.normal.x());
  return total;
}

ContactZone contact_zone(const ContactSolution& solution) {
  ContactZone zone;
  for (const auto& n : solution.contact) {
    if (!(n.force() > 0.0)) continue;
    zone.lower = zone.nodes == 0 ? n.x : zone.lower.cwiseMin(n.x);
    zone.upper = zone.nodes == 0 ? n.x : zone.upper.cwiseMax(n.x);
    ++zone.nodes;
    zone.length += n.weight;
  }
  return zone;
}

}  // namespace hemivem
