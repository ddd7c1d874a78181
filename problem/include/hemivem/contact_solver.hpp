// The whole solve of a contact problem (DESIGN §4):
//   assembly -> condensation through a SparseFactorization -> ReducedProblem ->
//   NonsmoothMinimizer -> back-substitution,
// running only the stages the problem needs: without a contact boundary one linear solve;
// without gaps no constraint (ConstraintKind::none).
#pragma once

#include <Eigen/Core>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <hemivem/contact.hpp>
#include <hemivem/contact_problem.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

/// One contact node of the solution.
struct ContactNode {
  int vertex = -1;
  Vec2 x = Vec2::Zero();
  double u_nu = 0.0;        ///< normal displacement a_i
  double multiplier = 0.0;  ///< -xi_i: the nodal reaction of the constraint (> 0 pushing back), ~0 when free
  std::string state;        ///< "free", "upper" (a_i = upper bound) or "lower" (a_i = lower bound)
};

struct ContactSolution {
  Eigen::VectorXd u;                    ///< nodal displacements, 2 per vertex
  int unknowns = 0;                     ///< free degrees of freedom of the assembled system
  std::vector<ContactNode> contact;     ///< empty without a contact boundary
  MinimizerResult minimizer;            ///< status, certificate, iterations ... (status converged for a plain linear solve)
  double uniqueness_margin = std::numeric_limits<double>::infinity();
  double energy = 0.0;                  ///< potential energy 1/2 u^T A u - b^T u + sum_i w_i j(u_nu,i) (free dofs)
  std::map<std::string, double> timings;  ///< seconds: assembly, condensation, minimize, back_substitution, total
  std::vector<std::string> stages;      ///< the stages that ran, in order
  bool converged() const noexcept { return minimizer.converged(); }
};

/// Solves `problem` with the given engines. The factorization is consumed (it keeps A22 for
/// back-substitution). Throws InputError for a problem that cannot be set up (e.g. a body
/// that is not held) and NumericalError when the factorization fails; a minimizer that does
/// not converge is reported in the result, not thrown.
/// When `reduced` is not null it receives a copy of the reduced problem (for export).
///
/// With an engine across processes (factorization->holds_results() false on all but one
/// process) every process calls solve_contact with the same problem: assembly runs on every
/// process, the engine's calls are collective, the minimizer and the results (u, contact,
/// energy, margin, `reduced`) belong to the process holding the results. Elsewhere the
/// solution carries the stages, the timings and the minimizer's status (shared), nothing else.
/// An exception thrown there by the minimizer is thrown on every process (the others get the
/// same type with a message saying so).
ContactSolution solve_contact(const ContactProblem& problem, std::unique_ptr<SparseFactorization> factorization,
                              const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                              ReducedProblem* reduced = nullptr);

}  // namespace hemivem
