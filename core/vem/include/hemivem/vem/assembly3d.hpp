// Boundary conditions, loads and the global assembly of the 3D VEM elasticity system
// (docs/three-dimensions.md). Dofs are 3 v + c for component c of vertex v; DofMap and
// LinearSystem are those of the plane problem (hemivem/vem/assembly.hpp).
#pragma once

#include <Eigen/Core>

#include <array>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/element3d.hpp>

namespace hemivem {

/// The global stiffness of all 3 num_vertices dofs (symmetric, both triangles stored).
SparseMatrix assemble_stiffness(const Mesh3D& mesh, const MaterialTable& materials,
                                   Stabilization stabilization = Stabilization::two_mu);

/// The load vector of all dofs: the body force and the tractions.
Eigen::VectorXd assemble_load(const Mesh3D& mesh, const VectorField3& body_force,
                                 const std::vector<TractionLoad3D>& tractions);

/// (K u)_d on the dofs d with rows[d] != 0 (0 elsewhere), as apply_stiffness of a plane mesh.
Eigen::VectorXd apply_stiffness(const Mesh3D& mesh, const MaterialTable& materials, Stabilization stabilization,
                                const Eigen::VectorXd& u, const std::vector<char>& rows);

/// The load and K u at the dofs of some vertices alone, as assemble_load_at and
/// apply_stiffness_at of a plane mesh.
Eigen::VectorXd assemble_load_at(const Mesh3D& mesh, const VectorField3& body_force,
                                 const std::vector<TractionLoad3D>& tractions, std::span<const int> vertices);
Eigen::VectorXd apply_stiffness_at(const Mesh3D& mesh, const MaterialTable& materials, Stabilization stabilization,
                                   const Eigen::VectorXd& u, std::span<const int> vertices,
                                   const std::vector<char>& rows);

DofMap make_dof_map(const Mesh3D& mesh, const std::vector<DirichletCondition3D>& dirichlet);
DofMap make_dof_map(const Mesh3D& mesh, const std::vector<DirichletCondition3D>& dirichlet,
                    const std::vector<int>& vertex_order);

/// The reduced system (prescribed dofs eliminated, their values lifted into b). InputError,
/// before any assembly, when no face has a prescribed displacement or their area is zero.
LinearSystem assemble(const ElasticityProblem3D& problem);

/// The rows of assemble(problem) of the vertices first_vertex, ..., end_vertex - 1, as
/// assemble_rows of a plane problem.
SystemRows assemble_rows(const ElasticityProblem3D& problem, int first_vertex, int end_vertex);
SystemRows assemble_rows(const ElasticityProblem3D& problem, const std::vector<int>& vertex_order, int first, int end);

/// The load of the free dofs of `dofs` at the problem's data (as assemble_rhs of a plane problem).
Eigen::VectorXd assemble_rhs(const ElasticityProblem3D& problem, const DofMap& dofs);
/// The same written into `b` (num_free() entries), as the plane's.
void assemble_rhs(const ElasticityProblem3D& problem, const DofMap& dofs, Eigen::Ref<Eigen::VectorXd> b);

/// Per cell: the P1 projection Pi u_h of the full nodal vector u (3 per vertex).
std::vector<LinearField3> project_solution(const Mesh3D& mesh, const Eigen::VectorXd& u);

/// The in-plane scaled vertex normals nu_i = (m_{i-1} + m_i) / 2 of a planar polygon (column i;
/// m_e = |e| times the edge's outward normal in the face's plane): the face projection of the
/// vertex-i basis function is 1/n + nu_i . (x - zbar) / |f|.
Eigen::Matrix3Xd face_vertex_normals(std::span<const Vec3> face);

}  // namespace hemivem
