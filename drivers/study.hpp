// hemivem study: the convergence study of the paper's Table 1 (DESIGN §6).
//
// The scene is solved on N x N squares for each N and for a reference N that every N divides;
// each coarse solution is prolonged exactly to the reference mesh (on axis-aligned rectangles
// the lowest-order VEM functions are bilinear), and the error is the exact energy of the
// bilinear difference there: ||v||_E = (1/sqrt 2) (sigma(v), eps(v))^(1/2), relative error
// ||u_ref - P u_h||_E / ||u_ref||_E.
#pragma once

#include <Eigen/Core>

#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include <hemivem/material.hpp>
#include <hemivem/mesh.hpp>

namespace hemivem::cli {

struct StudyOptions {
  std::string scene;                   ///< scene file; empty: the embedded Example 4.1
  std::vector<int> n{4, 8, 16, 32, 64};
  int ref = 256;
  std::vector<std::string> set;        ///< --set key=value, in order, applied to every solve
  std::string out = "out/study";
  bool json = false;                   ///< study.json on stdout instead of the table
  int verbosity = 1;                   ///< 0 quiet, 1 table and a progress line per solve
};

/// hemivem study [SCENE.toml]: writes study.csv, study.json and study.png (when gnuplot is
/// found) into options.out. Exit 0 when every solve converged, kNotConverged otherwise (the
/// outputs are still written and marked); InputError for a scene that is not on squares or
/// an N that does not divide the reference N.
int run_study(const StudyOptions& options, std::ostream& out, std::ostream& err);

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

}  // namespace hemivem::cli
