// The named sides of a rectangle and of a box (private to the mesh module): rectangle_side
// (boundary.cpp), select_box_side (mesh3d.cpp) and the sides of a piece (box_piece.cpp).
#pragma once

#include <string>
#include <utility>

namespace hemivem::detail {

/// The axis that side `side` of a rectangle (dim 2: left, right, bottom, top) or of a box
/// (dim 3: x0, x1, y0, y1, z0 or bottom, z1 or top) is normal to, and whether it is the upper
/// side along it. InputError naming the sides of the dimension for an unknown name.
std::pair<int, bool> box_side_axis(int dim, const std::string& side);

}  // namespace hemivem::detail
