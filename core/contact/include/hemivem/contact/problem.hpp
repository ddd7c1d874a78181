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
  /// Where the normal law's origin lies. false: j acts on u_nu, its origin where the body
  /// starts (the paper's foundation: a layer of thickness g that the body compresses from the
  /// start). true: j acts on the distance to the foundation's or obstacle's surface, u_nu - g_i
  /// (normal compliance or adhesion against an obstacle: zero distance where the body meets
  /// its surface); a node whose gap is infinite (its ray misses the obstacle) never meets it
  /// and has no law. The reduced problem's normal unknowns are then those distances.
  bool law_from_surface = false;
  /// The law of the tangential displacement u_tau on Gamma_3 (friction, docs/friction.md);
  /// null: frictionless (u_tau free). A bilateral constraint without one slides freely.
  std::shared_ptr<const ContactLaw> friction;
};

}  // namespace hemivem
