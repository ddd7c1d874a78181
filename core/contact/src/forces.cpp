#include <hemivem/contact/forces.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include "forces_of_vertices.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hemivem {

namespace detail {

template <int dim>
BasicForceBalance<PointOf<dim>> force_balance_of_vertices(const BasicElasticityProblem<dim>& problem,
                                                          const Eigen::VectorXd& u, const PointOf<dim>& contact,
                                                          const std::vector<std::pair<int, PointOf<dim>>>& at_vertices,
                                                          const std::vector<int>& vertices) {
  using Point = PointOf<dim>;
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const MeshOf<dim>& mesh = *problem.mesh;
  // every vector below holds the dofs of `vertices` alone, in their order: a process's own
  // vertices cost it their dofs, not the whole mesh's
  const Eigen::VectorXd f = assemble_load_at(mesh, problem.body_force, problem.tractions, vertices);
  const auto position = [&](int v) {
    const auto it = std::lower_bound(vertices.begin(), vertices.end(), v);
    return it != vertices.end() && *it == v ? static_cast<int>(it - vertices.begin()) : -1;
  };
  // the condition each dof takes its value from: the last one that prescribes it
  std::vector<int> owner(static_cast<std::size_t>(f.size()), -1);
  for (std::size_t k = 0; k < problem.dirichlet.size(); ++k) {
    const BasicDirichletCondition<dim>& bc = problem.dirichlet[k];
    for (int v : bc.held_vertices(mesh))
      if (const int p = position(v); p >= 0)
        for (int c = 0; c < dim; ++c)
          if (bc.fix[static_cast<std::size_t>(c)]) owner[static_cast<std::size_t>(dim * p + c)] = static_cast<int>(k);
  }
  std::vector<char> prescribed(owner.size());
  for (std::size_t d = 0; d < owner.size(); ++d) prescribed[d] = owner[d] >= 0;
  const Eigen::VectorXd r =
      apply_stiffness_at(mesh, problem.materials, problem.stabilization, u, vertices, prescribed) - f;
  BasicForceBalance<Point> balance;
  balance.contact = contact;
  for (std::size_t k = 0; k < problem.dirichlet.size(); ++k)
    balance.reactions.push_back({problem.dirichlet[k].name.empty() ? "dirichlet part " + std::to_string(k)
                                                                   : problem.dirichlet[k].name,
                                 Point::Zero()});
  for (Eigen::Index d = 0; d < f.size(); ++d) {
    balance.applied(d % dim) += f(d);
    if (const int k = owner[static_cast<std::size_t>(d)]; k >= 0)
      balance.reactions[static_cast<std::size_t>(k)].force(d % dim) += r(d);
  }
  // K u = f + reactions + the other forces at the prescribed dofs
  for (const auto& [v, force] : at_vertices)
    if (const int p = position(v); p >= 0)
      for (int c = 0; c < dim; ++c)
        if (const int k = owner[static_cast<std::size_t>(dim * p + c)]; k >= 0)
          balance.reactions[static_cast<std::size_t>(k)].force(c) -= force(c);
  return balance;
}

template ForceBalance force_balance_of_vertices(const ElasticityProblem&, const Eigen::VectorXd&, const Vec2&,
                                                const std::vector<std::pair<int, Vec2>>&, const std::vector<int>&);
template ForceBalance3D force_balance_of_vertices(const ElasticityProblem3D&, const Eigen::VectorXd&, const Vec3&,
                                                  const std::vector<std::pair<int, Vec3>>&, const std::vector<int>&);

}  // namespace detail

namespace {

template <int dim>
BasicForceBalance<PointOf<dim>> balance_of(const BasicElasticityProblem<dim>& problem, const Eigen::VectorXd& u,
                                           const PointOf<dim>& contact,
                                           const std::vector<std::pair<int, PointOf<dim>>>& at_vertices) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  std::vector<int> vertices(static_cast<std::size_t>(problem.mesh->num_vertices()));
  std::iota(vertices.begin(), vertices.end(), 0);
  return detail::force_balance_of_vertices<dim>(problem, u, contact, at_vertices, vertices);
}

}  // namespace

ForceBalance force_balance(const ElasticityProblem& problem, const Eigen::VectorXd& u, const Vec2& contact,
                           const std::vector<std::pair<int, Vec2>>& at_vertices) {
  return balance_of<2>(problem, u, contact, at_vertices);
}

ForceBalance3D force_balance(const ElasticityProblem3D& problem, const Eigen::VectorXd& u, const Vec3& contact,
                             const std::vector<std::pair<int, Vec3>>& at_vertices) {
  return balance_of<3>(problem, u, contact, at_vertices);
}

}  // namespace hemivem
