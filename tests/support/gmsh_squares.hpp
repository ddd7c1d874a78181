// A plane Gmsh file written by a test: squares on the unit square, in two regions, with its
// bottom and top as physical lines.
#pragma once

#include <array>
#include <sstream>
#include <string>

namespace hemivem::test {

/// A plane Gmsh file of squares nx x ny on the unit square: the left half region 1, the right
/// half region 2, its bottom the physical line "bottom" and its top "top".
inline std::string squares_msh(int nx, int ny) {
  std::ostringstream o;
  o << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"bottom\"\n1 2 \"top\"\n2 1 \"left\"\n2 2 \"right\"\n"
       "$EndPhysicalNames\n$Entities\n0 2 2 0\n";
  o << "1 0 0 0 1 0 0 1 1 0\n2 0 1 0 1 1 0 1 2 0\n";
  o << "1 0 0 0 0.5 1 0 1 1 0\n2 0.5 0 0 1 1 0 1 2 0\n$EndEntities\n";
  const int nv = (nx + 1) * (ny + 1);
  o << "$Nodes\n1 " << nv << " 1 " << nv << "\n2 1 0 " << nv << "\n";
  for (int k = 1; k <= nv; ++k) o << k << "\n";
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) o << static_cast<double>(i) / nx << " " << static_cast<double>(j) / ny << " 0\n";
  o << "$EndNodes\n";
  const auto node = [&](int i, int j) { return j * (nx + 1) + i + 1; };
  int left = 0;
  for (int i = 0; i < nx; ++i) left += 2 * i < nx ? 1 : 0;
  o << "$Elements\n4 " << 2 * nx + nx * ny << " 1 " << 2 * nx + nx * ny << "\n";
  int tag = 1;
  o << "1 1 1 " << nx << "\n";
  for (int i = 0; i < nx; ++i) o << tag++ << " " << node(i, 0) << " " << node(i + 1, 0) << "\n";
  o << "1 2 1 " << nx << "\n";
  for (int i = 0; i < nx; ++i) o << tag++ << " " << node(i, ny) << " " << node(i + 1, ny) << "\n";
  for (int half = 0; half < 2; ++half) {
    o << "2 " << half + 1 << " 3 " << (half == 0 ? left : nx - left) * ny << "\n";
    for (int j = 0; j < ny; ++j)
      for (int i = half == 0 ? 0 : left; i < (half == 0 ? left : nx); ++i)
        o << tag++ << " " << node(i, j) << " " << node(i + 1, j) << " " << node(i + 1, j + 1) << " " << node(i, j + 1) << "\n";
  }
  o << "$EndElements\n";
  return o.str();
}

/// squares_msh(n, n) with the square of the nodes (1, row), (2, row), (2, row + 1), (1, row + 1)
/// (counted from the lower left corner) given the nodes at `corners` (0 to 3: of those four) in
/// their place.
inline std::string squares_msh_changing_a_square(int n, int row, std::array<int, 4> corners) {
  std::string text = squares_msh(n, n);
  const auto node = [&](int i, int j) { return std::to_string(j * (n + 1) + i + 1); };
  const std::array<std::string, 4> was{node(1, row), node(2, row), node(2, row + 1), node(1, row + 1)};
  const std::string square = " " + was[0] + " " + was[1] + " " + was[2] + " " + was[3] + "\n";
  std::string changed;
  for (int c : corners) changed += " " + was[static_cast<std::size_t>(c)];
  const auto at = text.find(square);
  if (at != std::string::npos) text.replace(at, square.size(), changed + "\n");
  return text;
}

/// squares_msh(n, n) with a defect inside the mesh: the square of the nodes (1, 1), (2, 1),
/// (2, 2), (1, 2) repeats its second node in place of its fourth.
inline std::string squares_msh_repeating_a_vertex(int n) { return squares_msh_changing_a_square(n, 1, {0, 1, 2, 1}); }

/// squares_msh(n, n) with a defect on its bottom: the square of the nodes (1, 0), (2, 0), (2, 1),
/// (1, 1) given as (1, 0), (2, 0), (1, 1), (2, 1), which crosses itself.
inline std::string squares_msh_crossing_on_the_bottom(int n) { return squares_msh_changing_a_square(n, 0, {0, 1, 3, 2}); }

}  // namespace hemivem::test
