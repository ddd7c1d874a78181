#include <hemivem/contact/supports.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/rigid_motions.hpp>

namespace hemivem {

namespace {

// The functionals of the motions at the contact nodes along the normals (or the tangents).
Eigen::MatrixXd along(const RigidMotions& motions, const ContactBoundary& boundary, bool tangents) {
  Eigen::MatrixXd rows(boundary.size(), 3 * motions.num_pieces());
  for (int i = 0; i < boundary.size(); ++i) {
    const Vec2 nu = boundary.normals[static_cast<std::size_t>(i)];
    rows.row(i) = motions.functional(boundary.nodes[static_cast<std::size_t>(i)], tangents ? Vec2(-nu.y(), nu.x()) : nu);
  }
  return rows;
}

std::string listed(const RigidMotions& motions) {
  std::string text;
  for (int k = 0; k < motions.size(); ++k) text += (k == 0 ? "" : "; ") + motions.describe(k);
  return text;
}

}  // namespace

Supports find_supports(const Mesh& mesh, const DofMap& dofs, const ContactBoundary& boundary, bool normal_unknowns,
                       bool tangential_law) {
  RigidMotions free(mesh, dofs);
  Supports supports;
  if (free.empty()) return supports;
  const std::string count = free.size() == 1 ? "a rigid motion" : std::to_string(free.size()) + " rigid motions";
  if (boundary.size() == 0)
    throw InputError("the Dirichlet conditions leave " + count + " of the body free and there is no contact to hold " +
                     (free.size() == 1 ? "it: " : "them: ") + listed(free) +
                     "; prescribe displacements that hold the body (a clamped side, or rollers in two directions "
                     "away from one line)");
  // a bilateral constraint holds the normal displacements as a support would
  const RigidMotions rest = normal_unknowns ? free : free.without(along(free, boundary, false));
  Eigen::MatrixXd moved = normal_unknowns ? along(rest, boundary, false) : Eigen::MatrixXd(0, 3 * free.num_pieces());
  if (tangential_law) {
    const Eigen::MatrixXd t = along(rest, boundary, true);
    moved.conservativeResize(moved.rows() + t.rows(), Eigen::NoChange);
    moved.bottomRows(t.rows()) = t;
  }
  const RigidMotions unheld = rest.without(moved);
  if (!unheld.empty())
    throw InputError("the Dirichlet conditions leave " + listed(unheld) +
                     " free, and the contact cannot hold it: it moves no contact node along its normal" +
                     (tangential_law ? std::string(" or tangent")
                                     : std::string(" (frictionless contact does not resist sliding along it)")) +
                     "; prescribe displacements that hold it");
  for (int k = 0; k < free.size(); ++k) supports.held_by_contact.push_back(free.describe(k));
  return supports;
}

}  // namespace hemivem
