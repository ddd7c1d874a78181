// The projected stress of each cell of a solve, plane or solid: solution.vtu's stress and
// von_mises, stress.csv, result.json's "stress" and the summary's stress line
// (docs/reference/outputs.md).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/vem/material.hpp>

namespace hemivem::app {

/// The projected stress of a cell of a body of dimension dim: the stress of the projection
/// Pi u_h, constant on the cell, with the material of the cell's region. A plane body's yz and
/// xz are 0 and its zz is lambda (eps_xx + eps_yy) in plane strain, 0 in plane stress
/// (element_stresses of hemivem/vem/stress.hpp); a solid's sigma = lambda tr(eps) I + 2 mu eps,
/// eps the symmetric part of the projection's gradient.
template <int dim>
struct BasicCellStress {
  double xx = 0.0, yy = 0.0, zz = 0.0, yz = 0.0, xz = 0.0, xy = 0.0;
  /// sqrt(((xx - yy)^2 + (yy - zz)^2 + (zz - xx)^2) / 2 + 3 (yz^2 + xz^2 + xy^2)); a plane
  /// cell's as sqrt(... + 3 xy^2).
  double von_mises() const;
};
using CellStress = BasicCellStress<2>;

/// The projected stress of each element of a plane mesh or cell of a solid one; InputError for
/// a displacement whose size does not match the mesh (dim values per vertex).
std::vector<CellStress> cell_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u);
std::vector<BasicCellStress<3>> cell_stresses(const Mesh3D& mesh, const MaterialTable& materials,
                                              const Eigen::VectorXd& u);

/// The cell of the largest von Mises stress.
struct StressPeak {
  int cell = -1;                 ///< the cell (an element of a plane mesh), 0-based
  double von_mises = 0.0;        ///< its von Mises stress
  std::vector<double> centroid;  ///< its centroid: 2 coordinates in the plane, 3 in a solid
};

/// The first cell of the largest von Mises stress among `stresses` (one per cell of `mesh`);
/// none without cells or when a cell's von Mises stress is not finite (a displacement that is
/// not). InputError when `stresses` does not have one entry per cell.
std::optional<StressPeak> stress_peak(const Mesh& mesh, const std::vector<CellStress>& stresses);
std::optional<StressPeak> stress_peak(const Mesh3D& mesh, const std::vector<BasicCellStress<3>>& stresses);

/// stress_peak of a whole mesh that the processes hold in pieces, collective over `rows`: each
/// process's `stresses` are those of its piece `mesh`, `owned` flags the piece's cells it owns
/// (each cell of the whole mesh owned by one process) and `cells` gives each cell's number in
/// the whole mesh (increasing). The whole mesh's first cell of the largest von Mises stress,
/// numbered as the whole numbers it, the same on every process; none when a cell's von Mises
/// stress is not finite.
std::optional<StressPeak> stress_peak_of_pieces(const Mesh& mesh, const std::vector<CellStress>& stresses,
                                                const std::vector<char>& owned, const std::vector<int>& cells,
                                                const RowDistribution& rows);
std::optional<StressPeak> stress_peak_of_pieces(const Mesh3D& mesh, const std::vector<BasicCellStress<3>>& stresses,
                                                const std::vector<char>& owned, const std::vector<int>& cells,
                                                const RowDistribution& rows);

}  // namespace hemivem::app
