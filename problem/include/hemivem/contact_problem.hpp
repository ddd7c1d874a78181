// A contact problem: the elasticity problem, the contact boundary Gamma_3, its law, gap
// and constraint; and the paper's Example 4.1.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <hemivem/assembly.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/obstacle.hpp>
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

/// Example 4.1 of the paper on a mesh of the unit square, built from the default scene
/// (scenes/paper-example-4.1.toml, see scene.hpp): Gamma_1 = {x = 0} u {x = 1} (clamped),
/// Gamma_2 = top with f2 = (0, -8), Gamma_3 = bottom; E = 65, nu = 0.29 (plane strain),
/// f0 = 0, g = 0.02, the law (4.7) with split (4.8), the box constraint (4.6). Sides of the
/// mesh's bounding box are found with a tolerance of 1e-8 (Sutton's meshes miss them by up
/// to 5e-10).
ContactProblem example_4_1(const Mesh& mesh);

}  // namespace hemivem
