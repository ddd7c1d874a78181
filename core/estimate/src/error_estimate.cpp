#include <hemivem/estimate/error_estimate.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include <hemivem/error.hpp>
#include <hemivem/vem/element.hpp>

#include "estimate_terms.hpp"

namespace hemivem {

namespace {

using namespace detail;

// The 3-point Gauss rule on [0, 1]: exact for polynomials of degree 5.
constexpr std::array<double, 3> gauss_points{0.5 - 0.3872983346207417, 0.5, 0.5 + 0.3872983346207417};
constexpr std::array<double, 3> gauss_weights{5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// The in-plane stress of the element's projection Pi u_h (constant on the element).
Eigen::Matrix2d stress_of(const LinearField& field, const Lame& lame) {
  const Eigen::Matrix2d eps = 0.5 * (field.gradient + field.gradient.transpose());
  return lame.lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2.0 * lame.mu * eps;
}

}  // namespace

const std::vector<std::string>& error_estimate_part_names() {
  static const std::vector<std::string> names{"volume", "jump", "traction", "contact", "friction", "stabilization"};
  return names;
}

ErrorEstimate estimate_error(const ContactProblem& problem, const ContactSolution& solution) {
  const auto start = std::chrono::steady_clock::now();
  const ElasticityProblem& elasticity = problem.elasticity;
  if (elasticity.mesh == nullptr) throw InputError("estimate_error: the problem has no mesh");
  const Mesh& mesh = *elasticity.mesh;
  const int nv = mesh.num_vertices();
  const int ne = mesh.num_elements();
  if (solution.u.size() != 2 * static_cast<Eigen::Index>(nv))
    throw InputError("estimate_error: the solution has " + std::to_string(solution.u.size()) +
                     " displacement entries, the mesh " + std::to_string(nv) + " vertices (2 entries per vertex expected)");
  const Eigen::VectorXd& u = solution.u;
  const double C = error_estimate_constant;

  // ---- per element: Pi u_h, its stress, the volume residual and the stabilization term ----
  std::vector<ElementTerms> terms(static_cast<std::size_t>(ne));
  std::vector<Eigen::Matrix2d> stress(static_cast<std::size_t>(ne));
  std::vector<Vec2> z;
  Eigen::VectorXd local;
  for (int e = 0; e < ne; ++e) {
    const auto vertices = mesh.element(e);
    const int n = static_cast<int>(vertices.size());
    z.resize(static_cast<std::size_t>(n));
    local.resize(2 * n);
    for (int i = 0; i < n; ++i) {
      const int v = vertices[static_cast<std::size_t>(i)];
      z[static_cast<std::size_t>(i)] = mesh.vertex(v);
      local(2 * i) = u(2 * v);
      local(2 * i + 1) = u(2 * v + 1);
    }
    const Lame lame = elasticity.materials.lame(mesh.region(e));
    const LinearField field = project_p1(z, local);
    const Eigen::Matrix2d sigma = stress_of(field, lame);
    stress[static_cast<std::size_t>(e)] = sigma;
    const Eigen::Matrix2d eps = 0.5 * (field.gradient + field.gradient.transpose());
    ElementTerms& t = terms[static_cast<std::size_t>(e)];
    t.consistency_energy = mesh.area(e) * (sigma.cwiseProduct(eps)).sum();
    t.weight = C / (2.0 * lame.mu);

    // S_E(u - Pi u, u - Pi u) = tau |(I - Pi) u|^2: the nodal values of u_h minus those of Pi u_h
    if (elasticity.stabilization == Stabilization::two_mu) {
      double s = 0.0;
      for (int i = 0; i < n; ++i) {
        const Vec2 d = Vec2(local(2 * i), local(2 * i + 1)) - field(z[static_cast<std::size_t>(i)]);
        s += d.squaredNorm();
      }
      t.raw[stabilization] = 2.0 * lame.mu * s;
    } else {
      const VemElement element = vem_element(z, lame, elasticity.stabilization);
      t.raw[stabilization] = local.dot(element.stabilization * local);
    }

    // h_E^2 ||f0 + div sigma(Pi u_h)||^2_E = h_E^2 ||f0||^2_E: a degree-2 rule on the triangles
    // (centroid, z_i, z_i+1)
    if (elasticity.body_force) {
      const Vec2 c = mesh.centroid(e);
      double integral = 0.0;
      for (int i = 0; i < n; ++i) {
        const Vec2& a = z[static_cast<std::size_t>(i)];
        const Vec2& b = z[static_cast<std::size_t>((i + 1) % n)];
        const double area = 0.5 * std::abs((a - c).x() * (b - c).y() - (a - c).y() * (b - c).x());
        for (const auto& [wa, wb] : {std::pair{1.0 / 6.0, 1.0 / 6.0}, std::pair{2.0 / 3.0, 1.0 / 6.0},
                                     std::pair{1.0 / 6.0, 2.0 / 3.0}})
          integral += area / 3.0 * elasticity.body_force(c + wa * (a - c) + wb * (b - c)).squaredNorm();
      }
      t.raw[volume] = mesh.diameter(e) * mesh.diameter(e) * integral;
    }
  }

  // ---- what each boundary edge is ----
  const int nedges = mesh.num_edges();
  std::vector<std::array<bool, 2>> fixed(static_cast<std::size_t>(nedges), {false, false});
  for (const DirichletCondition& d : elasticity.dirichlet)
    for (int edge : d.edges) {
      if (edge < 0 || edge >= nedges) throw InputError("estimate_error: a Dirichlet edge id is out of range");
      for (int c = 0; c < 2; ++c) fixed[static_cast<std::size_t>(edge)][static_cast<std::size_t>(c)] |= d.fix[static_cast<std::size_t>(c)];
    }
  std::vector<std::vector<int>> loads(static_cast<std::size_t>(nedges));  // the TractionLoads on each edge
  for (std::size_t k = 0; k < elasticity.tractions.size(); ++k)
    for (int edge : elasticity.tractions[k].edges) {
      if (edge < 0 || edge >= nedges) throw InputError("estimate_error: a traction edge id is out of range");
      loads[static_cast<std::size_t>(edge)].push_back(static_cast<int>(k));
    }
  // per edge: 0 off Gamma_3, 1 on a frictionless contact part, 2 on one with friction
  std::vector<char> is_contact(static_cast<std::size_t>(nedges), 0);
  for (const ContactPart& part : contact_parts(problem))
    for (int edge : part.facets) {
      if (edge < 0 || edge >= nedges) throw InputError("estimate_error: a contact edge id is out of range");
      is_contact[static_cast<std::size_t>(edge)] = part.friction ? 2 : 1;
    }
  // The traction t_i = -p_i nu_i - q_i tau_i of each contact node (p, q: force / weight).
  std::vector<int> node_of(static_cast<std::size_t>(nv), -1);
  std::vector<Vec2> node_traction(solution.contact.size(), Vec2::Zero());
  for (std::size_t i = 0; i < solution.contact.size(); ++i) {
    const ContactNode& node = solution.contact[i];
    if (node.vertex < 0 || node.vertex >= nv)
      throw InputError("estimate_error: contact node " + std::to_string(i) + " names vertex " +
                       std::to_string(node.vertex) + ", outside the mesh");
    node_of[static_cast<std::size_t>(node.vertex)] = static_cast<int>(i);
    if (node.weight > 0.0) {
      const Vec2 tau(-node.normal.y(), node.normal.x());
      node_traction[i] = -(node.force() / node.weight) * node.normal - (node.friction_force / node.weight) * tau;
    }
  }

  // ---- edges ----
  for (int id = 0; id < nedges; ++id) {
    const MeshEdge& edge = mesh.edge(id);
    const Vec2 a = mesh.vertex(edge.v0);
    const Vec2 b = mesh.vertex(edge.v1);
    const double length = (b - a).norm();
    if (!(length > 0.0)) continue;
    const Vec2 n = Vec2((b - a).y(), -(b - a).x()) / length;  // outward from edge.left
    const Eigen::Matrix2d& sigma = stress[static_cast<std::size_t>(edge.left)];
    ElementTerms& left = terms[static_cast<std::size_t>(edge.left)];
    if (!edge.on_boundary()) {
      // h_e ||[sigma n]||^2_e, half to each side
      const Vec2 jump_vector = (sigma - stress[static_cast<std::size_t>(edge.right)]) * n;
      const double value = length * length * jump_vector.squaredNorm();
      left.raw[jump] += 0.5 * value;
      terms[static_cast<std::size_t>(edge.right)].raw[jump] += 0.5 * value;
      continue;
    }
    const auto& fix = fixed[static_cast<std::size_t>(id)];
    if (fix[0] && fix[1]) continue;  // Gamma_1
    const Vec2 sn = sigma * n;
    if (is_contact[static_cast<std::size_t>(id)]) {
      // h_e ||t_c - sigma n||^2_e, t_c linear between the nodal tractions (a node that is not a
      // contact node, e.g. on Gamma_1, takes the other end's traction)
      const int i0 = node_of[static_cast<std::size_t>(edge.v0)];
      const int i1 = node_of[static_cast<std::size_t>(edge.v1)];
      Vec2 t0 = i0 >= 0 ? node_traction[static_cast<std::size_t>(i0)] : Vec2::Zero();
      Vec2 t1 = i1 >= 0 ? node_traction[static_cast<std::size_t>(i1)] : Vec2::Zero();
      if (i0 < 0 && i1 >= 0) t0 = t1;
      if (i1 < 0 && i0 >= 0) t1 = t0;
      const Vec2 tangent(-n.y(), n.x());
      double normal_part = 0.0, tangential_part = 0.0;
      for (std::size_t q = 0; q < gauss_points.size(); ++q) {
        const Vec2 r = (1.0 - gauss_points[q]) * t0 + gauss_points[q] * t1 - sn;
        normal_part += gauss_weights[q] * r.dot(n) * r.dot(n);
        tangential_part += gauss_weights[q] * r.dot(tangent) * r.dot(tangent);
      }
      const double scale = length * length;  // h_e times the edge's length (the rule's Jacobian)
      left.raw[contact] += scale * normal_part;
      left.raw[is_contact[static_cast<std::size_t>(id)] == 2 ? friction : contact] += scale * tangential_part;
      continue;
    }
    // Gamma_2: the loads on the edge (zero traction on a free edge), in the components that
    // no Dirichlet condition fixes
    double value = 0.0;
    for (std::size_t q = 0; q < gauss_points.size(); ++q) {
      const Vec2 x = (1.0 - gauss_points[q]) * a + gauss_points[q] * b;
      Vec2 f2 = Vec2::Zero();
      for (int k : loads[static_cast<std::size_t>(id)]) {
        const TractionLoad& load = elasticity.tractions[static_cast<std::size_t>(k)];
        if (load.traction) f2 += load.traction(x);
        if (load.pressure) f2 -= load.pressure(x) * n;
      }
      Vec2 r = f2 - sn;
      for (int c = 0; c < 2; ++c)
        if (fix[static_cast<std::size_t>(c)]) r(c) = 0.0;
      value += gauss_weights[q] * r.squaredNorm();
    }
    left.raw[traction] += length * length * value;
  }

  return sum_estimate(terms, start);
}

namespace detail {

ErrorEstimate sum_estimate(const std::vector<ElementTerms>& terms, std::chrono::steady_clock::time_point start) {
  ErrorEstimate out;
  out.constant = error_estimate_constant;
  out.indicators.assign(terms.size(), 0.0);
  std::array<double, part_count> part_sq{};
  double energy_sq = 0.0, norm_sq = 0.0;
  for (std::size_t e = 0; e < terms.size(); ++e) {
    const ElementTerms& t = terms[e];
    double eta_sq = 0.0;
    for (std::size_t k = 0; k < part_count; ++k) {
      const double share = k == stabilization ? 0.5 * t.raw[k] : t.weight * t.raw[k];
      part_sq[k] += share;
      eta_sq += share;
    }
    out.indicators[e] = std::sqrt(eta_sq);
    energy_sq += eta_sq;
    norm_sq += 0.5 * (t.consistency_energy + t.raw[stabilization]);
  }
  const auto& names = error_estimate_part_names();
  for (std::size_t k = 0; k < part_count; ++k) out.parts[names[k]] = std::sqrt(part_sq[k]);
  out.energy = std::sqrt(energy_sq);
  out.norm = std::sqrt(norm_sq);
  out.relative = out.norm > 0.0 ? out.energy / out.norm : (out.energy == 0.0 ? 0.0 : std::numeric_limits<double>::infinity());
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace detail

}  // namespace hemivem
