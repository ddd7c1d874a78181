// The boxes of a process's piece of a generated mesh (hemivem/mesh/box_piece.hpp); the pieces
// themselves are made by the generators (generators.cpp, generators3d.cpp), box by box.
#include <hemivem/mesh/box_piece.hpp>

#include "box_grid.hpp"
#include "box_sides.hpp"

#include <algorithm>
#include <array>
#include <type_traits>
#include <string>

namespace hemivem {

bool makes_pieces(std::string_view generator) {
  return generator == "squares" || generator == "triangles" || generator == "distorted" || generator == "nonconvex" ||
         generator == "polar" || generator == "cubes" || generator == "tetrahedra";
}

int cells_per_box(std::string_view generator) {
  if (generator == "squares" || generator == "distorted" || generator == "nonconvex" || generator == "polar" ||
      generator == "cubes")
    return 1;
  if (generator == "triangles") return 2;
  if (generator == "tetrahedra") return 6;
  throw InputError("the generator '" + std::string(generator) +
                   "' makes no grid of boxes (squares, triangles, distorted, nonconvex, polar, cubes and tetrahedra do)");
}

BoxGridVertices::BoxGridVertices(std::string_view generator, int dim, std::array<int, 3> counts, GridClosure closure)
    : dim_(dim), counts_(counts), closure_(closure), fine_(generator == "nonconvex") {
  (void)cells_per_box(generator);
  if (dim == 2) counts_[2] = 1;
  if (!fine_) {
    count_ = 1;
    for (int a = 0; a < dim; ++a) count_ *= columns(a);
    if (closure_.centre) count_ -= columns(0) - 1;  // the first row is the centre alone
    return;
  }
  // rows r = 0, ..., 2 ny of the fine grid: the boundary's rows hold the corners, the others'
  // even rows every point, their odd rows the points between the corners inside
  const long long nx = counts_[0], rows = 2LL * counts_[1];
  row_start_.assign(static_cast<std::size_t>(rows + 2), 0);
  for (long long r = 0; r <= rows; ++r)
    row_start_[static_cast<std::size_t>(r + 1)] =
        row_start_[static_cast<std::size_t>(r)] + (r % 2 != 0 ? nx - 1 : (r == 0 || r == rows ? nx + 1 : 2 * nx + 1));
  count_ = row_start_.back();
}

long long BoxGridVertices::columns(int axis) const {
  const long long boxes = counts_[static_cast<std::size_t>(axis)];
  return axis == 0 && closure_.around ? boxes : boxes + 1;
}

std::array<long long, 3> BoxGridVertices::point(long long v) const {
  if (!fine_) {
    if (closure_.centre) {
      if (v == 0) return {0, 0, 0};
      v += columns(0) - 1;  // as if the first row were whole
    }
    std::array<long long, 3> at{0, 0, 0};
    for (int a = 0; a < dim_; ++a) {
      at[static_cast<std::size_t>(a)] = v % columns(a);
      v /= columns(a);
    }
    return at;
  }
  const auto [i, j] = fine_point(v);
  return {i / 2, j / 2, 0};
}

long long BoxGridVertices::corner(const std::array<long long, 3>& p) const {
  if (!fine_) {
    if (closure_.centre && p[1] == 0) return 0;
    long long v = 0, stride = 1;
    for (int a = 0; a < dim_; ++a) {
      v += p[static_cast<std::size_t>(a)] % columns(a) * stride;  // around a full turn, the last column the first
      stride *= columns(a);
    }
    return closure_.centre ? v - (columns(0) - 1) : v;
  }
  return fine_vertex(2 * p[0], 2 * p[1]);
}

std::array<long long, 2> BoxGridVertices::fine_point(long long v) const {
  const auto row = std::upper_bound(row_start_.begin(), row_start_.end(), v) - row_start_.begin() - 1;
  const long long p = v - row_start_[static_cast<std::size_t>(row)], rows = 2LL * counts_[1];
  return {row % 2 != 0 ? 2 * (p + 1) : (row == 0 || row == rows ? 2 * p : p), row};
}

long long BoxGridVertices::fine_vertex(long long i, long long j) const {
  const long long columns = 2LL * counts_[0], rows = 2LL * counts_[1];
  const long long first = row_start_[static_cast<std::size_t>(j)];
  if (j % 2 != 0) return i % 2 != 0 || i == 0 || i == columns ? -1 : first + i / 2 - 1;
  if (j == 0 || j == rows) return i % 2 != 0 ? -1 : first + i / 2;
  return first + i;
}

bool BoxGridVertices::on_side(std::span<const int> vertices) const {
  for (int axis = 0; axis < dim_; ++axis) {
    if (axis == 0 && closure_.around) continue;  // around a full turn: no first or last ray
    const long long top = fine_ ? 2LL * counts_[static_cast<std::size_t>(axis)] : columns(axis) - 1;
    bool low = true, high = true;
    for (const int v : vertices) {
      if (axis == 0 && closure_.centre && v == 0) continue;  // the centre of a disk lies on every ray
      const long long at = fine_ ? fine_point(v)[static_cast<std::size_t>(axis)] : point(v)[static_cast<std::size_t>(axis)];
      low = low && at == 0;
      high = high && at == top;
    }
    if (low || high) return true;
  }
  return false;
}

namespace {

/// grid_cut_facets of a plane or solid piece.
template <class MeshType>
std::vector<int> cut_facets_of_grid(const MeshType& piece, const BoxGridVertices& grid) {
  std::vector<int> out;
  for (const int f : piece.boundary_facets()) {
    bool on_side = false;
    if constexpr (std::is_same_v<MeshType, Mesh>) {
      const std::array<int, 2> ends{piece.edge(f).v0, piece.edge(f).v1};
      on_side = grid.on_side(ends);
    } else {
      on_side = grid.on_side(piece.face(f).vertices);
    }
    if (!on_side) out.push_back(f);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

std::vector<int> grid_cut_facets(const Mesh& piece, const BoxGridVertices& grid) { return cut_facets_of_grid(piece, grid); }
std::vector<int> grid_cut_facets(const Mesh3D& piece, const BoxGridVertices& grid) { return cut_facets_of_grid(piece, grid); }

namespace {

/// The number of box (i, j, k) of a grid of counts[0] x counts[1] x counts[2] boxes, x fastest.
std::size_t box_index(const std::array<int, 3>& counts, long long i, long long j, long long k) {
  return static_cast<std::size_t>((k * counts[1] + j) * counts[0] + i);
}

/// The box (i, j, k) numbered b (box_index).
std::array<long long, 3> box_at(const std::array<int, 3>& counts, std::size_t b) {
  const auto at = static_cast<long long>(b);
  return {at % counts[0], at / counts[0] % counts[1], at / (static_cast<long long>(counts[0]) * counts[1])};
}

/// Adds to the boxes `kept` flags (one flag per box of a grid of counts[0] x counts[1] x
/// counts[2], x fastest) the boxes around each edge of the grid that two kept boxes meet along
/// alone (diagonally across it, the other two not kept), until there is none: the surface of
/// the kept boxes is then one a solid mesh accepts (each boundary edge in two boundary faces).
void close_along_edges(std::vector<char>& kept, const std::array<int, 3>& counts) {
  const auto at = [&](std::array<long long, 3> box) -> char& { return kept[box_index(counts, box[0], box[1], box[2])]; };
  for (bool changed = true; changed;) {
    changed = false;
    for (int a = 0; a < 3; ++a) {  // the edges along axis a, between the boxes across axes b and c
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      for (long long s = 0; s < counts[static_cast<std::size_t>(a)]; ++s)
        for (long long p = 1; p < counts[static_cast<std::size_t>(b)]; ++p)
          for (long long q = 1; q < counts[static_cast<std::size_t>(c)]; ++q) {
            std::array<std::array<long long, 3>, 4> around{};  // (p-1, q-1), (p, q-1), (p-1, q), (p, q)
            for (int r = 0; r < 4; ++r) {
              around[static_cast<std::size_t>(r)][static_cast<std::size_t>(a)] = s;
              around[static_cast<std::size_t>(r)][static_cast<std::size_t>(b)] = p - 1 + (r & 1);
              around[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] = q - 1 + (r >> 1);
            }
            const bool k0 = at(around[0]), k1 = at(around[1]), k2 = at(around[2]), k3 = at(around[3]);
            if ((k0 && k3 && !k1 && !k2) || (k1 && k2 && !k0 && !k3)) {
              for (const auto& box : around) at(box) = 1;
              changed = true;
            }
          }
    }
  }
}

/// Adds to the boxes `kept` flags (as close_along_edges) a path of boxes from each part of them
/// that does not reach the grid's first column (the boxes at i = 0, and j = 0 in a solid) to it:
/// along x to i = 0, then in a solid along y to j = 0. The kept boxes are then one connected body,
/// as the whole grid is (a part apart would be a body of its own, free where the whole is held).
void join_to_first_column(std::vector<char>& kept, const std::array<int, 3>& counts, int dim) {
  const long long nx = counts[0], ny = counts[1], nz = counts[2];
  const auto index = [&](long long i, long long j, long long k) { return box_index(counts, i, j, k); };
  std::vector<char> reached(kept.size(), 0);
  std::vector<std::size_t> queue;
  const auto reach = [&](std::size_t b) {
    if (kept[b] && !reached[b]) {
      reached[b] = 1;
      queue.push_back(b);
    }
  };
  const auto spread = [&] {  // every kept box joined by faces to those reached
    while (!queue.empty()) {
      const auto [i, j, k] = box_at(counts, queue.back());
      queue.pop_back();
      if (i > 0) reach(index(i - 1, j, k));
      if (i + 1 < nx) reach(index(i + 1, j, k));
      if (j > 0) reach(index(i, j - 1, k));
      if (j + 1 < ny) reach(index(i, j + 1, k));
      if (k > 0) reach(index(i, j, k - 1));
      if (k + 1 < nz) reach(index(i, j, k + 1));
    }
  };
  for (long long k = 0; k < nz; ++k)
    for (long long j = 0; j < (dim == 2 ? ny : 1); ++j) reach(index(0, j, k));
  spread();
  for (std::size_t b = 0; b < kept.size(); ++b) {
    if (!kept[b] || reached[b]) continue;
    const auto [i, j, k] = box_at(counts, b);
    const auto join = [&](std::size_t c) {  // a box of the path: kept, and reached from the first column
      kept[c] = 1;
      reach(c);
    };
    for (long long x = 0; x <= i; ++x) join(index(x, j, k));
    if (dim == 3)
      for (long long y = 0; y < j; ++y) join(index(0, y, k));
    spread();
  }
}

}  // namespace

namespace detail {

PieceBoxes::PieceBoxes(std::string_view generator, int dim, std::array<int, 3> counts, const BoxPiece& piece,
                       GridClosure closure)
    : all_(false), dim_(dim), counts_(counts) {
  if (dim == 2) counts_[2] = 1;
  const auto layer_axis = static_cast<std::size_t>(dim - 1);
  const BoxGridVertices grid(generator, dim, counts_, closure);
  const long long vertices = grid.count();
  if (piece.first_vertex < 0 || piece.end_vertex < piece.first_vertex || piece.end_vertex > vertices)
    throw InputError("a piece of the mesh owns the vertices " + std::to_string(piece.first_vertex) + ", ..., " +
                     std::to_string(piece.end_vertex) + " (excluded): not a range of the mesh's " +
                     std::to_string(vertices) + " vertices");
  if (piece.end_vertex > piece.first_vertex) {
    // box layer k holds the vertex layers k and k + 1: those holding a vertex of the piece, and
    // one layer more on each side
    const auto first = static_cast<int>(grid.point(piece.first_vertex)[layer_axis]);
    const auto last = static_cast<int>(grid.point(piece.end_vertex - 1)[layer_axis]);
    first_layer_ = std::max(0, first - 2);
    last_layer_ = std::min(counts_[layer_axis] - 1, last + 1);
  }
  for (const std::string& side : piece.sides) {
    const auto [axis, upper] = box_side_axis(dim, side);
    (upper ? upper_ : lower_)[static_cast<std::size_t>(axis)] = true;
  }
  if (!piece.owned.empty() || !piece.held.empty()) {
    // the boxes within two boxes of a flagged or held vertex along every axis, with those of the
    // rules above, joined into one body and closed so that no two of them meet along an edge alone
    if (!piece.owned.empty() && static_cast<long long>(piece.owned.size()) != vertices)
      throw InputError("a piece of the mesh flags " + std::to_string(piece.owned.size()) + " vertices: not one flag per " +
                       "vertex of the mesh's " + std::to_string(vertices));
    const auto axis_count = [&](int a) { return static_cast<long long>(counts_[static_cast<std::size_t>(a)]); };
    near_.assign(static_cast<std::size_t>(axis_count(0) * axis_count(1) * axis_count(2)), 0);
    const auto keep_around = [&](long long v) {
      const std::array<long long, 3> at = grid.point(v);
      const bool centre = closure.centre && v == 0;  // a corner of every box of the first ring
      std::array<long long, 3> lo{0, 0, 0}, hi{0, 0, 0};
      for (int a = 0; a < dim; ++a) {
        lo[static_cast<std::size_t>(a)] = std::max(0LL, at[static_cast<std::size_t>(a)] - 2);
        hi[static_cast<std::size_t>(a)] = std::min(axis_count(a) - 1, at[static_cast<std::size_t>(a)] + 1);
      }
      if (closure.around || centre) {  // along x around the turn, or every box
        lo[0] = centre ? 0 : at[0] - 2;
        hi[0] = centre ? axis_count(0) - 1 : std::min(at[0] + 1, at[0] - 2 + axis_count(0) - 1);
      }
      for (long long k = lo[2]; k <= hi[2]; ++k)
        for (long long j = lo[1]; j <= hi[1]; ++j)
          for (long long i = lo[0]; i <= hi[0]; ++i)
            near_[box_index(counts_, (i % axis_count(0) + axis_count(0)) % axis_count(0), j, k)] = 1;
    };
    for (std::size_t v = 0; v < piece.owned.size(); ++v)
      if (piece.owned[v]) keep_around(static_cast<long long>(v));
    for (const int v : piece.held) {
      if (v < 0 || v >= vertices)
        throw InputError("a piece of the mesh holds the vertex " + std::to_string(v) + ": not one of the mesh's " +
                         std::to_string(vertices));
      keep_around(v);
    }
    for (long long k = 0; k < axis_count(2); ++k)
      for (long long j = 0; j < axis_count(1); ++j)
        for (long long i = 0; i < axis_count(0); ++i)
          if (by_rules(static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)))
            near_[box_index(counts_, i, j, k)] = 1;
    join_to_first_column(near_, counts_, dim);
    if (dim == 3) close_along_edges(near_, counts_);
  }
}

bool PieceBoxes::operator()(int i, int j, int k) const {
  if (all_) return true;
  if (!near_.empty()) return near_[box_index(counts_, i, j, k)] != 0;
  return by_rules(i, j, k);
}

bool PieceBoxes::by_rules(int i, int j, int k) const {
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
  if (solid ? generator != "cubes" && generator != "tetrahedra"
            : generator != "squares" && generator != "triangles" && generator != "distorted" && generator != "nonconvex")
    throw InputError(std::string("a process's piece of a mesh is made by the generators ") +
                     (solid ? "cubes and tetrahedra in a solid" : "squares, triangles, distorted and nonconvex in the plane") +
                     " (got '" +
                     std::string(generator) + "'): every process makes the whole of any other mesh");
}

}  // namespace detail

std::vector<int> piece_cells(std::string_view generator, GridSize n, const BoxPiece& piece) {
  detail::require_piece_generator(generator, 2);
  return cells_of_boxes(detail::PieceBoxes(generator, 2, {n.nx, n.ny, 1}, piece), {n.nx, n.ny, 1}, cells_per_box(generator));
}

std::vector<int> piece_cells(std::string_view generator, GridSize3 n, const BoxPiece& piece) {
  detail::require_piece_generator(generator, 3);
  return cells_of_boxes(detail::PieceBoxes(generator, 3, {n.nx, n.ny, n.nz}, piece), {n.nx, n.ny, n.nz}, cells_per_box(generator));
}

}  // namespace hemivem
