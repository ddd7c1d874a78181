#include <hemivem/contact/supports.hpp>
#include <hemivem/error.hpp>
#include <hemivem/support/condition.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <algorithm>
#include <cmath>

namespace hemivem {

namespace {

// The functionals of the motions at the contact nodes `which` (all when empty) along the
// normals (or the tangents).
template <int dim>
Eigen::MatrixXd along(const BasicRigidMotions<dim>& motions, const ContactBoundary& boundary, bool tangents,
                      const std::vector<char>& which = {}) {
  Eigen::MatrixXd rows(2 * boundary.size(), BasicRigidMotions<dim>::per_piece * motions.num_pieces());
  Eigen::Index r = 0;
  for (int i = 0; i < boundary.size(); ++i) {
    if (!which.empty() && !which[static_cast<std::size_t>(i)]) continue;
    const int node = boundary.nodes[static_cast<std::size_t>(i)];
    // at a pair of two bodies, the motion of the node relative to the point across from it
    const Across across = boundary.across.empty() ? Across{} : boundary.across[static_cast<std::size_t>(i)];
    const auto functional = [&](const PointOf<dim>& direction) -> Eigen::RowVectorXd {
      Eigen::RowVectorXd row = motions.functional(node, direction);
      for (int k = 0; k < across.size(); ++k)
        row -= across.weight[static_cast<std::size_t>(k)] * motions.functional(across.vertex[static_cast<std::size_t>(k)], direction);
      return row;
    };
    if constexpr (dim == 2) {
      const Vec2 nu = boundary.normals[static_cast<std::size_t>(i)];
      rows.row(r++) = functional(tangents ? Vec2(-nu.y(), nu.x()) : nu);
    } else {
      const Vec3 nu = boundary.normals3d[static_cast<std::size_t>(i)];
      if (!tangents) {
        rows.row(r++) = functional(nu);
        continue;
      }
      // a solid's friction acts in the whole tangent plane: two directions spanning it
      for (const Vec3& t : tangent_frame(nu)) rows.row(r++) = functional(t);
    }
  }
  return rows.topRows(r);
}

template <int dim>
std::string listed(const BasicRigidMotions<dim>& motions) {
  std::string text;
  for (int k = 0; k < motions.size(); ++k) text += (k == 0 ? "" : "; ") + motions.describe(k);
  return text;
}

// The supports with, per contact node, whether its normal displacement is an unknown (not
// bilateral) and whether a tangential law acts on it.
template <int dim, class M>
Supports supports_of(const M& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                     const std::vector<char>& normal_unknowns, const std::vector<char>& tangential_law,
                     const PieceBodies& bodies = {}) {
  const BasicRigidMotions<dim> free(mesh, dofs, bodies);
  Supports supports;
  if (free.empty()) return supports;
  const std::string count = free.size() == 1 ? "a rigid motion" : std::to_string(free.size()) + " rigid motions";
  if (boundary.size() == 0)
    throw InputError("the Dirichlet conditions leave " + count + " of the body free and there is no contact to hold " +
                     (free.size() == 1 ? "it: " : "them: ") + listed(free) +
                     "; prescribe displacements that hold the body (a clamped side, or rollers in two directions "
                     "away from one line)");
  const auto all = [](const std::vector<char>& v) { return std::all_of(v.begin(), v.end(), [](char c) { return c != 0; }); };
  const auto none = [](const std::vector<char>& v) { return std::none_of(v.begin(), v.end(), [](char c) { return c != 0; }); };
  std::vector<char> bilateral(normal_unknowns.size());
  for (std::size_t i = 0; i < bilateral.size(); ++i) bilateral[i] = normal_unknowns[i] ? 0 : 1;
  // a bilateral constraint holds the normal displacements as a support would
  const BasicRigidMotions<dim> rest = all(normal_unknowns) ? free : free.without(along(free, boundary, false, bilateral));
  Eigen::MatrixXd moved = none(normal_unknowns) ? Eigen::MatrixXd(0, BasicRigidMotions<dim>::per_piece * free.num_pieces())
                                                : along(rest, boundary, false, normal_unknowns);
  const bool friction = !none(tangential_law);
  if (friction) {
    const Eigen::MatrixXd t = along(rest, boundary, true, tangential_law);
    moved.conservativeResize(moved.rows() + t.rows(), Eigen::NoChange);
    moved.bottomRows(t.rows()) = t;
  }
  const BasicRigidMotions<dim> unheld = rest.without(moved);
  if (!unheld.empty())
    throw InputError("the Dirichlet conditions leave " + listed(unheld) +
                     " free, and the contact cannot hold it: it moves no contact node along its normal" +
                     (friction ? std::string(" or tangent")
                               : std::string(" (frictionless contact does not resist sliding along it)")) +
                     "; prescribe displacements that hold it");
  for (int k = 0; k < free.size(); ++k) supports.held_by_contact.push_back(free.describe(k));
  return supports;
}

}  // namespace

Supports find_supports(const Mesh& mesh, const DofMap& dofs, const ContactBoundary& boundary, bool normal_unknowns,
                       bool tangential_law) {
  const auto n = static_cast<std::size_t>(boundary.size());
  return supports_of<2>(mesh, dofs, boundary, std::vector<char>(n, normal_unknowns ? 1 : 0),
                        std::vector<char>(n, tangential_law ? 1 : 0));
}

namespace {

template <int dim, class M>
Supports supports_of_parts(const M& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                           const std::vector<BasicContactPart<dim>>& parts, const PieceBodies& bodies) {
  const auto n = static_cast<std::size_t>(boundary.size());
  std::vector<char> normal(n, 1), tangential(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int k = boundary.part_of(static_cast<int>(i));
    if (k < 0 || k >= static_cast<int>(parts.size()))
      throw InputError("contact node " + std::to_string(boundary.nodes[i]) + " is in contact part " + std::to_string(k) +
                       ", but " + std::to_string(parts.size()) + " parts are given");
    const auto& part = parts[static_cast<std::size_t>(k)];
    normal[i] = part.constraint == ConstraintKind::bilateral ? 0 : 1;
    tangential[i] = part.friction ? 1 : 0;
  }
  return supports_of<dim>(mesh, dofs, boundary, normal, tangential, bodies);
}

}  // namespace

Supports find_supports(const Mesh& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                       const std::vector<ContactPart>& parts, const PieceBodies& bodies) {
  return supports_of_parts<2>(mesh, dofs, boundary, parts, bodies);
}

Supports find_supports(const Mesh3D& mesh, const DofMap& dofs, const ContactBoundary& boundary,
                       const std::vector<BasicContactPart<3>>& parts, const PieceBodies& bodies) {
  return supports_of_parts<3>(mesh, dofs, boundary, parts, bodies);
}

void require_box_gap(double gap, int node, const std::string& part) {
  if (std::isfinite(gap) && gap >= 0.0) return;
  throw InputError("the box constraint |u_nu| <= g needs a finite gap >= 0, but the obstacle gives " + std::to_string(gap) +
                   " at contact node " + std::to_string(node) +
                   (part.empty() ? std::string() : " (contact part '" + part + "')") +
                   "; set contact.constraint = \"one-sided\" with an obstacle");
}

void require_nodes_in_every_part(const ContactBoundary& boundary, const std::vector<std::string>& names) {
  std::vector<char> touched(names.size(), 0);
  for (int i = 0; i < boundary.size(); ++i)
    if (const int k = boundary.part_of(i); k >= 0 && k < static_cast<int>(touched.size())) touched[static_cast<std::size_t>(k)] = 1;
  for (std::size_t k = 0; k < names.size(); ++k)
    if (!touched[k])
      throw InputError((names.size() > 1 ? "contact part '" + names[k] + "'" : std::string("the contact part")) +
                       " has no contact node left: the supports prescribe the normal displacement of every one of its "
                       "nodes (a prescribed normal component takes a node out of the contact); end the support's or "
                       "the contact's part before the other");
}

double factorized_condition_estimate(const SparseMatrix& A, const SparseFactorization& f) {
  auto apply = [&](const Eigen::MatrixXd& x) {
    Eigen::MatrixXd y;
    if (!f.solve(x, &y).ok() || y.cols() != x.cols()) return Eigen::MatrixXd();
    return y;
  };
  return norm1(A) * estimate_norm1_symmetric_blocks(static_cast<int>(A.rows()), apply);
}

}  // namespace hemivem
