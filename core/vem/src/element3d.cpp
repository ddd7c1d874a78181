#include <hemivem/error.hpp>
#include <hemivem/vem/element3d.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

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
  for (std::size_t i = 0; i < n; ++i) g.area_vector += (at(i) - g.mean).cross(at(i + 1 < n ? i + 1 : 0) - g.mean);
  g.area_vector *= 0.5;
  g.area = scale_free_norm(g.area_vector);
  if (!(g.area > 0.0)) throw MeshError("a face of zero area", -1);
  const Vec3 normal = g.area_vector / g.area;
  // centroid of the fan, with the triangles' areas signed along the normal (a non-convex face
  // has triangles of negative area when its vertex mean lies outside it)
  Vec3 moment = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = at(i) - g.mean, b = at(i + 1 < n ? i + 1 : 0) - g.mean;
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
    const Vec3 d = at(i + 1 < n ? i + 1 : 0) - at(i > 0 ? i - 1 : n - 1);
    weight(i, base + 0.5 * d.dot(t));
  }
}

/// Throws InputError unless the cell has at least 4 vertices and 4 faces, each face at least 3
/// vertices, every position in range and every vertex on a face. `used` is scratch.
void check_cell(std::size_t n, const std::vector<std::vector<int>>& faces, std::vector<char>& used) {
  if (n < 4) throw InputError("a polyhedral virtual element needs at least 4 vertices, got " + std::to_string(n));
  if (faces.size() < 4)
    throw InputError("a polyhedral virtual element needs at least 4 faces, got " + std::to_string(faces.size()));
  used.assign(n, 0);
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
}

/// The geometry of a cell: r_i = z_i - vertex mean, the scaled normals
/// N_i = sum_{f ni z_i} omega_i^f n_f (so that sum_f (int_f v) (x) n_f = sum_i v_i (x) N_i), the
/// vertex mean and the volume. Its vectors keep their capacity from cell to cell.
struct CellGeometry {
  std::vector<Vec3> r;
  std::vector<Vec3> N;
  Vec3 mean = Vec3::Zero();
  double volume = 0.0;
  std::vector<char> used;  // scratch of check_cell
};

/// The geometry of a cell, after checking its input. It is computed in coordinates relative to
/// the first vertex: a cell far from the origin loses no more digits than its vertices'
/// coordinates already have (and a translated copy of a cell, whose vertices differ from the
/// first by the same vectors, gets the same r, N and volume).
void cell_geometry(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces, CellGeometry& g) {
  const std::size_t n = z.size();
  check_cell(n, faces, g.used);
  g.r.resize(n);
  g.N.assign(n, Vec3::Zero());
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    g.r[i] = z[i] - z[0];
    sum += g.r[i];
  }
  const Vec3 local_mean = sum / static_cast<double>(n);
  for (Vec3& r : g.r) r -= local_mean;
  g.mean = z[0] + local_mean;
  double six_volume = 0.0;
  for (const auto& face : faces) {
    const auto at = [&](std::size_t i) -> Vec3 { return g.r[static_cast<std::size_t>(face[i])]; };
    const FaceGeometry f = face_geometry(face.size(), at);
    // divergence theorem: |E| = (1/3) sum_f int_f (x - x0) . n_f = (1/3) sum_f (c_f - x0) . (|f| n_f),
    // x0 the vertex mean of the cell (the origin of the coordinates r)
    six_volume += 2.0 * (f.mean + f.shift).dot(f.area_vector);
    const Vec3 normal = f.area_vector / f.area;
    face_weights_of(face.size(), at, f, [&](std::size_t i, double w) {
      g.N[static_cast<std::size_t>(face[i])] += w * normal;
    });
  }
  g.volume = six_volume / 6.0;
  if (!(g.volume > 0.0)) throw MeshError("cell has non-positive volume (are its faces oriented outward?)", -1);
}

/// The rigid-motion coefficients rho = (R^T R)^{-1} R^T w, R the rigid motions at the vertices
/// (translations, then rotations omega x r about x, y, z). Centring at the vertex mean makes
/// R^T R block diagonal: n I for the translations and the inertia tensor
/// sum_i (|r_i|^2 I - r_i r_i^T) of the vertices for the rotations (positive definite unless the
/// vertices are collinear).
struct RigidSolver {
  double inv_n = 0.0;
  Eigen::Matrix3d inverse_inertia;
  explicit RigidSolver(const std::vector<Vec3>& r) : inv_n(1.0 / static_cast<double>(r.size())) {
    double squared = 0.0;
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    for (const Vec3& x : r) {
      squared += x.squaredNorm();
      second.noalias() += x * x.transpose();
    }
    const Eigen::LLT<Eigen::Matrix3d> inertia(squared * Eigen::Matrix3d::Identity() - second);
    if (inertia.info() != Eigen::Success) throw MeshError("cell whose vertices are collinear", -1);
    inverse_inertia = inertia.solve(Eigen::Matrix3d::Identity());
  }
  /// (R^T R)^{-1} applied to the columns of M (6 x k).
  template <int Cols>
  Eigen::Matrix<double, 6, Cols> apply(const Eigen::Matrix<double, 6, Cols>& M) const {
    Eigen::Matrix<double, 6, Cols> out;
    out.template topRows<3>() = inv_n * M.template topRows<3>();
    out.template bottomRows<3>().noalias() = inverse_inertia * M.template bottomRows<3>();
    return out;
  }
};

using Mat36 = Eigen::Matrix<double, 3, 6>;
using Mat63 = Eigen::Matrix<double, 6, 3>;

/// The rows of vertex r in R: u = t + omega x r = t - [r]x omega.
Mat36 rigid_rows(const Vec3& r) {
  Mat36 R;
  R << 1.0, 0.0, 0.0, 0.0, r.z(), -r.y(),  //
      0.0, 1.0, 0.0, -r.z(), 0.0, r.x(),   //
      0.0, 0.0, 1.0, r.y(), -r.x(), 0.0;
  return R;
}

/// The rows of vertex r in Ds: the fields eps r whose Voigt strain (engineering shear) is the
/// unit vector e_k.
Mat36 strain_rows(const Vec3& r) {
  Mat36 D;
  D << r.x(), 0.0, 0.0, 0.0, 0.5 * r.z(), 0.5 * r.y(),  //
      0.0, r.y(), 0.0, 0.5 * r.z(), 0.0, 0.5 * r.x(),   //
      0.0, 0.0, r.z(), 0.5 * r.y(), 0.5 * r.x(), 0.0;
  return D;
}

/// The columns of vertex a in B: the Voigt strain (xx, yy, zz, 2yz, 2xz, 2xy) of v (x) a.
Mat63 strain_columns(const Vec3& a) {
  Mat63 B;
  B << a.x(), 0.0, 0.0,  //
      0.0, a.y(), 0.0,   //
      0.0, 0.0, a.z(),   //
      0.0, a.z(), a.y(), //
      a.z(), 0.0, a.x(), //
      a.y(), a.x(), 0.0;
  return B;
}

/// A dense matrix whose storage keeps its capacity from cell to cell.
struct Scratch {
  std::vector<double> data;
  Eigen::Map<Eigen::MatrixXd> matrix(Eigen::Index rows, Eigen::Index cols) {
    const auto size = static_cast<std::size_t>(rows * cols);
    if (data.size() < size) data.resize(size);
    return {data.data(), rows, cols};
  }
};

/// The lower triangles of K_c and K_s of one cell, with everything they depend on: the
/// vertices relative to the first one (z_i - z_0, as cell_geometry computes them), the faces,
/// the Lame constants and the stabilization.
struct CellSlot {
  bool valid = false;
  std::vector<double> relative;  // z_i - z_0 for i >= 1
  std::vector<int> face_sizes, face_vertices;
  double lambda = 0.0, mu = 0.0;
  Stabilization stabilization = Stabilization::two_mu;
  Scratch Kc, Ks;

  /// True when (z, faces, lame, stabilization) is this slot's cell or a translate of it whose
  /// relative vertices are the same bit for bit.
  bool matches(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces, const Lame& lame,
               Stabilization s) const {
    if (!valid || relative.size() != 3 * (z.size() - 1) || face_sizes.size() != faces.size() || s != stabilization ||
        std::memcmp(&lambda, &lame.lambda, sizeof(double)) != 0 || std::memcmp(&mu, &lame.mu, sizeof(double)) != 0)
      return false;
    for (std::size_t i = 1; i < z.size(); ++i) {
      const Vec3 d = z[i] - z[0];
      if (std::memcmp(d.data(), relative.data() + 3 * (i - 1), 3 * sizeof(double)) != 0) return false;
    }
    std::size_t k = 0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto& face = faces[f];
      if (face.size() != static_cast<std::size_t>(face_sizes[f]) || k + face.size() > face_vertices.size() ||
          !std::equal(face.begin(), face.end(), face_vertices.begin() + static_cast<std::ptrdiff_t>(k)))
        return false;
      k += face.size();
    }
    return true;
  }
  void set_key(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces, const Lame& lame, Stabilization s) {
    relative.resize(3 * (z.size() - 1));
    for (std::size_t i = 1; i < z.size(); ++i) {
      const Vec3 d = z[i] - z[0];
      std::memcpy(relative.data() + 3 * (i - 1), d.data(), 3 * sizeof(double));
    }
    face_sizes.clear();
    face_vertices.clear();
    for (const auto& face : faces) {
      face_sizes.push_back(static_cast<int>(face.size()));
      face_vertices.insert(face_vertices.end(), face.begin(), face.end());
    }
    lambda = lame.lambda;
    mu = lame.mu;
    stabilization = s;
    valid = true;
  }
};

/// What the element matrices of one cell are computed in; one per thread, reused.
/// element_stiffness_3d keeps the matrices of the last `recent.size()` cells it computed: a
/// cell that is a translate of one of them, its vertices relative to its first one the same
/// bit for bit (and its faces, Lame constants and stabilization the same), gets that cell's
/// matrices back. The computation reads nothing else, so they are the bits it would compute:
/// on a mesh of translated copies of a few cells (boxes of a grid) most cells cost a
/// comparison, on other meshes each cell costs one failed comparison more.
struct ElementWorkspace {
  CellGeometry g;
  std::vector<Vec3> a;                             // N_i / |E|, the columns of vertex i in B
  std::vector<Mat63, Eigen::aligned_allocator<Mat63>> M;  // (R^T R)^{-1} R^T (I - Ds B), by vertex
  Scratch P, E;
  CellSlot single;                 // vem_element_3d's
  std::array<CellSlot, 8> recent;  // element_stiffness_3d's, replaced in turn
  std::size_t next = 0;
};

/// The element matrices of a cell in the workspace: the lower triangles of K_c (Kc) and K_s
/// (Ks), E = I - Pi in full, the projection Pi in P when `projection` is set, and tau.
///
/// Pi = R (R^T R)^{-1} R^T (I - Ds B) + Ds B = R M + Ds B is formed by 3 x 3 blocks, one per
/// pair of vertices (i, j):
///   R_i M_j = M_j^t + M_j^r x r_i (column by column; M_j^t, M_j^r its translation and rotation rows),
///   Ds_i B_j = ((a_j . r_i) I + a_j r_i^T) / 2 (the strain sym(v (x) a_j) applied to r_i),
/// with M_j = (R^T R)^{-1} (R_j^T - (R^T Ds) B_j), R^T Ds a 6 x 6 sum over the vertices. The
/// consistency block is |E| B_i^T C B_j = |E| (lambda a_i a_j^T + mu (a_i . a_j) I + mu a_j a_i^T)
/// for the isotropic C, and K_s = tau E^T E a symmetric rank update: no product of two
/// 3n x 3n matrices, no heap allocation once the workspace has grown to the cell's size.
double element_matrices(std::span<const Vec3> z, const std::vector<std::vector<int>>& faces, const Lame& lame,
                        Stabilization stabilization, ElementWorkspace& w, CellSlot& slot, bool projection) {
  cell_geometry(z, faces, w.g);
  const std::size_t n = z.size();
  const auto n3 = static_cast<Eigen::Index>(3 * n);
  const std::vector<Vec3>& r = w.g.r;
  const double volume = w.g.volume;
  w.a.resize(n);
  for (std::size_t i = 0; i < n; ++i) w.a[i] = w.g.N[i] / volume;

  const RigidSolver rigid(r);
  Eigen::Matrix<double, 6, 6> RtDs = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t i = 0; i < n; ++i) RtDs.noalias() += rigid_rows(r[i]).transpose() * strain_rows(r[i]);
  w.M.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Mat63 RjT = rigid_rows(r[j]).transpose();
    w.M[j] = rigid.apply<3>(Mat63(RjT - RtDs * strain_columns(w.a[j])));
  }

  // Pi and E = I - Pi by blocks, entry by entry (column c of block (i, j) is
  // M_j^t e_c + M_j^r e_c x r_i + (r_i)_c a_j / 2, plus (a_j . r_i) / 2 on the diagonal)
  auto P = w.P.matrix(projection ? n3 : 0, projection ? n3 : 0);
  auto E = w.E.matrix(n3, n3);
  for (std::size_t j = 0; j < n; ++j) {
    const double* Mj = w.M[j].data();  // column c: rows 0-2 translation, 3-5 rotation
    const double ax = w.a[j].x(), ay = w.a[j].y(), az = w.a[j].z();
    for (std::size_t i = 0; i < n; ++i) {
      const double rx = r[i].x(), ry = r[i].y(), rz = r[i].z();
      const double ar = 0.5 * (ax * rx + ay * ry + az * rz);
      const double half[3] = {0.5 * rx, 0.5 * ry, 0.5 * rz};
      for (int c = 0; c < 3; ++c) {
        const double* m = Mj + 6 * c;
        double p[3] = {m[0] + (m[4] * rz - m[5] * ry) + half[c] * ax, m[1] + (m[5] * rx - m[3] * rz) + half[c] * ay,
                       m[2] + (m[3] * ry - m[4] * rx) + half[c] * az};
        p[c] += ar;
        const Eigen::Index col = static_cast<Eigen::Index>(3 * j) + c;
        double* e = &E(static_cast<Eigen::Index>(3 * i), col);
        for (int k = 0; k < 3; ++k) e[k] = (i == j && k == c ? 1.0 : 0.0) - p[k];
        if (projection) {
          double* q = &P(static_cast<Eigen::Index>(3 * i), col);
          for (int k = 0; k < 3; ++k) q[k] = p[k];
        }
      }
    }
  }

  // K_c, lower triangle (the diagonal blocks in full). |E| a_i a_j is a length, but |E| and the
  // Lame constants alone may leave the range of doubles (|E| = 1e-240 for a cell of side 1e-80):
  // |E| is scaled by 2^(-2k) and the a_i by 2^k, 2^k about the cell's size, which changes no bit
  // of a product that stays in range.
  auto Kc = slot.Kc.matrix(n3, n3);
  const int k = std::ilogb(volume) / 3;
  const double scaled_volume = std::ldexp(volume, -2 * k);
  const double lambda_v = lame.lambda * scaled_volume, mu_v = lame.mu * scaled_volume;
  double trace = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3 bj = std::ldexp(1.0, k) * w.a[j];
    const double aj[3] = {bj.x(), bj.y(), bj.z()};
    for (std::size_t i = j; i < n; ++i) {
      const Vec3 bi = std::ldexp(1.0, k) * w.a[i];
      const double ai[3] = {bi.x(), bi.y(), bi.z()};
      const double dot = mu_v * (ai[0] * aj[0] + ai[1] * aj[1] + ai[2] * aj[2]);
      for (int c = 0; c < 3; ++c) {
        double* k = &Kc(static_cast<Eigen::Index>(3 * i), static_cast<Eigen::Index>(3 * j) + c);
        for (int d = 0; d < 3; ++d) k[d] = lambda_v * ai[d] * aj[c] + mu_v * aj[d] * ai[c] + (d == c ? dot : 0.0);
      }
      if (i == j)
        for (int c = 0; c < 3; ++c) trace += Kc(static_cast<Eigen::Index>(3 * i + c), static_cast<Eigen::Index>(3 * j + c));
    }
  }
  const double tau = stabilization == Stabilization::two_mu ? 2.0 * lame.mu * std::cbrt(volume)
                                                            : trace / static_cast<double>(n3);
  // K_s = tau E^T E, lower triangle
  auto Ks = slot.Ks.matrix(n3, n3);
  Ks.setZero();
  Ks.selfadjointView<Eigen::Lower>().rankUpdate(E.transpose(), tau);
  return tau;
}

/// The full symmetric matrix from its lower triangle.
void mirror_lower(Eigen::Ref<Eigen::MatrixXd> K) {
  for (Eigen::Index j = 1; j < K.cols(); ++j)
    for (Eigen::Index i = 0; i < j; ++i) K(i, j) = K(j, i);
}

ElementWorkspace& workspace() {
  thread_local ElementWorkspace w;
  return w;
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
  ElementWorkspace& w = workspace();
  const double tau = element_matrices(vertices, faces, lame, stabilization, w, w.single, true);
  const auto n3 = static_cast<Eigen::Index>(3 * vertices.size());
  VemElement3D el;
  el.volume = w.g.volume;
  el.vertex_mean = w.g.mean;
  el.strain.resize(6, n3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    el.strain.middleCols<3>(static_cast<Eigen::Index>(3 * i)) = strain_columns(w.a[i]);
  el.projection = w.P.matrix(n3, n3);
  el.consistency = w.single.Kc.matrix(n3, n3);
  mirror_lower(el.consistency);
  el.stabilization = w.single.Ks.matrix(n3, n3);
  mirror_lower(el.stabilization);
  el.tau = tau;
  return el;
}

void element_stiffness_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                          const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K) {
  ElementWorkspace& w = workspace();
  CellSlot* slot = nullptr;
  for (CellSlot& s : w.recent)
    if (s.matches(vertices, faces, lame, stabilization)) {
      slot = &s;
      break;
    }
  if (slot == nullptr) {
    slot = &w.recent[w.next];
    w.next = (w.next + 1) % w.recent.size();
    slot->valid = false;
    element_matrices(vertices, faces, lame, stabilization, w, *slot, false);
    slot->set_key(vertices, faces, lame, stabilization);
  }
  const auto n3 = static_cast<Eigen::Index>(3 * vertices.size());
  const auto Kc = slot->Kc.matrix(n3, n3);
  const auto Ks = slot->Ks.matrix(n3, n3);
  K.resize(n3, n3);
  for (Eigen::Index j = 0; j < n3; ++j)
    for (Eigen::Index i = j; i < n3; ++i) K(i, j) = Kc(i, j) + Ks(i, j);
  mirror_lower(K);
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
  CellGeometry& g = workspace().g;
  cell_geometry(z, faces, g);
  const RigidSolver rigid(g.r);
  // eps = B v, then rho = (R^T R)^{-1} R^T (v - Ds eps)
  Eigen::Matrix<double, 6, 1> eps = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t i = 0; i < z.size(); ++i)
    eps.noalias() += strain_columns(g.N[i] / g.volume) * v.segment<3>(3 * static_cast<Eigen::Index>(i));
  Eigen::Matrix<double, 6, 1> Rtw = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec3 wi = v.segment<3>(3 * static_cast<Eigen::Index>(i)) - strain_rows(g.r[i]) * eps;
    Rtw.noalias() += rigid_rows(g.r[i]).transpose() * wi;
  }
  const Eigen::Matrix<double, 6, 1> rho = rigid.apply<1>(Rtw);
  LinearField3 f;
  f.center = g.mean;
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
  CellGeometry& g = workspace().g;
  cell_geometry(z, faces, g);
  LinearField3 f;
  f.center = g.mean;
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec3 vi = v.segment<3>(3 * static_cast<Eigen::Index>(i));
    f.value += vi;
    f.gradient += vi * g.N[i].transpose();
  }
  f.value /= static_cast<double>(z.size());
  f.gradient /= g.volume;
  return f;
}

}  // namespace hemivem
