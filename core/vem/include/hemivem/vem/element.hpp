// The lowest-order virtual element for plane linear elasticity (docs/tutorial/example-4.1.md, the virtual element method).
//
// Local degrees of freedom of an element with vertices z_0..z_{n-1} (counter-clockwise)
// are interleaved: 2i -> u_x(z_i), 2i+1 -> u_y(z_i).
#pragma once

#include <Eigen/Core>

#include <span>
#include <string>
#include <string_view>

#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// Scaling of the stabilization S_E = tau (I - Pi)^T (I - Pi).
enum class Stabilization {
  two_mu,      ///< tau = 2 mu ("dofi-dofi", the default; docs/tutorial/example-4.1.md)
  trace_scaled ///< tau = tr(K_c) / (2n)
};
std::string to_string(Stabilization s);
/// "2mu" / "two-mu" or "trace" / "trace-scaled" (case-insensitive); InputError otherwise.
Stabilization stabilization_from_string(std::string_view name);

/// A vector-valued polynomial of degree one: p(x) = value + gradient * (x - center).
struct LinearField {
  Vec2 center = Vec2::Zero();
  Vec2 value = Vec2::Zero();
  Eigen::Matrix2d gradient = Eigen::Matrix2d::Zero();  ///< gradient(c, d) = d p_c / d x_d
  Vec2 operator()(const Vec2& x) const { return value + gradient * (x - center); }
};

/// Everything the method computes on one element.
struct VemElement {
  double area = 0.0;
  Vec2 vertex_mean = Vec2::Zero();
  /// Projected strain (1/|E|) sum_e int_e sym(v (x) n_e) in Voigt form (xx, yy, 2xy): 3 x 2n.
  Eigen::MatrixXd strain;
  /// Nodal matrix of the P1 projection in the strain inner product with vertex-discrete
  /// rigid-motion conditions: 2n x 2n, Pi*Pi = Pi, Pi v = v for P1 fields.
  Eigen::MatrixXd projection;
  /// |E| B^T C B
  Eigen::MatrixXd consistency;
  /// tau (I - Pi)^T (I - Pi)
  Eigen::MatrixXd stabilization;
  double tau = 0.0;

  Eigen::MatrixXd stiffness() const { return consistency + stabilization; }
};

/// The element matrices of the polygon `vertices` (counter-clockwise, n >= 3).
VemElement vem_element(std::span<const Vec2> vertices, const Lame& lame,
                       Stabilization stabilization = Stabilization::two_mu);

/// K_E = consistency + stabilization of vem_element() alone, into K (resized to 2n x 2n; a K
/// of that size is reused): without heap allocation for elements of up to 8 vertices.
void element_stiffness(std::span<const Vec2> vertices, const Lame& lame, Stabilization stabilization,
                       Eigen::MatrixXd& K);

/// The scaled vertex normals nu_i = (m_{i-1} + m_i)/2, m_i = |e_i| n_i, of a polygon
/// (column i): the projected strain of v is (1/|E|) sum_i sym(v_i (x) nu_i).
Eigen::Matrix2Xd vertex_normals(std::span<const Vec2> vertices);

/// Pi u_h on one element from its local nodal values (size 2n): the P1 field of the
/// strain-inner-product projection.
LinearField project_p1(std::span<const Vec2> vertices, const Eigen::Ref<const Eigen::VectorXd>& local_values);

/// The strain of Pi u_h on one element, (eps_xx, eps_yy, 2 eps_xy) = B v, from its local nodal
/// values (size 2n): the symmetric part of project_p1()'s gradient, without the rest of the
/// projection. MeshError for a polygon of non-positive area.
Eigen::Vector3d projected_strain(std::span<const Vec2> vertices, const Eigen::Ref<const Eigen::VectorXd>& local_values);

/// Pi^nabla_1 u_h on one element (gradient = mean gradient, constant fixed by the mean of
/// the vertex values), the projection the load uses (3.13).
LinearField project_gradient(std::span<const Vec2> vertices, const Eigen::Ref<const Eigen::VectorXd>& local_values);

}  // namespace hemivem
