// Bilinear (Q1) fields on meshes of axis-aligned rectangles: the exact prolongation between
// nested squares and the exact energy (sigma(v), eps(v)) of a bilinear field, the yardstick of
// the convergence study (docs/table1.md). On such rectangles the lowest-order VEM functions are
// bilinear, so these are exact for VEM solutions there.
#pragma once

#include <array>

#include <Eigen/Core>

#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// Nodal values (2 per vertex, interleaved) of the bilinear interpolant of `coarse` (values on
/// make_squares(n_coarse), same domain) at the vertices of make_squares(n_fine); n_fine must be
/// a multiple of n_coarse. Exact for fields bilinear on every coarse square.
Eigen::VectorXd prolong_squares(const Eigen::VectorXd& coarse, int n_coarse, int n_fine);

/// The 8 x 8 stiffness of the Q1 (bilinear) element on the axis-aligned rectangle with the
/// given four vertices (any order; the matrix follows it, dofs interleaved), 2 x 2 Gauss:
/// v^T K v = (sigma(v), eps(v)) over the rectangle, exact for bilinear v.
Eigen::Matrix<double, 8, 8> q1_stiffness(const std::array<Vec2, 4>& vertices, const Lame& lame);

/// (sigma(v), eps(v)) over a mesh of axis-aligned rectangles (4-vertex elements) for the
/// bilinear field with nodal values `u` (2 per vertex), with the material of each element's
/// region. The energy norm is sqrt(q1_energy / 2).
double q1_energy(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u);

}  // namespace hemivem
