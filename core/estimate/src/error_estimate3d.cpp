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

#include "estimate_terms.hpp"

namespace hemivem {

namespace {

using namespace detail;

double polygon_diameter(std::span<const Vec3> z) {
  double d = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i)
    for (std::size_t j = i + 1; j < z.size(); ++j) d = std::max(d, (z[i] - z[j]).norm());
  return d;
}

void check_face_ids(const std::vector<int>& faces, int nfaces, const char* what) {
  for (int f : faces)
    if (f < 0 || f >= nfaces)
      throw InputError(std::string("estimate_error: a ") + what + " face id (" + std::to_string(f) + ") is out of range");
}

}  // namespace

ErrorEstimate estimate_error(const ContactProblem3D& problem, const ContactSolution3D& solution) {
  const auto start = std::chrono::steady_clock::now();
  const ElasticityProblem3D& elasticity = problem.elasticity;
  if (elasticity.mesh == nullptr) throw InputError("estimate_error: the problem has no mesh");
  const Mesh3D& mesh = *elasticity.mesh;
  const int nv = mesh.num_vertices();
  const int nc = mesh.num_cells();
  const int nfaces = mesh.num_faces();
  if (solution.u.size() != 3 * static_cast<Eigen::Index>(nv))
    throw InputError("estimate_error: the solution has " + std::to_string(solution.u.size()) +
                     " displacement entries, the mesh " + std::to_string(nv) + " vertices (3 entries per vertex expected)");
  const Eigen::VectorXd& u = solution.u;

  // ---- per cell: Pi u_h, its stress, the volume residual and the stabilization term ----
  std::vector<ElementTerms> terms(static_cast<std::size_t>(nc));
  std::vector<Eigen::Matrix3d> stress(static_cast<std::size_t>(nc));
  std::vector<Vec3> z;
  Eigen::VectorXd local;
  for (int c = 0; c < nc; ++c) {
    const auto& vertices = mesh.cell_vertices(c);
    const auto n = static_cast<Eigen::Index>(vertices.size());
    z.resize(vertices.size());
    local.resize(3 * n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const int v = vertices[static_cast<std::size_t>(i)];
      z[static_cast<std::size_t>(i)] = mesh.vertex(v);
      local.segment<3>(3 * i) = u.segment<3>(3 * static_cast<Eigen::Index>(v));
    }
    const auto faces = mesh.local_faces(c);
    const Lame lame = elasticity.materials.lame(mesh.region(c));
    const LinearField3 field = project_p1_3d(z, faces, local);
    const Eigen::Matrix3d sigma = stress_3d(field.gradient, lame);
    stress[static_cast<std::size_t>(c)] = sigma;
    const Eigen::Matrix3d eps = 0.5 * (field.gradient + field.gradient.transpose());
    ElementTerms& t = terms[static_cast<std::size_t>(c)];
    t.consistency_energy = mesh.volume(c) * sigma.cwiseProduct(eps).sum();
    t.weight = error_estimate_constant / (2.0 * lame.mu);

    // S_E(u - Pi u, u - Pi u): tau |(I - Pi) u|^2 with tau = 2 mu |E|^(1/3) (element3d.hpp)
    if (elasticity.stabilization == Stabilization::two_mu) {
      double s = 0.0;
      for (Eigen::Index i = 0; i < n; ++i)
        s += (local.segment<3>(3 * i) - field(z[static_cast<std::size_t>(i)])).squaredNorm();
      t.raw[stabilization] = 2.0 * lame.mu * std::cbrt(mesh.volume(c)) * s;
    } else {
      const VemElement3D element = vem_element_3d(z, faces, lame, elasticity.stabilization);
      t.raw[stabilization] = local.dot(element.stabilization * local);
    }

    // h_E^2 ||f0 + div sigma(Pi u_h)||^2_E = h_E^2 ||f0||^2_E
    if (elasticity.body_force)
      t.raw[volume] = mesh.diameter(c) * mesh.diameter(c) *
                      quadrature::integrate_cell(z, faces, [&](const Vec3& x) { return elasticity.body_force(x).squaredNorm(); });
  }

  // ---- what each boundary face is ----
  std::vector<std::array<bool, 3>> fixed(static_cast<std::size_t>(nfaces), {false, false, false});
  for (const DirichletCondition3D& d : elasticity.dirichlet) {
    check_face_ids(d.faces, nfaces, "Dirichlet");
    for (int f : d.faces)
      for (std::size_t k = 0; k < 3; ++k) fixed[static_cast<std::size_t>(f)][k] |= d.fix[k];
  }
  std::vector<std::vector<int>> loads(static_cast<std::size_t>(nfaces));
  for (std::size_t k = 0; k < elasticity.tractions.size(); ++k) {
    check_face_ids(elasticity.tractions[k].faces, nfaces, "traction");
    for (int f : elasticity.tractions[k].faces) loads[static_cast<std::size_t>(f)].push_back(static_cast<int>(k));
  }
  const std::vector<int> contact_face_ids = contact_faces(problem);
  check_face_ids(contact_face_ids, nfaces, "contact");
  std::vector<char> is_contact(static_cast<std::size_t>(nfaces), 0);
  for (int f : contact_face_ids) is_contact[static_cast<std::size_t>(f)] = 1;
  // the traction t_i = -p_i nu_i of each contact node
  std::vector<int> node_of(static_cast<std::size_t>(nv), -1);
  std::vector<Vec3> node_traction(solution.contact.size(), Vec3::Zero());
  for (std::size_t i = 0; i < solution.contact.size(); ++i) {
    const ContactNode3D& node = solution.contact[i];
    if (node.vertex < 0 || node.vertex >= nv)
      throw InputError("estimate_error: contact node " + std::to_string(i) + " names vertex " +
                       std::to_string(node.vertex) + ", outside the mesh");
    node_of[static_cast<std::size_t>(node.vertex)] = static_cast<int>(i);
    if (node.weight > 0.0) node_traction[i] = -node.pressure() * node.normal;
  }

  // ---- faces ----
  std::vector<Vec3> loop;
  std::vector<Vec3> traction_at;
  for (int f = 0; f < nfaces; ++f) {
    const MeshFace& face = mesh.face(f);
    loop.clear();
    for (int v : face.vertices) loop.push_back(mesh.vertex(v));
    const double area = mesh.face_area(f);
    if (!(area > 0.0)) continue;
    const double hf = polygon_diameter(loop);
    const Vec3 normal = mesh.face_normal(f);  // out of face.inner
    const Eigen::Matrix3d& sigma = stress[static_cast<std::size_t>(face.inner)];
    ElementTerms& inner = terms[static_cast<std::size_t>(face.inner)];
    if (!face.on_boundary()) {
      // h_f ||[sigma n]||^2_f, half to each side
      const double value = hf * area * ((sigma - stress[static_cast<std::size_t>(face.outer)]) * normal).squaredNorm();
      inner.raw[jump] += 0.5 * value;
      terms[static_cast<std::size_t>(face.outer)].raw[jump] += 0.5 * value;
      continue;
    }
    const auto& fix = fixed[static_cast<std::size_t>(f)];
    if (fix[0] && fix[1] && fix[2]) continue;  // Gamma_1
    const Vec3 sn = sigma * normal;
    if (is_contact[static_cast<std::size_t>(f)]) {
      // h_f ||t_c - sigma n||^2_f; a vertex that is not a contact node (on Gamma_1) takes the
      // mean of the face's contact nodes
      traction_at.assign(loop.size(), Vec3::Zero());
      Vec3 mean = Vec3::Zero();
      int count = 0;
      for (std::size_t i = 0; i < loop.size(); ++i)
        if (const int k = node_of[static_cast<std::size_t>(face.vertices[i])]; k >= 0) {
          traction_at[i] = node_traction[static_cast<std::size_t>(k)];
          mean += traction_at[i];
          ++count;
        }
      if (count > 0) mean /= static_cast<double>(count);
      for (std::size_t i = 0; i < loop.size(); ++i)
        if (node_of[static_cast<std::size_t>(face.vertices[i])] < 0) traction_at[i] = mean;
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
      continue;
    }
    // Gamma_2: the loads on the face (zero traction on a free face), in the components that no
    // Dirichlet condition fixes
    const auto& on_face = loads[static_cast<std::size_t>(f)];
    const double value = quadrature::integrate_polygon_3d(std::span<const Vec3>(loop), [&](const Vec3& x) {
      Vec3 f2 = Vec3::Zero();
      for (int k : on_face) {
        const TractionLoad3D& load = elasticity.tractions[static_cast<std::size_t>(k)];
        if (load.traction) f2 += load.traction(x);
        if (load.pressure) f2 -= load.pressure(x) * normal;
      }
      Vec3 r = f2 - sn;
      for (int k = 0; k < 3; ++k)
        if (fix[static_cast<std::size_t>(k)]) r(k) = 0.0;
      return r.squaredNorm();
    });
    inner.raw[traction] += hf * value;
  }
  return sum_estimate(terms, start);
}

}  // namespace hemivem
