// step-by-step: a contact problem solved with hemivem from another program.
//
// An elastic body Ω = (0,1)² is clamped on its sides x = 0 and x = 1, pushed down by a
// traction f2 = (0, −8) on its top, and rests on a foundation along its bottom Γ3. On Γ3 the
// normal displacement u_ν is limited by the gap, |u_ν| ≤ g = 0.02, and the foundation answers
// with a nonmonotone law: its potential j(u_ν) stiffens, softens, then stiffens again (the
// law (4.7) of Feng, Han and Huang). The displacement u minimises the potential energy
//
//     E(u) = ½ a(u, u) − ℓ(u) + ∫_Γ3 j(u_ν) ds   over  |u_ν| ≤ g on Γ3,
//
// a nonconvex, nonsmooth problem: a hemivariational inequality. This is the paper's
// Example 4.1, written out with the library's pieces instead of a scene file, in four steps:
//
//   1. the problem: mesh, material, boundary conditions, the law on Γ3;
//   2. condensation: the virtual element system A u = b is reduced, through a sparse
//      factorization (here CHOLMOD), to the normal displacements a of the contact nodes,
//      F(a) = ½ aᵀ S a − cᵀ a + Σ_i w_i j(a_i) with |a_i| ≤ g_i;
//   3. the minimizer (here the semismooth Newton engine) finds a critical point of F and a
//      certificate that says how close it is;
//   4. back-substitution gives the displacement everywhere.
//
// The program prints each step and exits with 0 when the certificate says "converged",
// 3 when it does not, and 2 when the problem cannot be set up or an engine fails.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/cholmod_factorization.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/ssn_minimizer.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <utility>
#include <vector>

namespace {

// ---- 1. The problem ------------------------------------------------------------------
struct Problem {
  hemivem::Rectangle domain{0.0, 1.0, 0.0, 1.0};
  int n = 32;
  hemivem::Mesh mesh;
  hemivem::ElasticityProblem elasticity;
  std::shared_ptr<const hemivem::ContactLaw> law;
};

void make_problem(Problem& p) {
  // A mesh of 32 × 32 squares on the unit square. Any polygonal mesh would do: the
  // lowest-order virtual element method needs only the vertices of each element.
  p.mesh = hemivem::make_squares(p.n, p.domain);

  // Linear elasticity: E = 65, ν = 0.29 in plane strain, no body force. The sides of the
  // rectangle select boundary edges: Γ1 (clamped, zero displacement) is left and right,
  // Γ2 (the traction) is the top.
  p.elasticity.mesh = &p.mesh;
  p.elasticity.materials = hemivem::MaterialTable(hemivem::Material{65.0, 0.29}, hemivem::PlaneModel::strain);
  const std::vector<int> clamped = hemivem::select_boundary_edges(
      p.mesh, std::vector<hemivem::Segment>{hemivem::rectangle_side(p.domain, "left"),
                                            hemivem::rectangle_side(p.domain, "right")});
  p.elasticity.dirichlet.push_back({clamped, {}, {true, true}});
  const std::vector<int> top =
      hemivem::select_boundary_edges(p.mesh, std::vector<hemivem::Segment>{hemivem::rectangle_side(p.domain, "top")});
  p.elasticity.tractions.push_back({top, [](const hemivem::Vec2&) { return hemivem::Vec2(0.0, -8.0); }, {}});

  // The contact law is data: j on the pieces between the breakpoints 0, 0.01 and 0.02,
  // as polynomials in r = u_ν (lowest degree first),
  //   j(r) = 0,  30 r²,  0.8 r − 10 r² − 0.004,  30 r² − 0.8 r + 0.012,
  // given with a convex part j1 so that j = j1 − j2 with j2 convex too (the split (4.8),
  // here j2 = 10 r²). The constructor checks continuity and the convexity of both parts.
  p.law = std::make_shared<hemivem::PiecewisePolynomialLaw>(hemivem::PiecewisePolynomialLaw::from_potential(
      "paper (4.7)", {0.0, 0.01, 0.02},
      {{0.0}, {0.0, 0.0, 30.0}, {-0.004, 0.8, -10.0}, {0.012, -0.8, 30.0}},
      {{0.0, 0.0, 10.0}, {0.0, 0.0, 40.0}, {-0.004, 0.8}, {0.012, -0.8, 40.0}}));
}

// Γ3 is the bottom. Each of its nodes i (the clamped corners excluded) gets an outward
// normal, a weight w_i (half the length of its two Γ3 edges: the nodal quadrature of
// ∫ j(u_ν) ds) and a gap g_i.
hemivem::ContactBoundary contact_boundary(const Problem& p, const hemivem::LinearSystem& system) {
  const std::vector<int> bottom =
      hemivem::select_boundary_edges(p.mesh, std::vector<hemivem::Segment>{hemivem::rectangle_side(p.domain, "bottom")});
  return hemivem::make_contact_boundary(p.mesh, bottom, system.dofs, [](const hemivem::Vec2&) { return 0.02; });
}

// ---- 3. The minimizer ----------------------------------------------------------------
// Semismooth Newton from a = 0. Whatever the engine does internally, the result is
// "converged" only when the certificate is below the tolerance: the primal
// residual ‖dist(a, C)‖∞ / ℓ and the dual residual ‖Sa − c + ζ + λ‖∞ / f (ζ the law force,
// λ the reaction of the constraint, ℓ and f the length and force scales: docs/reference/certificate.md).
hemivem::MinimizerResult minimize(const hemivem::ReducedProblem& reduced) {
  const hemivem::SsnMinimizer ssn;
  hemivem::MinimizerOptions options;
  options.tolerance = 1e-10;
  const hemivem::MinimizerResult result = ssn.minimize(reduced, Eigen::VectorXd(), options);
  std::printf("  minimizer     %s: %s after %d iterations%s\n", ssn.name().c_str(),
              hemivem::to_string(result.status).c_str(), result.iterations,
              result.may_be_nonunique ? " (F may have several critical points)" : "");
  std::printf("  certificate   primal %.3e, dual %.3e (tolerance %.1e)\n", result.certificate.primal,
              result.certificate.dual, result.certificate.tolerance);

  // How the contact nodes ended, in the words of `hemivem solve`: at the gap (the upper bound
  // a_i = g_i), or between the bounds by the sign of the law's force (in contact: pressed into
  // the foundation; in tension; separated: no force).
  int count[6] = {};
  for (Eigen::Index i = 0; i < result.a.size(); ++i) {
    const double force = result.law_force.size() == result.a.size() ? result.law_force(i) : 0.0;
    ++count[static_cast<int>(hemivem::contact_state(result.a(i), reduced.lower(i), reduced.upper(i), force))];
  }
  std::printf("  contact       %d nodes: ", static_cast<int>(result.a.size()));
  const std::pair<hemivem::ContactState, const char*> words[] = {
      {hemivem::ContactState::at_gap, "at the gap"},           {hemivem::ContactState::in_contact, "in contact"},
      {hemivem::ContactState::in_tension, "in tension"},       {hemivem::ContactState::separated, "separated"},
      {hemivem::ContactState::at_minus_gap, "at minus the gap"}};
  const char* separator = "";
  for (const auto& [state, text] : words)
    if (const int n = count[static_cast<int>(state)]; n > 0) {
      std::printf("%s%d %s", separator, n, text);
      separator = ", ";
    }
  std::printf("\n");
  std::printf("  F(a)          %.10g\n", result.objective);
  return result;
}

}  // namespace

int main() {
  try {
    Problem problem;
    make_problem(problem);
    // Assembly gives A u = b on the free degrees of freedom (the clamped ones removed).
    const hemivem::LinearSystem system = hemivem::assemble(problem.elasticity);
    const hemivem::ContactBoundary gamma3 = contact_boundary(problem, system);
    std::printf("step-by-step: Example 4.1 on %d x %d squares, engines cholmod + ssn\n", problem.n, problem.n);
    std::printf("  problem       %d vertices, %d elements, %d unknowns, %d contact nodes, law '%s'\n",
                problem.mesh.num_vertices(), problem.mesh.num_elements(), system.dofs.num_free(), gamma3.size(),
                problem.law->name().c_str());

    // ---- 2. Condensation -------------------------------------------------------------
    // Order the unknowns as (normal displacements a of the contact nodes, the rest) and
    // eliminate the rest: S = A11 − A12 A22⁻¹ A21, c = b1 − A12 A22⁻¹ b2. CHOLMOD factorizes
    // A22 once and keeps the factor for step 4. The box constraint is |a_i| ≤ g_i.
    // λ_min(S − α_j W) > 0, with α_j the largest negative curvature of j, means F is
    // strongly convex: the critical point is the unique solution.
    auto cholmod = std::make_unique<hemivem::CholmodFactorization>();
    const hemivem::Condensation condensation(system, gamma3, std::move(cholmod), problem.law,
                                             hemivem::ConstraintKind::box);
    const hemivem::ReducedProblem& reduced = condensation.reduced();
    std::printf("  condensation  S is %d x %d, lambda_min(S - alpha_j W) = %.6g\n", static_cast<int>(reduced.size()),
                static_cast<int>(reduced.size()), condensation.uniqueness_margin());

    const hemivem::MinimizerResult result = minimize(reduced);

    // ---- 4. Back-substitution --------------------------------------------------------
    // The interior follows from a: u2 = A22⁻¹ (b2 − A21 a) with the factor kept in step 2;
    // u holds two components per vertex, the clamped ones included.
    const Eigen::VectorXd u = condensation.back_substitute(result.a);
    double largest = 0.0;
    for (Eigen::Index v = 0; v < u.size() / 2; ++v) largest = std::max(largest, std::hypot(u(2 * v), u(2 * v + 1)));
    std::printf("  displacement  max |u| = %.6g\n", largest);

    return result.converged() ? 0 : 3;
  } catch (const std::exception& e) {
    // hemivem reports bad input (InputError, MeshError) and failed factorizations
    // (NumericalError) as exceptions with a message naming the cause.
    std::fprintf(stderr, "step-by-step: %s\n", e.what());
    return 2;
  }
}
