#include <hemivem/contact/forces.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>

namespace hemivem {

ForceBalance force_balance(const ElasticityProblem& problem, const Eigen::VectorXd& u, const Vec2& contact) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const Mesh& mesh = *problem.mesh;
  const Eigen::VectorXd f = assemble_load(mesh, problem.body_force, problem.tractions);
  // the condition each dof takes its value from: the last one that prescribes it
  std::vector<int> owner(static_cast<std::size_t>(f.size()), -1);
  for (std::size_t k = 0; k < problem.dirichlet.size(); ++k) {
    const DirichletCondition& bc = problem.dirichlet[k];
    for (int id : bc.edges)
      for (int v : {mesh.edge(id).v0, mesh.edge(id).v1})
        for (int c = 0; c < 2; ++c)
          if (bc.fix[static_cast<std::size_t>(c)]) owner[static_cast<std::size_t>(2 * v + c)] = static_cast<int>(k);
  }
  std::vector<char> prescribed(owner.size());
  for (std::size_t d = 0; d < owner.size(); ++d) prescribed[d] = owner[d] >= 0;
  const Eigen::VectorXd r = apply_stiffness(mesh, problem.materials, problem.stabilization, u, prescribed) - f;
  ForceBalance balance;
  balance.contact = contact;
  for (std::size_t k = 0; k < problem.dirichlet.size(); ++k)
    balance.reactions.push_back({problem.dirichlet[k].name.empty() ? "dirichlet part " + std::to_string(k)
                                                                   : problem.dirichlet[k].name,
                                 Vec2::Zero()});
  for (Eigen::Index d = 0; d < f.size(); ++d) {
    balance.applied(d % 2) += f(d);
    if (const int k = owner[static_cast<std::size_t>(d)]; k >= 0)
      balance.reactions[static_cast<std::size_t>(k)].force(d % 2) += r(d);
  }
  return balance;
}

}  // namespace hemivem
