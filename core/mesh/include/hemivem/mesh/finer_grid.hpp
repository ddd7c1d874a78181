// Values at the vertices of a grid of boxes carried onto the grid of half its boxes' size: the
// step between the grids of a grid sequence (hemivem/scene/grid_sequence.hpp). The generators on
// a grid of boxes (squares and triangles in the plane, cubes and tetrahedra in a solid) number
// the grid's points alike, layer by layer along the last axis (generators.hpp, generators3d.hpp).
#pragma once

#include <Eigen/Core>

#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>

namespace hemivem {

/// The values at the points of the grid of 2 n.nx x 2 n.ny boxes interpolated from `coarse`,
/// `components` numbers at each point of the grid of n.nx x n.ny boxes on the same rectangle
/// (point (i, j) at j (n.nx + 1) + i, its numbers consecutive): a point shared with the coarse
/// grid keeps its values, the others the mean of the coarse box's corners they lie between
/// (multilinear interpolation on each coarse box, exact for every affine field). InputError
/// for `components` < 1 or values of another size.
Eigen::VectorXd values_on_finer_grid(const Eigen::VectorXd& coarse, GridSize n, int components);

/// The same on a box: from the grid of n.nx x n.ny x n.nz boxes (point (i, j, k) at
/// (k (n.ny + 1) + j) (n.nx + 1) + i) to that of 2 n.nx x 2 n.ny x 2 n.nz.
Eigen::VectorXd values_on_finer_grid(const Eigen::VectorXd& coarse, GridSize3 n, int components);

}  // namespace hemivem
