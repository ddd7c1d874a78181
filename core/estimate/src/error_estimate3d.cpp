#include <hemivem/estimate/error_estimate3d.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <hemivem/error.hpp>
#include <hemivem/vem/element3d.hpp>
#include <hemivem/vem/quadrature3d.hpp>

#include "estimate_steps.hpp"

namespace hemivem {

namespace {

using namespace detail;

// Per cell: Pi u_h, its stress, the volume residual and the stabilization term.
ElementResiduals<3> element_residuals(const ElasticityProblem3D& elasticity, const Eigen::VectorXd& u) {
  const Mesh3D& mesh = *elasticity.mesh;
  const int nc = mesh.num_cells();
  ElementResiduals<3> out;
  out.terms.resize(static_cast<std::size_t>(nc));
  out.stress.resize(static_cast<std::size_t>(nc));
  std::vector<Vec3> z;
  Eigen::VectorXd local;
  for (int c = 0; c < nc; ++c) {
    gather_element<3>(mesh, mesh.cell_vertices(c), u, z, local);
    const auto faces = mesh.local_faces(c);
    const Lame lame = elasticity.materials.lame(mesh.region(c));
    const LinearField3 field = project_p1_3d(z, faces, local);
    const Eigen::Matrix3d sigma = stress_of<3>(field.gradient, lame);
    out.stress[static_cast<std::size_t>(c)] = sigma;
    ElementTerms& t = out.terms[static_cast<std::size_t>(c)];
    t = element_base_terms<3>(mesh.volume(c), sigma, field.gradient, lame);
    // S_E(u - Pi u, u - Pi u) = tau |(I - Pi) u|^2 with tau = 2 mu |E|^(1/3) (element3d.hpp)
    if (elasticity.stabilization == Stabilization::two_mu) {
      t.raw[stabilization] = 2.0 * lame.mu * std::cbrt(mesh.volume(c)) * nodal_defect<3>(z, local, field);
    } else {
      const VemElement3D element = vem_element_3d(z, faces, lame, elasticity.stabilization);
      t.raw[stabilization] = local.dot(element.stabilization * local);
    }
    // h_E^2 ||f0 + div sigma(Pi u_h)||^2_E = h_E^2 ||f0||^2_E
    if (elasticity.body_force)
      t.raw[volume] = mesh.diameter(c) * mesh.diameter(c) *
                      quadrature::integrate_cell(z, faces, [&](const Vec3& x) { return elasticity.body_force(x).squaredNorm(); });
  }
  return out;
}

// h_f ||t_c - sigma n||^2_f on a contact face f (vertices `loop`), t_c linear on the fan of
// triangles (face centroid, z_i, z_i+1) between the tractions at the vertices
// (facet_tractions) and their mean at the centroid, into the contact part of `inner`.
void add_contact_residual(ElementTerms& inner, const Mesh3D& mesh, int f, const std::vector<Vec3>& loop, double hf,
                          const Vec3& sn, const std::vector<Vec3>& traction_at) {
  Vec3 center_traction = Vec3::Zero();
  for (const Vec3& t : traction_at) center_traction += t;
  center_traction /= static_cast<double>(loop.size());
  const Vec3 fc = mesh.face_centroid(f);
  double value = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const std::size_t j = (i + 1) % loop.size();
    const Vec3 a = loop[i], b = loop[j], ta = traction_at[i], tb = traction_at[j];
    // the linear interpolant on (fc, a, b) from its barycentric coordinates
    const Vec3 e1 = a - fc, e2 = b - fc;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
    if (!(det > 0.0)) continue;
    value += quadrature::integrate_triangle_3d(fc, a, b, [&](const Vec3& x) {
      const Vec3 r = x - fc;
      const double r1 = r.dot(e1), r2 = r.dot(e2);
      const double la = (d22 * r1 - d12 * r2) / det, lb = (d11 * r2 - d12 * r1) / det;
      return ((1.0 - la - lb) * center_traction + la * ta + lb * tb - sn).squaredNorm();
    });
  }
  inner.raw[contact] += hf * value;
}

// h_f ||f2 - sigma n||^2_f on a Gamma_2 face f (vertices `loop`), into the traction part of `inner`.
void add_load_residual(ElementTerms& inner, const ElasticityProblem3D& elasticity, const BoundaryFacets<3>& boundary, int f,
                       const std::vector<Vec3>& loop, double hf, const Vec3& normal, const Vec3& sn) {
  const auto& on_face = boundary.loads[static_cast<std::size_t>(f)];
  const auto& fix = boundary.fixed[static_cast<std::size_t>(f)];
  const double value = quadrature::integrate_polygon_3d(std::span<const Vec3>(loop), [&](const Vec3& x) {
    return load_residual<3>(elasticity.tractions, on_face, x, normal, sn, fix);
  });
  inner.raw[traction] += hf * value;
}

// The terms of face f: the jump on an interior face, the contact residual on Gamma_3, the load
// residual on Gamma_2, nothing on Gamma_1.
void add_face_terms(const Mesh3D& mesh, const ElasticityProblem3D& elasticity, const BoundaryFacets<3>& boundary, int f,
                    ElementResiduals<3>& elements, std::vector<Vec3>& loop, std::vector<Vec3>& tractions) {
  const MeshFace& face = mesh.face(f);
  loop.clear();
  for (int v : face.vertices) loop.push_back(mesh.vertex(v));
  const double area = mesh.face_area(f);
  if (!(area > 0.0)) return;
  const double hf = std::sqrt(area);  // the face's size |f|^(1/2), as an edge's length in the plane
  const Vec3 normal = mesh.face_normal(f);  // out of face.inner
  if (!face.on_boundary()) {
    add_jump<3>(elements.terms, elements.stress, face.inner, face.outer, normal, hf * area);
    return;
  }
  const auto& fix = boundary.fixed[static_cast<std::size_t>(f)];
  if (fix[0] && fix[1] && fix[2]) return;  // Gamma_1
  ElementTerms& inner = elements.terms[static_cast<std::size_t>(face.inner)];
  const Vec3 sn = elements.stress[static_cast<std::size_t>(face.inner)] * normal;
  if (boundary.contact[static_cast<std::size_t>(f)]) {
    facet_tractions<3>(face.vertices, boundary, tractions);
    add_contact_residual(inner, mesh, f, loop, hf, sn, tractions);
  } else {
    add_load_residual(inner, elasticity, boundary, f, loop, hf, normal, sn);
  }
}

}  // namespace

ErrorEstimate estimate_error(const ContactProblem3D& problem, const ContactSolution3D& solution) {
  const auto start = std::chrono::steady_clock::now();
  return sum_estimate(estimate_terms(problem, solution), start);
}

namespace detail {

std::vector<ElementTerms> estimate_terms(const ContactProblem3D& problem, const ContactSolution3D& solution) {
  const Mesh3D& mesh = checked_mesh<3>(problem, solution.u);
  ElementResiduals<3> elements = element_residuals(problem.elasticity, solution.u);
  const BoundaryFacets<3> boundary = boundary_facets<3>(problem, problem.parts, solution, mesh.num_faces());
  std::vector<Vec3> loop;
  std::vector<Vec3> tractions;
  for (int f = 0; f < mesh.num_faces(); ++f)
    add_face_terms(mesh, problem.elasticity, boundary, f, elements, loop, tractions);
  return std::move(elements.terms);
}

}  // namespace detail

}  // namespace hemivem
