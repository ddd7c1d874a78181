// The steps of the residual estimator that are the same for a plane and a solid body, written
// once for the dimension and instantiated by the plane's estimate_error (error_estimate.cpp,
// dim = 2, facets are edges) and the solid's (error_estimate3d.cpp, dim = 3, facets are
// faces): the checks of the input, the terms of an element that do not depend on its shape,
// what each boundary facet is, the contact tractions at a facet's vertices, the jump across an
// interior facet and the residual of a facet's loads.
#pragma once

#include <array>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/material.hpp>

#include "estimate_terms.hpp"

namespace hemivem::detail {

template <int dim>
using Point = Eigen::Matrix<double, dim, 1>;
template <int dim>
using Tensor = Eigen::Matrix<double, dim, dim>;
template <int dim>
using ElasticityOf = decltype(BasicContactProblem<dim>::elasticity);
template <int dim>
using MeshOf = std::remove_cvref_t<decltype(*std::declval<ElasticityOf<dim>>().mesh)>;

/// The mesh of `problem`. InputError when the problem has none or when `u` does not hold dim
/// entries per vertex.
template <int dim>
const MeshOf<dim>& checked_mesh(const BasicContactProblem<dim>& problem, const Eigen::VectorXd& u) {
  if (problem.elasticity.mesh == nullptr) throw InputError("estimate_error: the problem has no mesh");
  const MeshOf<dim>& mesh = *problem.elasticity.mesh;
  const int nv = mesh.num_vertices();
  if (u.size() != dim * static_cast<Eigen::Index>(nv))
    throw InputError("estimate_error: the solution has " + std::to_string(u.size()) + " displacement entries, the mesh " +
                     std::to_string(nv) + " vertices (" + std::to_string(dim) + " entries per vertex expected)");
  return mesh;
}

// ---- per element ----

/// The residuals of all elements and the stress of Pi u_h on each (constant on an element).
template <int dim>
struct ElementResiduals {
  std::vector<ElementTerms> terms;
  std::vector<Tensor<dim>> stress;
};

/// The positions of an element's vertices into `z` and their displacements into `local`
/// (dim entries per vertex, in the element's vertex order).
template <int dim, class Mesh, class Vertices>
void gather_element(const Mesh& mesh, const Vertices& vertices, const Eigen::VectorXd& u, std::vector<Point<dim>>& z,
                    Eigen::VectorXd& local) {
  const auto n = static_cast<Eigen::Index>(vertices.size());
  z.resize(vertices.size());
  local.resize(dim * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int v = vertices[static_cast<std::size_t>(i)];
    z[static_cast<std::size_t>(i)] = mesh.vertex(v);
    local.template segment<dim>(dim * i) = u.template segment<dim>(dim * static_cast<Eigen::Index>(v));
  }
}

/// The symmetric part of a gradient: the strain.
template <int dim>
Tensor<dim> strain_of(const Tensor<dim>& gradient) {
  return 0.5 * (gradient + gradient.transpose());
}

/// The stress lambda tr(eps) I + 2 mu eps of the strain of `gradient`.
template <int dim>
Tensor<dim> stress_of(const Tensor<dim>& gradient, const Lame& lame) {
  const Tensor<dim> eps = strain_of<dim>(gradient);
  return lame.lambda * eps.trace() * Tensor<dim>::Identity() + 2.0 * lame.mu * eps;
}

/// The terms of an element that do not depend on its shape: |E| sigma : eps of Pi u_h and the
/// weight C / (2 mu_E).
template <int dim>
ElementTerms element_base_terms(double measure, const Tensor<dim>& sigma, const Tensor<dim>& gradient, const Lame& lame) {
  ElementTerms t;
  t.consistency_energy = measure * sigma.cwiseProduct(strain_of<dim>(gradient)).sum();
  t.weight = error_estimate_constant / (2.0 * lame.mu);
  return t;
}

/// |(I - Pi) u|^2: the sum over the vertices of the squared difference between the nodal
/// values of u_h and those of Pi u_h (`field`).
template <int dim, class Field>
double nodal_defect(const std::vector<Point<dim>>& z, const Eigen::VectorXd& local, const Field& field) {
  double s = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i)
    s += (local.template segment<dim>(dim * static_cast<Eigen::Index>(i)) - field(z[i])).squaredNorm();
  return s;
}

// ---- what each boundary facet is ----

/// InputError for a facet id of a `what` part (Dirichlet, traction, contact) outside [0, count).
template <int dim>
void check_facet_ids(const std::vector<int>& ids, int count, const char* what) {
  for (int id : ids)
    if (id < 0 || id >= count)
      throw InputError(std::string("estimate_error: a ") + what +
                       (dim == 2 ? std::string(" edge id") : " face id (" + std::to_string(id) + ")") + " is out of range");
}

/// What each boundary facet is, and the traction of each contact node.
template <int dim>
struct BoundaryFacets {
  std::vector<std::array<bool, dim>> fixed;  ///< per facet: the components a Dirichlet condition fixes
  std::vector<std::vector<int>> loads;       ///< per facet: the indices of the traction loads on it
  /// per facet: 0 off Gamma_3, 1 on a frictionless contact part, 2 on one with friction
  std::vector<char> contact;
  std::vector<int> node_of;               ///< per vertex: its contact node (-1: none)
  std::vector<Point<dim>> node_traction;  ///< per contact node: its traction
};

/// Per facet: the components that the Dirichlet conditions on it fix.
template <int dim, class Dirichlet>
std::vector<std::array<bool, dim>> fixed_components(const std::vector<Dirichlet>& dirichlet, int nfacets) {
  std::array<bool, dim> none{};
  std::vector<std::array<bool, dim>> fixed(static_cast<std::size_t>(nfacets), none);
  for (const Dirichlet& d : dirichlet) {
    check_facet_ids<dim>(d.facets, nfacets, "Dirichlet");
    for (int f : d.facets)
      for (std::size_t k = 0; k < dim; ++k) fixed[static_cast<std::size_t>(f)][k] |= d.fix[k];
  }
  return fixed;
}

/// Per facet: the indices of the traction loads on it.
template <int dim, class Load>
std::vector<std::vector<int>> facet_loads(const std::vector<Load>& tractions, int nfacets) {
  std::vector<std::vector<int>> loads(static_cast<std::size_t>(nfacets));
  for (std::size_t k = 0; k < tractions.size(); ++k) {
    check_facet_ids<dim>(tractions[k].facets, nfacets, "traction");
    for (int f : tractions[k].facets) loads[static_cast<std::size_t>(f)].push_back(static_cast<int>(k));
  }
  return loads;
}

/// Per facet: 0 off Gamma_3, 1 on a frictionless part of `parts`, 2 on one with friction (the
/// other body's facets that a part meets, BasicContactPart::against, as the part's own).
template <int dim>
std::vector<char> contact_kinds(const std::vector<BasicContactPart<dim>>& parts, int nfacets) {
  std::vector<char> kind(static_cast<std::size_t>(nfacets), 0);
  for (const BasicContactPart<dim>& part : parts) {
    check_facet_ids<dim>(part.facets, nfacets, "contact");
    check_facet_ids<dim>(part.against, nfacets, "contact");
    for (int f : part.facets) kind[static_cast<std::size_t>(f)] = part.friction ? 2 : 1;
    for (int f : part.against) kind[static_cast<std::size_t>(f)] = part.friction ? 2 : 1;
  }
  return kind;
}

/// The traction of a contact node: t_i = -(p_i nu_i + zeta_t,i) / w_i (p: the normal force,
/// zeta_t: the friction force, in the plane friction_force along tau, on a solid's surface the
/// vector friction_vector), zero where its weight is not positive.
template <int dim>
Point<dim> node_traction(const BasicContactNode<dim>& node) {
  if (!(node.weight > 0.0)) return Point<dim>::Zero();
  if constexpr (dim == 2) {
    const Point<dim> tau(-node.normal.y(), node.normal.x());
    return -(node.force() / node.weight) * node.normal - (node.friction_force / node.weight) * tau;
  } else {
    return -node.pressure() * node.normal - node.friction_vector / node.weight;
  }
}

/// The contact node of each vertex and the traction of each node into `b`; a vertex of the
/// other body across from nodes (BasicContactNode::across) bears the opposite of their
/// tractions, weighted as the vertex's share of each point across (the opposite of the node's
/// traction at the vertex at its point). InputError for a node that names a vertex outside the
/// mesh.
template <int dim>
void contact_tractions(const std::vector<BasicContactNode<dim>>& nodes, int nv, BoundaryFacets<dim>& b) {
  b.node_of.assign(static_cast<std::size_t>(nv), -1);
  b.node_traction.assign(nodes.size(), Point<dim>::Zero());
  std::vector<double> share(static_cast<std::size_t>(nv), 0.0);  // per vertex across: its weights summed
  const auto outside = [nv](int v) { return v < 0 || v >= nv; };
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const BasicContactNode<dim>& node = nodes[i];
    if (outside(node.vertex) || (node.partner >= 0 && outside(node.partner)))
      throw InputError("estimate_error: contact node " + std::to_string(i) + " names vertex " +
                       std::to_string(outside(node.vertex) ? node.vertex : node.partner) + ", outside the mesh");
    b.node_of[static_cast<std::size_t>(node.vertex)] = static_cast<int>(i);
    b.node_traction[i] = node_traction<dim>(node);
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Across& across = nodes[i].across;
    for (int k = 0; k < across.size(); ++k) {
      const int q = across.vertex[static_cast<std::size_t>(k)];
      const double w = across.weight[static_cast<std::size_t>(k)];
      if (outside(q))
        throw InputError("estimate_error: contact node " + std::to_string(i) + " names vertex " + std::to_string(q) +
                         ", outside the mesh");
      int& at = b.node_of[static_cast<std::size_t>(q)];
      if (at < 0) {
        at = static_cast<int>(b.node_traction.size());
        b.node_traction.push_back(Point<dim>::Zero());
      }
      b.node_traction[static_cast<std::size_t>(at)] -= w * b.node_traction[i];
      share[static_cast<std::size_t>(q)] += w;
    }
  }
  for (int q = 0; q < nv; ++q)
    if (share[static_cast<std::size_t>(q)] > 0.0)
      b.node_traction[static_cast<std::size_t>(b.node_of[static_cast<std::size_t>(q)])] /= share[static_cast<std::size_t>(q)];
}

/// What each of the mesh's `nfacets` facets is: the components fixed on it, its loads, its
/// contact part's kind (of `parts`), and the contact nodes of `solution` with their tractions.
template <int dim>
BoundaryFacets<dim> boundary_facets(const BasicContactProblem<dim>& problem, const std::vector<BasicContactPart<dim>>& parts,
                                    const BasicContactSolution<dim>& solution, int nfacets) {
  BoundaryFacets<dim> b;
  b.fixed = fixed_components<dim>(problem.elasticity.dirichlet, nfacets);
  b.loads = facet_loads<dim>(problem.elasticity.tractions, nfacets);
  b.contact = contact_kinds<dim>(parts, nfacets);
  contact_tractions<dim>(solution.contact, problem.elasticity.mesh->num_vertices(), b);
  return b;
}

// ---- the facets ----

/// h ||[sigma n]||^2 on an interior facet, `scale` h times the facet's measure, half to each side.
template <int dim>
void add_jump(std::vector<ElementTerms>& terms, const std::vector<Tensor<dim>>& stress, int inner, int outer,
              const Point<dim>& normal, double scale) {
  const Point<dim> jump_vector = (stress[static_cast<std::size_t>(inner)] - stress[static_cast<std::size_t>(outer)]) * normal;
  const double value = scale * jump_vector.squaredNorm();
  terms[static_cast<std::size_t>(inner)].raw[jump] += 0.5 * value;
  terms[static_cast<std::size_t>(outer)].raw[jump] += 0.5 * value;
}

/// The contact traction at each vertex of a facet on Gamma_3 into `out`: its contact node's,
/// and at a vertex that is not a contact node (e.g. on Gamma_1) the mean of the facet's
/// contact nodes (on an edge: the other end's); zero on a facet without contact nodes.
template <int dim, class Vertices>
void facet_tractions(const Vertices& vertices, const BoundaryFacets<dim>& b, std::vector<Point<dim>>& out) {
  out.assign(vertices.size(), Point<dim>::Zero());
  Point<dim> mean = Point<dim>::Zero();
  int count = 0;
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (const int k = b.node_of[static_cast<std::size_t>(vertices[i])]; k >= 0) {
      out[i] = b.node_traction[static_cast<std::size_t>(k)];
      mean += out[i];
      ++count;
    }
  if (count > 0) mean /= static_cast<double>(count);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    if (b.node_of[static_cast<std::size_t>(vertices[i])] < 0) out[i] = mean;
}

/// |f2(x) - sigma n|^2 on Gamma_2 in the components that no Dirichlet condition fixes (`fix`):
/// f2 the sum of the loads `on_facet` of `tractions` at x (zero on a free facet), a pressure
/// acting along -normal.
template <int dim, class Load>
double load_residual(const std::vector<Load>& tractions, const std::vector<int>& on_facet, const Point<dim>& x,
                     const Point<dim>& normal, const Point<dim>& sn, const std::array<bool, dim>& fix) {
  Point<dim> f2 = Point<dim>::Zero();
  for (int k : on_facet) {
    const Load& load = tractions[static_cast<std::size_t>(k)];
    if (load.traction) f2 += load.traction(x);
    if (load.pressure) f2 -= load.pressure(x) * normal;
  }
  Point<dim> r = f2 - sn;
  for (int c = 0; c < dim; ++c)
    if (fix[static_cast<std::size_t>(c)]) r(c) = 0.0;
  return r.squaredNorm();
}

}  // namespace hemivem::detail
