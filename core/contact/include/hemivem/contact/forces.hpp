// The balance of forces on the body at a solution: the applied load, the reaction of each
// Dirichlet part, the resultant of the contact forces, and how closely they sum to zero.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The resultants (Fx, Fy) of the forces on the body. Equilibrium of the discrete problem
/// says applied + the reactions + contact = 0 (the stiffness K annihilates translations).
struct ForceBalance {
  /// One Dirichlet part's reaction: the force the support exerts on the body.
  struct Reaction {
    std::string name;
    Vec2 force = Vec2::Zero();
  };
  Vec2 applied = Vec2::Zero();      ///< the sum of the load vector f: tractions, pressures and body force
  std::vector<Reaction> reactions;  ///< per Dirichlet condition, in the problem's order
  Vec2 contact = Vec2::Zero();      ///< the resultant of the contact forces (ContactSolution::contact_force)
  /// applied + the reactions + contact.
  Vec2 sum() const;
  /// |sum()| / |applied|; for a body without load (driven by prescribed displacements, gaps or
  /// an obstacle) |sum()| over the largest |reaction| or |contact|; 0 when every force is 0.
  double residual() const;
};

/// The balance of forces of the nodal displacement `u` of `problem` (2 per vertex) with the
/// contact resultant `contact`: applied = sum of f, and the reaction of each Dirichlet
/// condition the sum of r = K u - f over the dofs it prescribes (a dof that several conditions
/// prescribe counts for the last one, whose value it takes). A condition without a name is
/// called "dirichlet part i" (i from 0). Costs the load vector and the element matrices of
/// the elements at prescribed dofs.
ForceBalance force_balance(const ElasticityProblem& problem, const Eigen::VectorXd& u, const Vec2& contact);

}  // namespace hemivem
