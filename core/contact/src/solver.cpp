#include <hemivem/support/condition.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/contact/contact3d.hpp>

#include "solver.templates.hpp"
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace hemivem {


ContactBoundary contact_boundary(const ContactProblem& problem, const DofMap& dofs) {
  const std::vector<ContactPart> parts = contact_parts(problem);
  if (parts.empty()) return ContactBoundary{};
  const ContactBoundary boundary = make_contact_boundary(*problem.elasticity.mesh, parts, dofs);
  std::vector<std::string> names;
  for (const ContactPart& part : parts) names.push_back(part.name);
  require_nodes_in_every_part(boundary, names);
  for (int i = 0; i < boundary.size(); ++i) {
    const ContactPart& part = parts[static_cast<std::size_t>(boundary.part_of(i))];
    if (part.obstacle && part.constraint == ConstraintKind::box)
      require_box_gap(boundary.gaps(i), boundary.nodes[static_cast<std::size_t>(i)], parts.size() > 1 ? part.name : "");
  }
  return boundary;
}


// ---- the kernels of each dimension ---------------------------------------------------------

namespace detail {

template <>
struct Kernels<2> {
  static void check(const ContactProblem& problem) {
    for (const ContactPart& part : contact_parts(problem))
      if (part.friction_bound)
        throw InputError("a friction bound that depends on the normal contact (Coulomb's law, or a bound h(u_nu)) "
                         "depends on the solution and is found by a fixed point along a loading path: solve it with "
                         "the path solver (hemivem/path/path.hpp)");
  }
  static LinearSystem assemble(const ContactProblem& problem) { return hemivem::assemble(problem.elasticity); }
  static std::vector<ContactPart> parts(const ContactProblem& problem) { return contact_parts(problem); }
  static ContactBoundary boundary(const ContactProblem& problem, const std::vector<ContactPart>&, const DofMap& dofs) {
    return contact_boundary(problem, dofs);
  }
  static std::vector<std::string> held_by_contact(const ContactProblem& problem, const DofMap& dofs,
                                                  const ContactBoundary& boundary, const std::vector<ContactPart>& parts) {
    return find_supports(*problem.elasticity.mesh, dofs, boundary, parts, problem.elasticity.piece_bodies)
        .held_by_contact;
  }
  static ForceBalance balance(const ContactProblem& problem, const Eigen::VectorXd& u, const Vec2& contact) {
    return force_balance(problem.elasticity, u, contact);
  }
};

}  // namespace detail

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

ContactNode contact_node(const Mesh& mesh, const ContactBoundary& boundary, const Condensation& cond,
                         const DofMap& dofs, int i, const MinimizerResult& m, const Eigen::VectorXd* residual) {
  const ReducedProblem& rp = cond.reduced();
  const bool forces = m.law_force.size() == m.a.size() && m.reaction.size() == m.a.size();
  ContactNode node;
  node.vertex = boundary.nodes[static_cast<std::size_t>(i)];
  node.part = boundary.part_of(i);
  node.partner = boundary.partner_of(i);
  if (!boundary.across.empty()) node.across = boundary.across[static_cast<std::size_t>(i)];
  node.x = mesh.vertex(node.vertex);
  node.weight = boundary.weights(i);
  node.normal = boundary.normals[static_cast<std::size_t>(i)];
  // no gap is used where u_nu = 0 is imposed (bilateral)
  node.gap = cond.normal_coordinate(i) >= 0 ? boundary.gaps(i) : std::numeric_limits<double>::quiet_NaN();
  if (const int k = cond.normal_coordinate(i); k >= 0) {
    node.u_nu = m.a(k) + cond.origin()(k);
    node.law_force = forces ? m.law_force(k) : 0.0;
    node.reaction = forces ? m.reaction(k) : 0.0;
    node.state = contact_state(m.a(k), rp.lower(k), rp.upper(k), node.law_force);
  } else {
    // u_nu = 0 imposed: the normal force is what holds the node there, the normal part of
    // the residual A u - b at its dofs (NaN where a dof of the node is prescribed or the
    // residual is not given)
    node.state = ContactState::tied;
    const int dx = dofs.free_index(2 * node.vertex);
    const int dy = dofs.free_index(2 * node.vertex + 1);
    node.reaction = residual && dx >= 0 && dy >= 0 ? -Vec2((*residual)(dx), (*residual)(dy)).dot(node.normal)
                                                   : std::numeric_limits<double>::quiet_NaN();
  }
  if (const int k = cond.tangential_coordinate(i); k >= 0) {
    node.u_tau = m.a(k);
    node.friction_force = forces ? m.law_force(k) + m.reaction(k) : 0.0;
    node.friction_state = friction_state(rp.law_of(k), node.u_tau);
    const Vec2 tau(-node.normal.y(), node.normal.x());
    node.u_tangential = node.u_tau * tau;
    node.friction_vector = node.friction_force * tau;
  }
  return node;
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

template class BasicContactSolver<2>;
template void require_finite_solution<2>(BasicContactSolution<2>&);
template ContactSetUp<2> contact_set_up<2>(const ContactProblem&, const DofMap&);
template void require_contact_laws<2>(const std::vector<ContactPart>&);

int node_block_size(const DofMap& dofs, int dim) {
  if (dim < 1 || dofs.num_dofs() % dim != 0) return 1;
  // the free dofs come in blocks of a vertex's components where each vertex has all its
  // components prescribed or none
  const std::vector<int>& held = dofs.prescribed_dofs();
  for (std::size_t k = 0; k < held.size(); k += static_cast<std::size_t>(dim)) {
    const auto last = k + static_cast<std::size_t>(dim) - 1;
    if (held[k] % dim != 0 || last >= held.size() || held[last] != held[k] + dim - 1) return 1;
  }
  return dim;
}

FrictionState friction_state(const ContactLaw& law, double u_tau) {
  const std::vector<double> kinks = law.kinks();
  if (std::binary_search(kinks.begin(), kinks.end(), u_tau)) return FrictionState::stick;
  if (law.name() == "slip-weakening") {
    const std::vector<double> b = law.breakpoints();  // -slip, 0, slip
    return std::abs(u_tau) < b.back() ? FrictionState::slip_weakening : FrictionState::slip_kinetic;
  }
  return FrictionState::slip;
}

namespace {

template <class Enum, std::size_t n>
Enum enum_from_string(const std::string& text, const std::array<const char*, n>& words, const char* what) {
  for (std::size_t k = 0; k < n; ++k)
    if (text == words[k]) return static_cast<Enum>(k);
  std::string list;
  for (const char* w : words) list += std::string(list.empty() ? "" : ", ") + "'" + w + "'";
  throw InputError("unknown " + std::string(what) + " '" + text + "' (expected one of: " + list + ")");
}

constexpr std::array<const char*, 6> contact_state_words{"separated", "in-contact", "in-tension",
                                                         "at-gap",    "at-minus-gap", "tied"};
constexpr std::array<const char*, 5> friction_state_words{"", "stick", "slip", "slip-weakening", "slip-kinetic"};

}  // namespace

std::string to_string(ContactState state) { return contact_state_words[static_cast<std::size_t>(state)]; }

ContactState contact_state_from_string(const std::string& text) {
  return enum_from_string<ContactState>(text, contact_state_words, "contact state");
}

ContactState contact_state(double a, double lo, double hi, double law_force) noexcept {
  if (a == hi) return ContactState::at_gap;
  if (a == lo) return ContactState::at_minus_gap;
  return law_force > 0.0 ? ContactState::in_contact : (law_force < 0.0 ? ContactState::in_tension : ContactState::separated);
}

std::string to_string(FrictionState state) { return friction_state_words[static_cast<std::size_t>(state)]; }

FrictionState friction_state_from_string(const std::string& text) {
  return enum_from_string<FrictionState>(text, friction_state_words, "friction state");
}

template <int dim>
Eigen::Matrix<double, dim, 1> contact_resultant(const std::vector<BasicContactNode<dim>>& nodes) {
  using Point = Eigen::Matrix<double, dim, 1>;
  Point total = Point::Zero();
  for (const auto& n : nodes) total += n.force_on_body();
  return total;
}

template <int dim>
Eigen::Matrix<double, dim, 1> external_contact_resultant(const std::vector<BasicContactNode<dim>>& nodes) {
  using Point = Eigen::Matrix<double, dim, 1>;
  Point total = Point::Zero();
  for (const auto& n : nodes)
    if (n.partner < 0) total += n.force_on_body();
  return total;
}

template <int dim>
typename BasicContactSolution<dim>::Point BasicContactSolution<dim>::contact_force() const {
  return contact_resultant(contact);
}

template <int dim>
BasicContactZone<dim> contact_zone(const std::vector<BasicContactNode<dim>>& nodes) {
  BasicContactZone<dim> zone;
  for (const auto& n : nodes) {
    if (!(n.force() > 0.0)) continue;
    zone.lower = zone.nodes == 0 ? n.x : zone.lower.cwiseMin(n.x);
    zone.upper = zone.nodes == 0 ? n.x : zone.upper.cwiseMax(n.x);
    ++zone.nodes;
    zone.length += n.weight;
  }
  return zone;
}

template struct BasicContactSolution<2>;
template struct BasicContactSolution<3>;
template Vec2 contact_resultant(const std::vector<BasicContactNode<2>>&);
template Vec3 contact_resultant(const std::vector<BasicContactNode<3>>&);
template <int dim>
std::vector<std::pair<int, Eigen::Matrix<double, dim, 1>>> forces_across(const std::vector<BasicContactNode<dim>>& nodes) {
  std::vector<std::pair<int, Eigen::Matrix<double, dim, 1>>> out;
  for (const auto& n : nodes)
    for (int k = 0; k < n.across.size(); ++k)
      out.emplace_back(n.across.vertex[static_cast<std::size_t>(k)],
                       -n.across.weight[static_cast<std::size_t>(k)] * n.force_on_body());
  return out;
}

template <int dim>
BasicForceBalance<Eigen::Matrix<double, dim, 1>> contact_force_balance(const BasicElasticityProblem<dim>& problem,
                                                                       const Eigen::VectorXd& u,
                                                                       const std::vector<BasicContactNode<dim>>& nodes) {
  auto balance = force_balance(problem, u, external_contact_resultant(nodes), forces_across(nodes));
  for (const auto& n : nodes)
    if (n.across.size() > 0) balance.internal = std::max(balance.internal, n.force_on_body().norm());
  return balance;
}

template std::vector<std::pair<int, Vec2>> forces_across(const std::vector<BasicContactNode<2>>&);
template std::vector<std::pair<int, Vec3>> forces_across(const std::vector<BasicContactNode<3>>&);
template ForceBalance contact_force_balance(const ElasticityProblem&, const Eigen::VectorXd&,
                                            const std::vector<BasicContactNode<2>>&);
template ForceBalance3D contact_force_balance(const ElasticityProblem3D&, const Eigen::VectorXd&,
                                              const std::vector<BasicContactNode<3>>&);
template Vec2 external_contact_resultant(const std::vector<BasicContactNode<2>>&);
template Vec3 external_contact_resultant(const std::vector<BasicContactNode<3>>&);
template BasicContactZone<2> contact_zone(const std::vector<BasicContactNode<2>>&);
template BasicContactZone<3> contact_zone(const std::vector<BasicContactNode<3>>&);

}  // namespace hemivem
