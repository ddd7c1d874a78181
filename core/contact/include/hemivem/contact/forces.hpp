// The balance of forces on the body at a solution: the applied load, the reaction of each
// Dirichlet part, the resultant of the contact forces, and how closely they sum to zero.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <string>
#include <vector>

#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The resultants ((Fx, Fy) in the plane, (Fx, Fy, Fz) in space) of the forces on the body.
/// Equilibrium of the discrete problem says applied + the reactions + contact = 0 (the
/// stiffness K annihilates translations).
template <class Vector>
struct BasicForceBalance {
  /// One Dirichlet part's reaction: the force the support exerts on the body.
  struct Reaction {
    std::string name;
    Vector force = Vector::Zero();
  };
  Vector applied = Vector::Zero();  ///< the sum of the load vector f: tractions, pressures and body force
  std::vector<Reaction> reactions;  ///< per Dirichlet condition, in the problem's order
  Vector contact = Vector::Zero();  ///< the resultant of the contact forces (the solution's contact_force)
  /// The largest force of two bodies on each other at one pair (internal to the bodies
  /// together, absent from the sum): the scale of the residual where no external force acts,
  /// as in an interference fit. 0 for one body.
  double internal = 0.0;
  /// applied + the reactions + contact.
  Vector sum() const {
    Vector total = applied + contact;
    for (const auto& r : reactions) total += r.force;
    return total;
  }
  /// |sum()| over the largest of |applied|, |contact|, the |reaction|s and `internal` (a load
  /// that cancels out, or none, leaves the supports' and the contact's forces as the scale); 0
  /// when every force is 0.
  double residual() const {
    double scale = std::max({applied.norm(), contact.norm(), internal});
    for (const auto& r : reactions) scale = std::max(scale, r.force.norm());
    const double imbalance = sum().norm();
    if (scale == 0.0 && imbalance == 0.0) return 0.0;
    return imbalance / scale;
  }
};

using ForceBalance = BasicForceBalance<Eigen::Vector2d>;
using ForceBalance3D = BasicForceBalance<Eigen::Vector3d>;

/// The balance of forces of the nodal displacement `u` of `problem` (2 per vertex) with the
/// contact resultant `contact`: applied = sum of f, and the reaction of each Dirichlet
/// condition the sum of r = K u - f over the dofs it prescribes (a dof that several conditions
/// prescribe counts for the last one, whose value it takes). A condition without a name is
/// called "dirichlet part i" (i from 0). Costs the load vector and the element matrices of
/// the elements at prescribed dofs. `at_vertices`: other forces on vertices (vertex, force),
/// such as those of another body's contact nodes on the vertices across from them, which the
/// reaction of a condition prescribing their dofs does not include.
ForceBalance force_balance(const ElasticityProblem& problem, const Eigen::VectorXd& u, const Vec2& contact,
                           const std::vector<std::pair<int, Vec2>>& at_vertices = {});

}  // namespace hemivem
