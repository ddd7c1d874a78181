// A contact problem: the elasticity problem, the contact boundary Gamma_3, its law, gap
// and constraint; and the paper's Example 4.1.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <hemivem/vem/assembly.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/contact/obstacle.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

struct ContactProblem {
  ElasticityProblem elasticity;        ///< mesh, materials, loads and Gamma_1
  std::vector<int> contact_edges;      ///< Gamma_3 (boundary edge ids)
  std::function<double(const Vec2&)> gap;  ///< g >= 0 at a point of Gamma_3
  /// A rigid obstacle instead of `gap`: each node's gap is Obstacle::gap along its normal
  /// (negative where the node starts inside, +inf where its ray misses; one-sided or no
  /// constraint only).
  std::optional<Obstacle> obstacle;
  std::shared_ptr<const ContactLaw> law;
  ConstraintKind constraint = ConstraintKind::box;
  /// The law of the tangential displacement u_tau on Gamma_3 (friction, docs/friction.md);
  /// null: frictionless (u_tau free). A bilateral constraint without one slides freely.
  std::shared_ptr<const ContactLaw> friction;
};

}  // namespace hemivem
