#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/contact/supports.hpp>

#include "solver.templates.hpp"
#include <hemivem/contact/supports.hpp>
#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/vem/element3d.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>

namespace hemivem {

namespace {

std::string point_text(const Vec3& p) {
  return "(" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")";
}

}  // namespace

namespace {

// The unit normal of contact node v from the sum of its faces' weighted normals; with
// prescribed components (bit c of `mask` for component c: a symmetry plane or a roller meeting
// Gamma_3) made exactly perpendicular to them, which must be tangential. Empty when a prescribed
// component is the normal one: the support holds the node, which leaves the contact.
std::optional<Vec3> node_normal(const Mesh3D& mesh, int v, const Vec3& sum, int mask, const Vec3& lo, const Vec3& hi) {
  const double length = scale_free_norm(sum);
  if (!(length > 0.0))
    throw InputError("contact node " + std::to_string(v) + " has no defined normal (its contact faces cancel)");
  Vec3 normal = sum / length;
  if (mask == 0) return normal;
  for (int c = 0; c < 3; ++c)
    if ((mask & (1 << c)) && 1.0 - std::abs(normal(c)) <= tangential_tolerance) return std::nullopt;
  for (int c = 0; c < 3; ++c) {
    if (!(mask & (1 << c))) continue;
    // on a symmetry plane: every contact face on one side of it
    const double extent = (hi - lo).norm();
    const bool one_side = lo(c) >= -1e-12 * extent || hi(c) <= 1e-12 * extent;
    if (!(std::abs(normal(c)) <= (one_side ? symmetry_tolerance : tangential_tolerance)))
      throw InputError("contact node " + std::to_string(v) + " at " + point_text(mesh.vertex(v)) + " has its " +
                       std::string(1, "xyz"[c]) + " displacement prescribed, which is not tangential to its contact normal " +
                       point_text(normal) +
                       ": a contact node may have prescribed components in its tangent plane (a symmetry plane) "
                       "or along its normal, not oblique to them; end the support's or the contact's faces before it");
    normal(c) = 0.0;
  }
  return normal.normalized();
}

}  // namespace

ContactBoundary make_contact_boundary(const Mesh3D& mesh, const std::vector<ContactPart3D>& parts, const DofMap& dofs) {
  if (dofs.num_dofs() != 3 * mesh.num_vertices())
    throw InputError("a dof map of " + std::to_string(dofs.num_dofs()) + " dofs for a mesh of " +
                     std::to_string(3 * mesh.num_vertices()));
  ContactBoundary cb;
  cb.dimension = 3;
  struct Sum {
    Vec3 normal = Vec3::Zero();
    double weight = 0.0;
    int part = -1;  // the first part holding the node
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the vertices of its faces, less the node
  };
  std::map<int, Sum> acc;
  std::map<int, std::size_t> face_part;
  std::vector<Vec3> z;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    for (int id : parts[k].facets) {
      if (id < 0 || id >= mesh.num_faces()) throw InputError("contact face id " + std::to_string(id) + " out of range");
      if (!mesh.face(id).on_boundary()) throw InputError("contact face " + std::to_string(id) + " is not on the boundary");
      if (const auto [at, added] = face_part.emplace(id, k); !added)
        throw InputError("contact face " + std::to_string(id) + " at " + point_text(mesh.face_centroid(id)) +
                         " is in contact parts '" + parts[at->second].name + "' and '" + parts[k].name +
                         "'; each face belongs to one contact part (parts may meet at an edge or a node, which then "
                         "belongs to the part listed first)");
      cb.faces.push_back(id);
      const auto& loop = mesh.face(id).vertices;
      const Vec3 c = mesh.face_centroid(id), n = mesh.face_normal(id);
      const std::size_t m = loop.size();
      z.clear();
      for (int v : loop) z.push_back(mesh.vertex(v));
      const Eigen::VectorXd omega = face_weights(z);  // int_f v = sum_i omega_i v_i in the enhanced face space
      for (std::size_t i = 0; i < m; ++i) {
        const int a = loop[i], b = loop[(i + 1) % m];
        acc[a].weight += omega(static_cast<Eigen::Index>(i));
        if (acc[a].part < 0) acc[a].part = static_cast<int>(k);
        const double half = 0.25 * scale_free_norm((mesh.vertex(a) - c).cross(mesh.vertex(b) - c));
        for (int v : {a, b}) acc[v].normal += half * n;
      }
      for (int a : loop)
        for (int b : loop) {
          acc[a].lo = acc[a].lo.cwiseMin(mesh.vertex(b) - mesh.vertex(a));
          acc[a].hi = acc[a].hi.cwiseMax(mesh.vertex(b) - mesh.vertex(a));
        }
    }
  }
  for (const auto& [v, entry] : acc) {
    int mask = 0;
    for (int c = 0; c < 3; ++c)
      if (dofs.free_index(3 * v + c) < 0) mask |= 1 << c;
    if (mask == 7) continue;  // on Gamma_1
    if (!(entry.weight > 0.0))
      throw InputError("contact node " + std::to_string(v) + " at " + point_text(mesh.vertex(v)) +
                       " has the quadrature weight " + std::to_string(entry.weight) +
                       " (the sum of its contact faces' weights, which must be positive): a contact face is too far "
                       "from its vertices' mean to integrate over; split it");
    const std::optional<Vec3> held = node_normal(mesh, v, entry.normal, mask, entry.lo, entry.hi);
    if (!held) continue;  // its normal displacement is prescribed
    const Vec3 normal = *held;
    const ContactPart3D& part = parts[static_cast<std::size_t>(entry.part)];
    double g = 0.0;
    if (part.obstacle) {
      g = part.obstacle->gap(mesh.vertex(v), normal);
      if (std::isnan(g)) throw InputError("the obstacle gives no gap at contact node " + std::to_string(v));
    } else {
      g = part.gap ? part.gap(mesh.vertex(v)) : 0.0;
      if (!std::isfinite(g) || g < 0.0)
        throw InputError("gap " + std::to_string(g) + " at contact node " + std::to_string(v) + " must be finite and >= 0");
    }
    cb.nodes.push_back(v);
    cb.normals3d.push_back(normal);
    cb.prescribed_mask.push_back(mask);
    cb.part.push_back(entry.part);
    cb.weights.conservativeResize(cb.size());
    cb.weights(cb.size() - 1) = entry.weight;
    cb.gaps.conservativeResize(cb.size());
    cb.gaps(cb.size() - 1) = g;
  }
  pair_with_other_body<3>(mesh, parts, cb);
  return cb;
}

ContactBoundary make_contact_boundary(const Mesh3D& mesh, const std::vector<int>& faces, const DofMap& dofs,
                                         const std::function<double(const Vec3&)>& gap, const Obstacle3D* obstacle) {
  ContactPart3D part;
  part.name = "contact";
  part.facets = faces;
  part.gap = gap;
  if (obstacle) part.obstacle = *obstacle;
  return make_contact_boundary(mesh, std::vector<ContactPart3D>{std::move(part)}, dofs);
}

std::vector<int> contact_faces(const ContactProblem3D& problem) {
  std::vector<int> faces;
  for (const ContactPart3D& part : problem.parts) faces.insert(faces.end(), part.facets.begin(), part.facets.end());
  return faces;
}

ContactBoundary contact_boundary(const ContactProblem3D& problem, const DofMap& dofs) {
  const std::vector<ContactPart3D> parts = contact_parts(problem);
  if (parts.empty()) return ContactBoundary{};
  for (const ContactPart3D& part : parts)
    if (part.obstacle)
      if (const std::string d = part.obstacle->defect(); !d.empty())
        throw InputError("the obstacle" + (parts.size() > 1 ? " of contact part '" + part.name + "'" : std::string()) + ": " + d);
  const ContactBoundary boundary = make_contact_boundary(*problem.elasticity.mesh, parts, dofs);
  std::vector<std::string> names;
  for (const ContactPart3D& part : parts) names.push_back(part.name);
  require_nodes_in_every_part(boundary, names);
  for (int i = 0; i < boundary.size(); ++i) {
    const ContactPart3D& part = parts[static_cast<std::size_t>(boundary.part_of(i))];
    if (part.obstacle && part.constraint == ConstraintKind::box)
      require_box_gap(boundary.gaps(i), boundary.nodes[static_cast<std::size_t>(i)], parts.size() > 1 ? part.name : "");
  }
  return boundary;
}

BasicContactNode<3> contact_node(const Mesh3D& mesh, const ContactBoundary& boundary, const Condensation& cond,
                                 const DofMap& dofs, int i, const MinimizerResult& m, const Eigen::VectorXd* residual) {
  const ReducedProblem& rp = cond.reduced();
  const bool forces = m.law_force.size() == m.a.size() && m.reaction.size() == m.a.size();
  ContactNode3D node;
  const auto k0 = static_cast<std::size_t>(i);
  node.vertex = boundary.nodes[k0];
  node.part = boundary.part_of(i);
  node.partner = boundary.partner_of(i);
  if (!boundary.across.empty()) node.across = boundary.across[static_cast<std::size_t>(i)];
  node.x = mesh.vertex(node.vertex);
  node.weight = boundary.weights(i);
  node.normal = boundary.normals3d[k0];
  node.gap = cond.normal_coordinate(i) >= 0 ? boundary.gaps(i) : std::numeric_limits<double>::quiet_NaN();
  if (const int k = cond.normal_coordinate(i); k >= 0) {
    node.u_nu = m.a(k) + cond.origin()(k);
    node.law_force = forces ? m.law_force(k) : 0.0;
    node.reaction = forces ? m.reaction(k) : 0.0;
    node.state = contact_state(m.a(k), rp.lower(k), rp.upper(k), node.law_force);
  } else {
    node.state = ContactState::tied;
    double f = 0.0;
    bool known = residual != nullptr;
    for (int c = 0; c < 3 && known; ++c) {
      const int d = dofs.free_index(3 * node.vertex + c);
      if (d < 0) {
        if (node.normal(c) != 0.0) known = false;
        continue;
      }
      f -= (*residual)(d) * node.normal(c);
    }
    node.reaction = known ? f : std::numeric_limits<double>::quiet_NaN();
  }
  // the tangential slots (one where a tangential component is prescribed, two otherwise): the
  // vectors, their lengths and the state of the law of the norm
  for (const int slot : {1, 2}) {
    const int k = slot == 1 ? cond.tangential_coordinate(i) : cond.second_tangential_coordinate(i);
    if (k < 0) continue;
    const Vec3 t = cond.slot_direction(i, slot);
    node.u_tangential += m.a(k) * t;
    if (forces) node.friction_vector += (m.law_force(k) + m.reaction(k)) * t;
  }
  if (const int k = cond.tangential_coordinate(i); k >= 0) {
    node.u_tau = node.u_tangential.norm();
    node.friction_force = node.friction_vector.norm();
    node.friction_state = friction_state(rp.law_of(k), node.u_tau);
  }
  return node;
}

namespace detail {

template <>
struct Kernels<3> {
  static void check(const ContactProblem3D& problem) {
    if (!problem.elasticity.mesh) throw InputError("the elasticity problem has no mesh");
  }
  static LinearSystem assemble(const ContactProblem3D& problem) { return hemivem::assemble(problem.elasticity); }
  static std::vector<ContactPart3D> parts(const ContactProblem3D& problem) { return contact_parts(problem); }
  static ContactBoundary boundary(const ContactProblem3D& problem, const std::vector<ContactPart3D>&, const DofMap& dofs) {
    return contact_boundary(problem, dofs);
  }
  // The free motions the contact holds (find_supports); one that nothing holds is refused with
  // every free motion of each piece by the axes, and where the piece is.
  static std::vector<std::string> held_by_contact(const ContactProblem3D& problem, const DofMap& dofs,
                                                  const ContactBoundary& boundary,
                                                  const std::vector<ContactPart3D>& parts) {
    const Mesh3D& mesh = *problem.elasticity.mesh;
    const PieceBodies& bodies = problem.elasticity.piece_bodies;
    const BasicRigidMotions<3> free(mesh, dofs, bodies);
    if (free.empty()) return {};
    try {
      return find_supports(mesh, dofs, boundary, parts, bodies).held_by_contact;
    } catch (const InputError& e) {
      std::string words;
      for (int k = 0; k < free.size(); ++k) words += (k == 0 ? "" : ", ") + free.describe_by_axes(k);
      throw InputError("the supports leave rigid motions of the body free (" + words + "), and " +
                       (boundary.size() == 0 ? std::string("there is no contact to hold them")
                                             : "its contact cannot hold them all (" + e.detail() + ")") +
                       "; a three-dimensional body, and each piece of it, must be held by its supports (symmetry "
                       "planes count) or by the normal contact of its nodes");
    }
  }
  static ForceBalance3D balance(const ContactProblem3D& problem, const Eigen::VectorXd& u, const Vec3& contact) {
    return force_balance(problem.elasticity, u, contact);
  }
};

}  // namespace detail

template class BasicContactSolver<3>;
template void require_finite_solution<3>(BasicContactSolution<3>&);
template ContactSetUp<3> contact_set_up<3>(const ContactProblem3D&, const DofMap&);
template void require_contact_laws<3>(const std::vector<ContactPart3D>&);

namespace {

std::vector<ContactSolution3D> solve_3d(const ContactProblem3D& problem, const LinearSystem* given,
                                        std::unique_ptr<SparseFactorization> factorization,
                                        std::span<const NonsmoothMinimizer* const> minimizers,
                                        const MinimizerOptions& options, ReducedProblem* reduced,
                                        bool estimate_condition) {
  std::optional<ContactSolver3D> solver;
  if (given) solver.emplace(problem, *given, std::move(factorization), options);
  else solver.emplace(problem, std::move(factorization), options);
  return solver->estimate_condition(estimate_condition).export_reduced(reduced).run(minimizers);
}

}  // namespace

std::vector<ContactSolution3D> solve_contact(const ContactProblem3D& problem,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced,
                                                bool estimate_condition) {
  return solve_3d(problem, nullptr, std::move(factorization), minimizers, options, reduced, estimate_condition);
}

std::vector<ContactSolution3D> solve_contact(const ContactProblem3D& problem, const LinearSystem& system,
                                                std::unique_ptr<SparseFactorization> factorization,
                                                std::span<const NonsmoothMinimizer* const> minimizers,
                                                const MinimizerOptions& options, ReducedProblem* reduced,
                                                bool estimate_condition) {
  return solve_3d(problem, &system, std::move(factorization), minimizers, options, reduced, estimate_condition);
}

ContactSolution3D solve_contact(const ContactProblem3D& problem, std::unique_ptr<SparseFactorization> factorization,
                                   const NonsmoothMinimizer& minimizer, const MinimizerOptions& options,
                                   ReducedProblem* reduced, bool estimate_condition) {
  const NonsmoothMinimizer* one[] = {&minimizer};
  return solve_contact(problem, std::move(factorization), one, options, reduced, estimate_condition).front();
}

}  // namespace hemivem
