#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/quadrature3d.hpp>
#include <hemivem/error.hpp>

#include "element_loop.hpp"
#include "load_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace hemivem {

Eigen::Matrix3Xd face_vertex_normals(std::span<const Vec3> z) {
  const std::size_t n = z.size();
  const Vec3 area = polygon_area_vector(z);
  const Vec3 normal = area / scale_free_norm(area);
  Eigen::Matrix3Xd nu = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 m = (z[(i + 1) % n] - z[i]).cross(normal);  // |e| times the edge's outward normal in the plane
    nu.col(static_cast<Eigen::Index>(i)) += 0.5 * m;
    nu.col(static_cast<Eigen::Index>((i + 1) % n)) += 0.5 * m;
  }
  return nu;
}

namespace {

using quadrature::integrate_cell;
using quadrature::integrate_triangle_3d;

void gather(const Mesh3D& mesh, int c, std::vector<Vec3>& z) {
  z.clear();
  for (int v : mesh.cell_vertices(c)) z.push_back(mesh.vertex(v));
}

std::vector<Vec3> face_points(const Mesh3D& mesh, int f) {
  std::vector<Vec3> z;
  for (int v : mesh.face(f).vertices) z.push_back(mesh.vertex(v));
  return z;
}

}  // namespace

void detail::cell_body_load(const Mesh3D& mesh, int c, const VectorField3& body_force, const LoadTerms& add) {
  thread_local std::vector<Vec3> z;
  thread_local Eigen::VectorXd unit;
  gather(mesh, c, z);
  const auto faces = mesh.local_faces(c);
  const auto n3 = static_cast<Eigen::Index>(3 * z.size());
  unit.setZero(n3);
  // the load of local basis function k is int f0 . Pi^nabla_1 phi_k
  const LinearField3 first = [&] {
    unit(0) = 1.0;
    auto p = project_gradient_3d(z, faces, unit);
    unit(0) = 0.0;
    return p;
  }();
  const Vec3 center = first.center;
  const Vec3 F0 = integrate_cell(z, faces, [&](const Vec3& x) { return body_force(x); });
  const Eigen::Matrix3d M =
      integrate_cell(z, faces, [&](const Vec3& x) -> Eigen::Matrix3d { return body_force(x) * (x - center).transpose(); });
  const auto& verts = mesh.cell_vertices(c);
  for (Eigen::Index k = 0; k < n3; ++k) {
    unit(k) = 1.0;
    const LinearField3 phi = project_gradient_3d(z, faces, unit);
    unit(k) = 0.0;
    add(3 * verts[static_cast<std::size_t>(k / 3)] + static_cast<int>(k % 3),
        F0.dot(phi.value) + M.cwiseProduct(phi.gradient).sum());
  }
}

void detail::facet_traction_load(const Mesh3D& mesh, const TractionLoad3D& load, int id, const LoadTerms& add) {
  if (id < 0 || id >= mesh.num_faces()) throw InputError("traction face id " + std::to_string(id) + " out of range");
  if (!mesh.face(id).on_boundary()) throw InputError("traction face " + std::to_string(id) + " is not on the boundary");
  const auto z = face_points(mesh, id);
  const Vec3 normal = mesh.face_normal(id);
  auto t = [&](const Vec3& x) {
    Vec3 v = load.traction ? load.traction(x) : Vec3::Zero();
    if (load.pressure) v -= load.pressure(x) * normal;
    return v;
  };
  Vec3 zbar = Vec3::Zero();
  for (const Vec3& p : z) zbar += p;
  zbar /= static_cast<double>(z.size());
  // T0 = int_f t, T1 = int_f t (x - zbar)^T on the fan from the centroid
  const Vec3 fc = mesh.face_centroid(id);
  Vec3 T0 = Vec3::Zero();
  Eigen::Matrix3d T1 = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec3& a = z[i];
    const Vec3& b = z[(i + 1) % z.size()];
    T0 += integrate_triangle_3d(fc, a, b, t);
    T1 += integrate_triangle_3d(fc, a, b, [&](const Vec3& x) -> Eigen::Matrix3d { return t(x) * (x - zbar).transpose(); });
  }
  // T1 nu_i / |f| with nu_i and |f| scaled by 2^(-k), 2^k about the face's size: T1 nu_i (a
  // fourth power of lengths) may leave the range of doubles where T1 nu_i / |f| does not; the
  // scaling changes no bit of a result that stays in range
  const int k = std::ilogb(mesh.face_area(id)) / 2;
  const Eigen::Matrix3Xd nu = std::ldexp(1.0, -k) * face_vertex_normals(z);
  const double area = std::ldexp(mesh.face_area(id), -k);
  const auto& loop = mesh.face(id).vertices;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const Vec3 term = T0 / static_cast<double>(loop.size()) + T1 * nu.col(static_cast<Eigen::Index>(i)) / area;
    for (int c = 0; c < 3; ++c) add(3 * loop[i] + c, term(c));
  }
}

std::vector<LinearField3> project_solution(const Mesh3D& mesh, const Eigen::VectorXd& u) {
  if (u.size() != 3 * mesh.num_vertices())
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries, expected " +
                     std::to_string(3 * mesh.num_vertices()));
  std::vector<LinearField3> out(static_cast<std::size_t>(mesh.num_cells()));
  std::vector<Vec3> z;
  Eigen::VectorXd local;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    gather(mesh, c, z);
    const auto& verts = mesh.cell_vertices(c);
    local.resize(3 * static_cast<Eigen::Index>(verts.size()));
    for (std::size_t i = 0; i < verts.size(); ++i) local.segment<3>(3 * static_cast<Eigen::Index>(i)) = u.segment<3>(3 * verts[i]);
    out[static_cast<std::size_t>(c)] = project_p1_3d(z, mesh.local_faces(c), local);
  }
  return out;
}

}  // namespace hemivem
