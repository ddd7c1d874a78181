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

#include "estimate_steps.hpp"

namespace hemivem {

namespace {

using namespace detail;

// The 3-point Gauss rule on [0, 1]: exact for polynomials of degree 5.
constexpr std::array<double, 3> gauss_points{0.5 - 0.3872983346207417, 0.5, 0.5 + 0.3872983346207417};
constexpr std::array<double, 3> gauss_weights{5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// h_E^2 ||f0 + div sigma(Pi u_h)||^2_E = h_E^2 ||f0||^2_E on element e (vertices z): a degree-2
// rule on the triangles (centroid, z_i, z_i+1).
double volume_residual(const Mesh& mesh, int e, const std::vector<Vec2>& z, const VectorField& body_force) {
  const int n = static_cast<int>(z.size());
  const Vec2 c = mesh.centroid(e);
  double integral = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec2& a = z[static_cast<std::size_t>(i)];
    const Vec2& b = z[static_cast<std::size_t>((i + 1) % n)];
    const double area = 0.5 * std::abs((a - c).x() * (b - c).y() - (a - c).y() * (b - c).x());
    for (const auto& [wa, wb] : {std::pair{1.0 / 6.0, 1.0 / 6.0}, std::pair{2.0 / 3.0, 1.0 / 6.0},
                                 std::pair{1.0 / 6.0, 2.0 / 3.0}})
      integral += area / 3.0 * body_force(c + wa * (a - c) + wb * (b - c)).squaredNorm();
  }
  return mesh.diameter(e) * mesh.diameter(e) * integral;
}

// Per element: Pi u_h, its stress, the volume residual and the stabilization term.
ElementResiduals<2> element_residuals(const ElasticityProblem& elasticity, const Eigen::VectorXd& u) {
  const Mesh& mesh = *elasticity.mesh;
  const int ne = mesh.num_elements();
  ElementResiduals<2> out;
  out.terms.resize(static_cast<std::size_t>(ne));
  out.stress.resize(static_cast<std::size_t>(ne));
  std::vector<Vec2> z;
  Eigen::VectorXd local;
  for (int e = 0; e < ne; ++e) {
    gather_element<2>(mesh, mesh.element(e), u, z, local);
    const Lame lame = elasticity.materials.lame(mesh.region(e));
    const LinearField field = project_p1(z, local);
    const Eigen::Matrix2d sigma = stress_of<2>(field.gradient, lame);
    out.stress[static_cast<std::size_t>(e)] = sigma;
    ElementTerms& t = out.terms[static_cast<std::size_t>(e)];
    t = element_base_terms<2>(mesh.area(e), sigma, field.gradient, lame);
    // S_E(u - Pi u, u - Pi u) = tau |(I - Pi) u|^2 with tau = 2 mu
    if (elasticity.stabilization == Stabilization::two_mu) {
      t.raw[stabilization] = 2.0 * lame.mu * nodal_defect<2>(z, local, field);
    } else {
      const VemElement element = vem_element(z, lame, elasticity.stabilization);
      t.raw[stabilization] = local.dot(element.stabilization * local);
    }
    if (elasticity.body_force) t.raw[volume] = volume_residual(mesh, e, z, elasticity.body_force);
  }
  return out;
}

// h_e ||t_c - sigma n||^2_e on a contact edge from a to b, t_c linear between the tractions at
// its ends (facet_tractions), into the contact part of `left`, and the tangential part into
// the friction part on an edge of a part with friction (`kind` 2).
void add_contact_residual(ElementTerms& left, const Vec2& a, const Vec2& b, const Vec2& n, const Vec2& sn,
                          const std::vector<Vec2>& tractions, char kind) {
  const Vec2& t0 = tractions[0];
  const Vec2& t1 = tractions[1];
  const Vec2 tangent(-n.y(), n.x());
  double normal_part = 0.0, tangential_part = 0.0;
  for (std::size_t q = 0; q < gauss_points.size(); ++q) {
    const Vec2 r = (1.0 - gauss_points[q]) * t0 + gauss_points[q] * t1 - sn;
    normal_part += gauss_weights[q] * r.dot(n) * r.dot(n);
    tangential_part += gauss_weights[q] * r.dot(tangent) * r.dot(tangent);
  }
  const double length = (b - a).norm();
  const double scale = length * length;  // h_e times the edge's length (the rule's Jacobian)
  left.raw[contact] += scale * normal_part;
  left.raw[kind == 2 ? friction : contact] += scale * tangential_part;
}

// h_e ||f2 - sigma n||^2_e on a Gamma_2 edge `id` from a to b, into the traction part of `left`.
void add_load_residual(ElementTerms& left, const ElasticityProblem& elasticity, const BoundaryFacets<2>& boundary, int id,
                       const Vec2& a, const Vec2& b, const Vec2& n, const Vec2& sn) {
  double value = 0.0;
  for (std::size_t q = 0; q < gauss_points.size(); ++q) {
    const Vec2 x = (1.0 - gauss_points[q]) * a + gauss_points[q] * b;
    value += gauss_weights[q] * load_residual<2>(elasticity.tractions, boundary.loads[static_cast<std::size_t>(id)], x, n, sn,
                                                 boundary.fixed[static_cast<std::size_t>(id)]);
  }
  const double length = (b - a).norm();
  left.raw[traction] += length * length * value;
}

// The terms of edge `id`: the jump on an interior edge, the contact residual on Gamma_3, the
// load residual on Gamma_2, nothing on Gamma_1.
void add_edge_terms(const Mesh& mesh, const ElasticityProblem& elasticity, const BoundaryFacets<2>& boundary, int id,
                    ElementResiduals<2>& elements, std::vector<Vec2>& tractions) {
  const MeshEdge& edge = mesh.edge(id);
  const Vec2 a = mesh.vertex(edge.v0);
  const Vec2 b = mesh.vertex(edge.v1);
  const double length = (b - a).norm();
  if (!(length > 0.0)) return;
  const Vec2 n = Vec2((b - a).y(), -(b - a).x()) / length;  // outward from edge.left
  if (!edge.on_boundary()) {
    add_jump<2>(elements.terms, elements.stress, edge.left, edge.right, n, length * length);
    return;
  }
  const auto& fix = boundary.fixed[static_cast<std::size_t>(id)];
  if (fix[0] && fix[1]) return;  // Gamma_1
  ElementTerms& left = elements.terms[static_cast<std::size_t>(edge.left)];
  const Vec2 sn = elements.stress[static_cast<std::size_t>(edge.left)] * n;
  if (const char kind = boundary.contact[static_cast<std::size_t>(id)]) {
    facet_tractions<2>(std::array<int, 2>{edge.v0, edge.v1}, boundary, tractions);
    add_contact_residual(left, a, b, n, sn, tractions, kind);
  } else {
    add_load_residual(left, elasticity, boundary, id, a, b, n, sn);
  }
}

}  // namespace

const std::vector<std::string>& error_estimate_part_names() {
  static const std::vector<std::string> names{"volume", "jump", "traction", "contact", "friction", "stabilization"};
  return names;
}

ErrorEstimate estimate_error(const ContactProblem& problem, const ContactSolution& solution) {
  const auto start = std::chrono::steady_clock::now();
  return sum_estimate(estimate_terms(problem, solution), start);
}

namespace detail {

std::vector<ElementTerms> estimate_terms(const ContactProblem& problem, const ContactSolution& solution) {
  const Mesh& mesh = checked_mesh<2>(problem, solution.u);
  ElementResiduals<2> elements = element_residuals(problem.elasticity, solution.u);
  const BoundaryFacets<2> boundary = boundary_facets<2>(problem, contact_parts(problem), solution, mesh.num_edges());
  std::vector<Vec2> tractions;
  for (int id = 0; id < mesh.num_edges(); ++id) add_edge_terms(mesh, problem.elasticity, boundary, id, elements, tractions);
  return std::move(elements.terms);
}

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
