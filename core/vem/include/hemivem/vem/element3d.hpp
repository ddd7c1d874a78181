// The lowest-order virtual element for 3D linear elasticity (docs/three-dimensions.md).
//
// Local degrees of freedom of a cell with vertices z_0..z_{n-1} are interleaved: 3i + c is
// component c of the displacement at z_i.
//
// The face space is the enhanced lowest-order space of Ahmad, Alsaedi, Brezzi, Marini and
// Russo: on each face f, the integral of v is that of its face projection Pi^nabla_f v (the
// linear function with the mean gradient (1/|f|) sum_i v_i nu_i^f, nu_i^f the in-plane vertex
// normals, and the mean of the vertex values at the vertex mean), so
//   int_f v = sum_i omega_i^f v_i,  omega_i^f = |f|/n_f + nu_i^f . (c_f - zbar_f),
// exact for linear v (c_f the face centroid, zbar_f its vertex mean). The projected strain is
//   eps_bar(v) = (1/|E|) sum_f sym((int_f v) (x) n_f),
// the consistency part K_c = |E| B^T C B (C the 6 x 6 isotropic elasticity matrix in Voigt
// form xx, yy, zz, 2yz, 2xz, 2xy), the projection Pi onto P1 fields in the strain inner
// product with the rigid part fixed by the vertex-discrete conditions (six rigid motions), and
// the stabilization tau (I - Pi)^T (I - Pi) with tau = 2 mu h_E (h_E = |E|^(1/3), the scaling
// that keeps it comparable to K_c) or tr(K_c) / (3n).
#pragma once

#include <Eigen/Core>

#include <span>
#include <vector>

#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/element.hpp>
#include <hemivem/vem/material.hpp>

namespace hemivem {

/// The 6 x 6 elasticity matrix in Voigt form (xx, yy, zz, 2yz, 2xz, 2xy).
Eigen::Matrix<double, 6, 6> elasticity_matrix_3d(const Lame& lame);

/// A vector-valued polynomial of degree one in 3D: p(x) = value + gradient * (x - center).
struct LinearField3 {
  Vec3 center = Vec3::Zero();
  Vec3 value = Vec3::Zero();
  Eigen::Matrix3d gradient = Eigen::Matrix3d::Zero();  ///< gradient(c, d) = d p_c / d x_d
  Vec3 operator()(const Vec3& x) const { return value + gradient * (x - center); }
};

/// The stress lambda tr(eps) I + 2 mu eps of the strain eps = sym(gradient) (constant on a cell
/// for the gradient of Pi u_h).
inline Eigen::Matrix3d stress_3d(const Eigen::Matrix3d& gradient, const Lame& lame) {
  const Eigen::Matrix3d eps = 0.5 * (gradient + gradient.transpose());
  return lame.lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2.0 * lame.mu * eps;
}

/// Everything the method computes on one cell.
struct VemElement3D {
  double volume = 0.0;
  Vec3 vertex_mean = Vec3::Zero();
  /// Projected strain in Voigt form: 6 x 3n.
  Eigen::MatrixXd strain;
  /// Nodal matrix of the P1 projection: 3n x 3n, Pi*Pi = Pi, Pi v = v for P1 fields.
  Eigen::MatrixXd projection;
  Eigen::MatrixXd consistency;    ///< |E| B^T C B
  Eigen::MatrixXd stabilization;  ///< tau (I - Pi)^T (I - Pi)
  double tau = 0.0;
  Eigen::MatrixXd stiffness() const { return consistency + stabilization; }
};

/// The face-integral weights omega_i^f of a planar polygon (counter-clockwise seen from
/// outside the cell): int_f v = sum_i omega_i v(z_i) for v in the enhanced face space. They sum
/// to |f| and are exact for linear v. InputError for fewer than 3 vertices, MeshError for a
/// face of zero area.
Eigen::VectorXd face_weights(std::span<const Vec3> face);

/// The element matrices of a polyhedron: `vertices` its vertices, `faces` loops of positions in
/// `vertices`, each counter-clockwise seen from outside (Mesh3D::local_faces). InputError for
/// fewer than 4 vertices or 4 faces, a face of fewer than 3 vertices, a position out of range
/// or a vertex on no face; MeshError for a face of zero area or a cell of non-positive volume
/// (faces oriented inward). The same errors for the functions below.
VemElement3D vem_element_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                            const Lame& lame, Stabilization stabilization = Stabilization::two_mu);

/// K_E of vem_element_3d alone, into K (resized to 3n x 3n), the same bits. Without heap
/// allocation once the calling thread's workspace has grown to the cell's size. Each thread
/// keeps the matrices of the last 8 cells it computed: a cell that is a translate of one of
/// them (its vertices minus its first vertex the same bit for bit, and the same faces, Lame
/// constants and stabilization) gets that cell's matrix back instead of computing it again.
/// K depends on nothing else, so it is the matrix the computation would give, bit for bit;
/// on a grid of boxes or tetrahedra whose coordinates are exact in binary most cells cost a
/// comparison, on a Voronoi mesh each cell one failed comparison more.
void element_stiffness_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                          const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K);

/// Pi u_h on one cell from its local nodal values (size 3n; InternalError otherwise).
LinearField3 project_p1_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                           const Eigen::Ref<const Eigen::VectorXd>& local_values);

/// Pi^nabla_1 u_h on one cell (gradient = (1/|E|) sum_f (int_f v) (x) n_f, constant fixed by the
/// mean of the vertex values), the projection the body force uses.
LinearField3 project_gradient_3d(std::span<const Vec3> vertices, const std::vector<std::vector<int>>& faces,
                                 const Eigen::Ref<const Eigen::VectorXd>& local_values);

}  // namespace hemivem
