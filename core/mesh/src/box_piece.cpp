// The boxes of a process's piece of a generated mesh (hemivem/mesh/box_piece.hpp); the pieces
// themselves are made by the generators (generators.cpp, generators3d.cpp), box by box.
#include <hemivem/mesh/box_piece.hpp>

#include "box_grid.hpp"
#include "box_sides.hpp"

#include <algorithm>
#include <string>

namespace hemivem {

bool makes_pieces(std::string_view generator) {
  return generator == "squares" || generator == "triangles" || generator == "cubes" || generator == "tetrahedra";
}

int cells_per_box(std::string_view generator) {
  if (generator == "squares" || generator == "cubes") return 1;
  if (generator == "triangles") return 2;
  if (generator == "tetrahedra") return 6;
  throw InputError("the generator '" + std::string(generator) +
                   "' makes no grid of boxes (squares, triangles, cubes and tetrahedra do)");
}

namespace detail {

PieceBoxes::PieceBoxes(int dim, std::array<int, 3> counts, const BoxPiece& piece)
    : all_(false), dim_(dim), counts_(counts) {
  if (dim == 2) counts_[2] = 1;
  const int layer_axis = dim - 1;
  // the vertices of a layer along the last axis, and of the grid
  long long stride = 1;
  for (int a = 0; a < layer_axis; ++a) stride *= counts_[static_cast<std::size_t>(a)] + 1;
  const long long vertices = stride * (counts_[static_cast<std::size_t>(layer_axis)] + 1);
  if (piece.first_vertex < 0 || piece.end_vertex < piece.first_vertex || piece.end_vertex > vertices)
    throw InputError("a piece of the mesh owns the vertices " + std::to_string(piece.first_vertex) + ", ..., " +
                     std::to_string(piece.end_vertex) + " (excluded): not a range of the mesh's " +
                     std::to_string(vertices) + " vertices");
  if (piece.end_vertex > piece.first_vertex) {
    // box layer k holds the vertex layers k and k + 1: those holding a vertex of the piece, and
    // one layer more on each side
    const auto first = static_cast<int>(piece.first_vertex / stride);
    const auto last = static_cast<int>((piece.end_vertex - 1) / stride);
    first_layer_ = std::max(0, first - 2);
    last_layer_ = std::min(counts_[static_cast<std::size_t>(layer_axis)] - 1, last + 1);
  }
  for (const std::string& side : piece.sides) {
    const auto [axis, upper] = box_side_axis(dim, side);
    (upper ? upper_ : lower_)[static_cast<std::size_t>(axis)] = true;
  }
}

bool PieceBoxes::operator()(int i, int j, int k) const {
  if (all_) return true;
  const std::array<int, 3> at{i, j, k};
  if (at[static_cast<std::size_t>(dim_ - 1)] >= first_layer_ && at[static_cast<std::size_t>(dim_ - 1)] <= last_layer_)
    return true;
  bool first_column = true;  // the boxes at index 0 across the layers
  for (int a = 0; a < dim_; ++a) {
    const auto s = static_cast<std::size_t>(a);
    if ((lower_[s] && at[s] == 0) || (upper_[s] && at[s] == counts_[s] - 1)) return true;
    if (a < dim_ - 1) first_column = first_column && at[s] == 0;
  }
  return first_column;
}

}  // namespace detail

namespace {

/// The whole numbers of the cells of the boxes `keep` makes, `per_box` cells a box, box by box in
/// the order of the grid (x fastest).
std::vector<int> cells_of_boxes(const detail::PieceBoxes& keep, std::array<int, 3> counts, int per_box) {
  std::vector<int> out;
  int box = 0;
  for (int k = 0; k < counts[2]; ++k)
    for (int j = 0; j < counts[1]; ++j)
      for (int i = 0; i < counts[0]; ++i, ++box)
        if (keep(i, j, k))
          for (int c = 0; c < per_box; ++c) out.push_back(per_box * box + c);
  return out;
}

}  // namespace

namespace detail {

void require_piece_generator(std::string_view generator, int dim) {
  const bool solid = dim == 3;
  if (solid ? generator != "cubes" && generator != "tetrahedra" : generator != "squares" && generator != "triangles")
    throw InputError(std::string("a process's piece of a mesh is made by the generators ") +
                     (solid ? "cubes and tetrahedra in a solid" : "squares and triangles in the plane") + " (got '" +
                     std::string(generator) + "'): every process makes the whole of any other mesh");
}

}  // namespace detail

std::vector<int> piece_cells(std::string_view generator, GridSize n, const BoxPiece& piece) {
  detail::require_piece_generator(generator, 2);
  return cells_of_boxes(detail::PieceBoxes(2, {n.nx, n.ny, 1}, piece), {n.nx, n.ny, 1}, cells_per_box(generator));
}

std::vector<int> piece_cells(std::string_view generator, GridSize3 n, const BoxPiece& piece) {
  detail::require_piece_generator(generator, 3);
  return cells_of_boxes(detail::PieceBoxes(3, {n.nx, n.ny, n.nz}, piece), {n.nx, n.ny, n.nz}, cells_per_box(generator));
}

}  // namespace hemivem
