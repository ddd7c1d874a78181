// Checks and grid points shared by the generators on a box (generators3d.hpp).
#pragma once

#include <hemivem/mesh/generators3d.hpp>

namespace hemivem::detail {

/// InputError naming `generator` for a size outside [1, 1000] per axis, a box that is not
/// finite with x0 < x1, y0 < y1, z0 < z1 or beyond 1e100, or cells too small for double precision.
void check_box_grid(const char* generator, GridSize3 n, const Box& box);

/// The point i/n of the way from a to b, exactly b for i == n.
double box_grid_coordinate(double a, double b, long i, long n);

}  // namespace hemivem::detail
