#include <hemivem/error.hpp>
#include <hemivem/vem/element3d.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <string>

namespace hemivem {

Eigen::Matrix<double, 6, 6> elasticity_matrix_3d(const Lame& l) {
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  C.topLeftCorner<3, 3>().setConstant(l.lambda);
  C.topLeftCorner<3, 3>().diagonal().array() += 2 * l.mu;
  C.bottomRightCorner<3, 3>().diagonal().setConstant(l.mu);
  return C;
}

namespace {

/// Geometry of one planar face: its area vector |f| n_f, its area, its vertex mean and the shift
/// c_f - zbar_f from the vertex mean to the area centroid. The shift is kept apart from the
/// mean (c_f itself is never formed), so that it carries no round-off of the face's position.
struct FaceGeometry {
  Vec3 area_vector = Vec3::Zero();
  double area = 0.0;
  Vec3 mean = Vec3::Zero();
  Vec3 shift = Vec3::Zero();
};

/// The geometry of the face whose i-th vertex is at(i), for i < n. Callers pass coordinates
/// relative to a nearby point (a vertex of the cell), so that round-off is relative to the size
/// of the cell, not to its distance from the origin.
template <class At>
FaceGeometry face_geometry(std::size_t n, const At& at) {
  FaceGeometry g;
  for (std::size_t i = 0; i < n; ++i) g.mean += at(i);
  g.mean /= static_cast<double>(n);
  // area vector of the fan of triangles (zbar, z_i, z_{i+1})
  for (std::size_t i = 0; i < n; ++i) g.area_vector += (at(i) - g.mean).cross(at((i + 1) % n) - g.mean);
  g.area_vector *= 0.5;
  g.area = g.area_vector.norm();
  if (!(g.area > 0.0)) throw MeshError("a face of zero area", -1);
  const Vec3 normal = g.area_vector / g.area;
  // centroid of the fan, with the triangles' areas signed along the normal (a non-convex face
  // has triangles of negative area when its vertex mean lies outside it)
  Vec3 moment = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = at(i) - g.mean, b = at((i + 1) % n) - g.mean;
    moment += 0.5 * a.cross(b).dot(normal) * (a + b) / 3.0;
  }
  g.shift = moment / g.area;
  return g;
}

/// omega_i = |f|/n + nu_i . (c_f - zbar_f), nu_i = (m_{i-1} + m_i)/2, m_i = (z_{i+1} - z_i) x n_f.
/// Calls weight(i, omega_i) for each vertex.
template <class At, class Weight>
void face_weights_of(std::size_t n, const At& at, const FaceGeometry& g, const Weight& weight) {
  const Vec3 normal = g.area_vector / g.area;
  // nu_i . shift = ((z_{i+1} - z_{i-1}) x n_f) . shift / 2
  const Vec3 t = normal.cross(g.shift);  // (d x n) . s = d . (n x s)
  const double base = g.area / static_cast<double>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = at((i + 1) % n) - at((i + n - 1) % n);
    weight(i, base + 0.5 * d.dot(t));
  }
}

/// Everything the projection needs on one cell.
struct CellOperators {
  Eigen::MatrixXd B;   // 6 x 3n projected strain
  Eigen::MatrixXd R;   // 3n x 6 rigid motions at the vertices (centred at the vertex mean)
  Eigen::MatrixXd Ds;  // 3n x 6 strain modes at the vertices
  Eigen::Matrix3Xd N;  // column i: sum over the faces at z_i of omega_i^f n_f
  Eigen::Matrix3Xd r;  // column i: z_i - vertex mean
  Vec3 mean = Vec3::Zero();
  double volume = 0.0;
};

/// The scaled normals N_i = sum_{f ni z_i} omega_i^f n_f (so that sum_f (int_f v) (x) n_f =
/// sum_i v_i (x) N_i), the volume and the vertex mean of a cell, after checking its input. The
/// geometry is computed in coordinates relative to the first vertex: a cell far from the origin
/// loses no more digits than its vertices' coordinates already have.
CellOperators cell_geometry(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces) {
  const std::size_t n = z.size();
  if (n < 4) throw InputError("a polyhedral virtual element needs at least 4 vertices, got " + std::to_string(n));
  if (faces.size() < 4)
    throw InputError("a polyhedral virtual element needs at least 4 faces, got " + std::to_string(faces.size()));
  std::vector<char> used(n, 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3)
      throw InputError("face " + std::to_string(f) + " of a cell has " + std::to_string(face.size()) +
                       " vertices; a face needs at least 3");
    for (int v : face) {
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw InputError("face " + std::to_string(f) + " of a cell names vertex " + std::to_string(v) + " of " +
                         std::to_string(n));
      used[static_cast<std::size_t>(v)] = 1;
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!used[i]) throw InputError("vertex " + std::to_string(i) + " of a cell is on none of its faces");

  CellOperators c;
  const Eigen::Index cols = static_cast<Eigen::Index>(n);
  c.r.resize(3, cols);
  for (Eigen::Index i = 0; i < cols; ++i) c.r.col(i) = z[static_cast<std::size_t>(i)] - z[0];
  const Vec3 local_mean = c.r.rowwise().mean();
  c.r.colwise() -= local_mean;
  c.mean = z[0] + local_mean;
  c.N.setZero(3, cols);
  double six_volume = 0.0;
  for (const auto& face : faces) {
    const auto at = [&](std::size_t i) -> Vec3 { return c.r.col(face[i]); };
    const FaceGeometry g = face_geometry(face.size(), at);
    // divergence theorem: |E| = (1/3) sum_f int_f (x - x0) . n_f = (1/3) sum_f (c_f - x0) . (|f| n_f),
    // x0 the vertex mean of the cell (the origin of the coordinates r)
    six_volume += 2.0 * (g.mean + g.shift).dot(g.area_vector);
    const Vec3 normal = g.area_vector / g.area;
    face_weights_of(face.size(), at, g, [&](std::size_t i, double w) {
      c.N.col(face[i]) += w * normal;
    });
  }
  c.volume = six_volume / 6.0;
  if (!(c.volume > 0.0)) throw MeshError("cell has non-positive volume (are its faces oriented outward?)", -1);
  return c;
}

CellOperators build(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces) {
  CellOperators c = cell_geometry(z, faces);
  const Eigen::Index n = static_cast<Eigen::Index>(z.size());
  c.B.setZero(6, 3 * n);
  c.R.setZero(3 * n, 6);
  c.Ds.setZero(3 * n, 6);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 a = c.N.col(i) / c.volume;
    const Eigen::Index x = 3 * i, y = 3 * i + 1, w = 3 * i + 2;
    // eps_xx, eps_yy, eps_zz, 2 eps_yz, 2 eps_xz, 2 eps_xy of v_i (x) a
    c.B(0, x) = a.x();
    c.B(1, y) = a.y();
    c.B(2, w) = a.z();
    c.B(3, y) = a.z();
    c.B(3, w) = a.y();
    c.B(4, x) = a.z();
    c.B(4, w) = a.x();
    c.B(5, x) = a.y();
    c.B(5, y) = a.x();

    const Vec3 r = c.r.col(i);
    // translations, then rotations omega x r about x, y, z
    c.R(x, 0) = c.R(y, 1) = c.R(w, 2) = 1.0;
    c.R(y, 3) = -r.z();
    c.R(w, 3) = r.y();
    c.R(x, 4) = r.z();
    c.R(w, 4) = -r.x();
    c.R(x, 5) = -r.y();
    c.R(y, 5) = r.x();
    // the fields whose Voigt strain is the unit vector e_k (engineering shear)
    c.Ds(x, 0) = r.x();
    c.Ds(y, 1) = r.y();
    c.Ds(w, 2) = r.z();
    c.Ds(y, 3) = 0.5 * r.z();
    c.Ds(w, 3) = 0.5 * r.y();
    c.Ds(x, 4) = 0.5 * r.z();
    c.Ds(w, 4) = 0.5 * r.x();
    c.Ds(x, 5) = 0.5 * r.y();
    c.Ds(y, 5) = 0.5 * r.x();
  }
  return c;
}

/// The rigid-motion coefficients rho = (R^T R)^{-1} R^T w. Centring at the vertex mean makes
/// R^T R block diagonal: n I for the translations and the inertia tensor
/// sum_i (|r_i|^2 I - r_i r_i^T) of the vertices for the rotations (positive definite unless the
/// vertices are collinear).
struct RigidSolver {
  double inv_n = 0.0;
  Eigen::LLT<Eigen::Matrix3d> inertia;
  explicit RigidSolver(const CellOperators& c) : inv_n(1.0 / static_cast<double>(c.N.cols())) {
    const Eigen::Matrix3d J =
        c.r.colwise().squaredNorm().sum() * Eigen::Matrix3d::Identity() - c.r * c.r.transpose();
    inertia.compute(J);
    if (inertia.info() != Eigen::Success) throw MeshError("cell whose vertices are collinear", -1);
  }
  /// (R^T R)^{-1} applied to the columns of M (6 x k).
  Eigen::MatrixXd apply(const Eigen::MatrixXd& M) const {
    Eigen::MatrixXd out(6, M.cols());
    out.topRows<3>() = inv_n * M.topRows<3>();
    out.bottomRows<3>() = inertia.solve(M.bottomRows<3>());
    return out;
  }
};

struct ElementMatrices {
  CellOperators c;
  Eigen::MatrixXd projection, consistency, stabilization;
  double tau = 0.0;
};

ElementMatrices element_matrices(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces,
                                 const Lame& lame, Stabilization stabilization) {
  ElementMatrices m{build(z, faces), {}, {}, {}, 0.0};
  const CellOperators& c = m.c;
  const Eigen::Index n3 = c.B.cols();
  // Pi = R (R^T R)^{-1} R^T (I - Ds B) + Ds B
  const RigidSolver rigid(c);
  const Eigen::MatrixXd DsB = c.Ds * c.B;
  const Eigen::MatrixXd RtI = rigid.apply(c.R.transpose());
  m.projection = c.R * (RtI - RtI * DsB) + DsB;
  m.consistency = (c.volume * c.B.transpose()) * elasticity_matrix_3d(lame) * c.B;
  m.tau = stabilization == Stabilization::two_mu ? 2.0 * lame.mu * std::cbrt(c.volume)
                                                 : m.consistency.trace() / static_cast<double>(n3);
  const Eigen::MatrixXd IminusPi = Eigen::MatrixXd::Identity(n3, n3) - m.projection;
  m.stabilization = m.tau * (IminusPi.transpose() * IminusPi);
  return m;
}

}  // namespace

Eigen::VectorXd face_weights(std::span<const Vec3> face) {
  const std::size_t n = face.size();
  if (n < 3) throw InputError("a face needs at least 3 vertices, got " + std::to_string(n));
  const auto at = [&](std::size_t i) -> Vec3 { return face[i] - face[0]; };
  const FaceGeometry g = face_geometry(n, at);
  Eigen::VectorXd w(static_cast<Eigen::Index>(n));
  face_weights_of(n, at, g, [&](std::size_t i, double omega) { w(static_cast<Eigen::Index>(i)) = omega; });
  return w;
}

VemElement3D vem_element_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                            const Lame& lame, Stabilization stabilization) {
  ElementMatrices m = element_matrices(vertices, faces, lame, stabilization);
  VemElement3D el;
  el.volume = m.c.volume;
  el.vertex_mean = m.c.mean;
  el.strain = std::move(m.c.B);
  el.projection = std::move(m.projection);
  el.consistency = std::move(m.consistency);
  el.stabilization = std::move(m.stabilization);
  el.tau = m.tau;
  return el;
}

void element_stiffness_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                          const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K) {
  const ElementMatrices m = element_matrices(vertices, faces, lame, stabilization);
  K = m.consistency + m.stabilization;
}

namespace {

void check_values(std::span<const Vec3> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (v.size() != 3 * static_cast<Eigen::Index>(z.size()))
    throw InternalError("local values of size " + std::to_string(v.size()) + " for a cell of " +
                        std::to_string(z.size()) + " vertices");
}

}  // namespace

LinearField3 project_p1_3d(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces,
                           const Eigen::Ref<const Eigen::VectorXd>& v) {
  check_values(z, v);
  const CellOperators c = build(z, faces);
  const RigidSolver rigid(c);
  const Eigen::Matrix<double, 6, 1> eps = c.B * v;
  const Eigen::Matrix<double, 6, 1> rho = rigid.apply(c.R.transpose() * (v - c.Ds * eps));
  LinearField3 f;
  f.center = c.mean;
  f.value = rho.head<3>();
  // symmetric part from the Voigt strain, skew part from the rotation vector (omega x r)
  f.gradient << eps(0), 0.5 * eps(5) - rho(5), 0.5 * eps(4) + rho(4),  //
      0.5 * eps(5) + rho(5), eps(1), 0.5 * eps(3) - rho(3),            //
      0.5 * eps(4) - rho(4), 0.5 * eps(3) + rho(3), eps(2);
  return f;
}

LinearField3 project_gradient_3d(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces,
                                 const Eigen::Ref<const Eigen::VectorXd>& v) {
  check_values(z, v);
  const CellOperators c = cell_geometry(z, faces);
  LinearField3 f;
  f.center = c.mean;
  for (Eigen::Index i = 0; i < c.N.cols(); ++i) {
    const Vec3 vi = v.segment<3>(3 * i);
    f.value += vi;
    f.gradient += vi * c.N.col(i).transpose();
  }
  f.value /= static_cast<double>(c.N.cols());
  f.gradient /= c.volume;
  return f;
}

}  // namespace hemivem
