// A process's piece of a generated mesh (hemivem/mesh/box_piece.hpp): every vertex of the whole
// mesh, and of its cells those near the process's vertices, along the named sides and in the first
// column, each as the whole makes it; the piece a process keeps of a mesh made whole
// (hemivem/mesh/mesh_piece.hpp, cut_problem_piece of hemivem/scene/scene_pieces.hpp); and the
// share of the full-space route posed from either (pose_share, hemivem/contact/pose_share.hpp),
// which is the share posed from the whole mesh.
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/box_piece.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/scene_pieces.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "gmsh_squares.hpp"
#include "piece_parts.hpp"
#include "posed_share_checks.hpp"
#include "pressed_block3d.hpp"
#include "test_support.hpp"
#include "thread_rows.hpp"
#include "thread_rows.hpp"

using namespace hemivem;
using hemivem::test::expect_same_share;
using hemivem::test::expect_whole_bodies;
using hemivem::test::facets_of_cell;
using hemivem::test::sorted_facets;
using hemivem::test::WholeParts;

namespace {

/// A cell's vertex loops, each turned to start at its smallest vertex, in order: the cell as the
/// mesh holds it whatever the numbering of its faces.
std::vector<std::vector<int>> loops_of(const Mesh& mesh, int e) {
  return {std::vector<int>(mesh.element(e).begin(), mesh.element(e).end())};
}
std::vector<std::vector<int>> loops_of(const Mesh3D& mesh, int c) {
  std::vector<std::vector<int>> loops = mesh.cell(c);
  for (auto& l : loops) std::rotate(l.begin(), std::min_element(l.begin(), l.end()), l.end());
  std::sort(loops.begin(), loops.end());
  return loops;
}

int num_cells_of(const Mesh& mesh) { return mesh.num_elements(); }
int num_cells_of(const Mesh3D& mesh) { return mesh.num_cells(); }

/// Whether cell c holds a vertex in [v0, v1).
template <class M>
bool holds_vertex(const M& mesh, int c, int v0, int v1) {
  for (const auto& loop : loops_of(mesh, c))
    for (int v : loop)
      if (v >= v0 && v < v1) return true;
  return false;
}

/// The piece holds every vertex of `whole` where the whole has it; its cells are the cells `cells`
/// of the whole (piece_cells), each once and in the whole's order; among them every cell holding one of [v0, v1) and every
/// cell with a facet on `facets` (boundary facets of the whole given by their sorted vertices);
/// and it holds fewer cells than the whole when `smaller`.
template <class M>
void expect_piece_of(const M& piece, const std::vector<int>& cells, const M& whole, int v0, int v1,
                     const std::set<std::vector<int>>& facets, bool smaller) {
  SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
  ASSERT_EQ(piece.num_vertices(), whole.num_vertices());
  for (int v = 0; v < whole.num_vertices(); ++v) ASSERT_EQ(piece.vertex(v), whole.vertex(v)) << "vertex " << v;
  std::map<std::vector<std::vector<int>>, int> cell_of;
  for (int c = 0; c < num_cells_of(whole); ++c) cell_of[loops_of(whole, c)] = c;
  int last = -1;
  std::set<int> held;
  ASSERT_EQ(cells.size(), static_cast<std::size_t>(num_cells_of(piece)));
  for (int c = 0; c < num_cells_of(piece); ++c) {
    const auto at = cell_of.find(loops_of(piece, c));
    ASSERT_NE(at, cell_of.end()) << "cell " << c << " of the piece is no cell of the whole";
    EXPECT_EQ(at->second, cells[static_cast<std::size_t>(c)]) << "cell " << c << "'s number in the whole";
    EXPECT_GT(at->second, last) << "the whole's order of cells";
    last = at->second;
    held.insert(at->second);
  }
  for (int c = 0; c < num_cells_of(whole); ++c) {
    if (holds_vertex(whole, c, v0, v1)) EXPECT_TRUE(held.count(c)) << "cell " << c << " holds a vertex of the piece";
    for (const auto& loop : loops_of(whole, c)) {
      std::vector<int> sorted = loop;
      std::sort(sorted.begin(), sorted.end());
      if (facets.count(sorted)) EXPECT_TRUE(held.count(c)) << "cell " << c << " lies along a named side";
    }
  }
  if (smaller) EXPECT_LT(num_cells_of(piece), num_cells_of(whole));
}

/// grid_cut_facets of the piece `made` (the whole's cells `cells`) are its boundary facets inside
/// the whole mesh (boundary facets of the piece cut from the whole that are none of the whole's),
/// increasing; some when `some`.
template <class M>
void expect_cut_facets(const M& made, const std::vector<int>& cells, const M& whole, const BoxGridVertices& grid, bool some) {
  const M cut = cut_mesh_piece(whole, cells);
  std::set<std::vector<int>> inside = sorted_facets(cut, cut.boundary_facets());
  for (const auto& key : sorted_facets(whole, whole.boundary_facets())) inside.erase(key);
  const std::vector<int> found = grid_cut_facets(made, grid);
  EXPECT_EQ(std::adjacent_find(found.begin(), found.end(), std::greater_equal<>()), found.end()) << "not increasing";
  EXPECT_EQ(sorted_facets(made, found), inside);
  EXPECT_EQ(inside.empty(), !some);
}

/// The thirds of the vertices, and an empty range.
std::vector<std::pair<int, int>> thirds(int n) { return {{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {n / 2, n / 2}}; }

// how each generator numbers its vertices: the grid point of each is the corner of the boxes at
// or below it (within the box above and to the right of it), and the corner at each grid point
// lies there
TEST(BoxPiece, EachVertexLiesAtItsGridPointAndEachCornerIsTheVertexThere) {
  const Rectangle domain{0.0, 2.0, 0.0, 1.0};
  const GridSize n(8, 6);
  const double hx = 2.0 / 8, hy = 1.0 / 6;
  for (const std::string generator : {"squares", "distorted", "nonconvex"}) {
    SCOPED_TRACE(generator);
    const Mesh whole = make_mesh(generator, n, domain, 7);
    const BoxGridVertices grid(generator, 2, {n.nx, n.ny, 1});
    ASSERT_EQ(grid.count(), whole.num_vertices());
    const double off = generator == "distorted" ? 0.2 : 0.0;  // a box's sides the vertices inside move
    long long last_row = 0;
    for (int v = 0; v < whole.num_vertices(); ++v) {
      const auto p = grid.point(v);
      const Vec2 x = whole.vertex(v);
      EXPECT_GE(x.x(), (p[0] - off) * hx - 1e-12) << "vertex " << v;
      EXPECT_LT(x.x(), (p[0] + 1) * hx) << "vertex " << v;
      EXPECT_GE(x.y(), (p[1] - off) * hy - 1e-12) << "vertex " << v;
      EXPECT_LT(x.y(), (p[1] + 1) * hy) << "vertex " << v;
      EXPECT_GE(p[1], last_row) << "layer by layer";
      last_row = p[1];
    }
    for (long long j = 0; j <= n.ny; ++j)
      for (long long i = 0; i <= n.nx; ++i) {
        const long long v = grid.corner({i, j, 0});
        ASSERT_LT(v, whole.num_vertices());
        EXPECT_EQ(grid.point(v), (std::array<long long, 3>{i, j, 0}));
        if (generator != "distorted" || i == 0 || j == 0 || i == n.nx || j == n.ny)
          EXPECT_LT((whole.vertex(static_cast<int>(v)) - Vec2(i * hx, j * hy)).norm(), 1e-12) << i << ", " << j;
      }
  }
  const BoxGridVertices cubes("cubes", 3, {3, 2, 4});
  EXPECT_EQ(cubes.count(), 4 * 3 * 5);
  EXPECT_EQ(cubes.corner({1, 2, 3}), 1 + 2 * 4 + 3 * 12);
  EXPECT_EQ(cubes.point(1 + 2 * 4 + 3 * 12), (std::array<long long, 3>{1, 2, 3}));
}

// squares, triangles, distorted squares (each piece holds every vertex, moved as the whole
// mesh's of the same seed) and the nonconvex cells (a grid twice as fine, BoxGridVertices)
TEST(BoxPiece, APlanePieceHoldsTheCellsOfItsVerticesAndItsSides) {
  const Rectangle domain{0.0, 2.0, 0.0, 1.0};
  for (const std::string generator : {"squares", "triangles", "distorted", "nonconvex"}) {
    SCOPED_TRACE(generator);
    const Mesh whole = make_mesh(generator, GridSize(8, 12), domain, 7);
    const std::set<std::vector<int>> bottom =
        sorted_facets(whole, select_boundary_edges(whole, {rectangle_side(whole.bounding_box(), "bottom")}));
    const BoxGridVertices grid(generator, 2, {8, 12, 1});
    for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
      const BoxPiece piece{v0, v1, {"bottom"}};
      const Mesh made = make_mesh_piece(generator, GridSize(8, 12), domain, piece, 7);
      expect_piece_of(made, piece_cells(generator, GridSize(8, 12), piece), whole, v0, v1, bottom, true);
      expect_cut_facets(made, piece_cells(generator, GridSize(8, 12), piece), whole, grid, true);
    }
  }
  EXPECT_NE(make_mesh_piece("distorted", GridSize(8, 12), domain, BoxPiece{0, 10, {}}, 7).vertex(10),
            make_mesh_piece("distorted", GridSize(8, 12), domain, BoxPiece{0, 10, {}}, 8).vertex(10))
      << "the seed moves the vertices inside";
}

TEST(BoxPiece, ASolidPieceHoldsTheCellsOfItsVerticesAndItsSides) {
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  for (const std::string generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    const Mesh3D whole = make_mesh3d(generator, GridSize3(4, 3, 9), domain);
    std::set<std::vector<int>> sides = sorted_facets(whole, select_box_side(whole, domain, "bottom"));
    const auto x1 = sorted_facets(whole, select_box_side(whole, domain, "x1"));
    sides.insert(x1.begin(), x1.end());
    const BoxGridVertices grid(generator, 3, {4, 3, 9});
    for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
      const BoxPiece piece{v0, v1, {"bottom", "x1"}};
      const Mesh3D made = make_mesh3d_piece(generator, GridSize3(4, 3, 9), domain, piece);
      expect_piece_of(made, piece_cells(generator, GridSize3(4, 3, 9), piece), whole, v0, v1, sides, true);
      expect_cut_facets(made, piece_cells(generator, GridSize3(4, 3, 9), piece), whole, grid, true);
    }
  }
}

/// The number of connected parts of a mesh: cells joined across their facets.
template <class M>
int parts_of(const M& mesh) {
  std::vector<int> parent(static_cast<std::size_t>(num_cells_of(mesh)));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int c) {
    while (parent[static_cast<std::size_t>(c)] != c) c = parent[static_cast<std::size_t>(c)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(c)])];
    return c;
  };
  std::map<std::vector<int>, int> first_cell;
  for (int c = 0; c < num_cells_of(mesh); ++c)
    for (const auto& f : facets_of_cell(mesh, c))
      if (const auto [at, fresh] = first_cell.emplace(f, c); !fresh) parent[static_cast<std::size_t>(root(c))] = root(at->second);
  int parts = 0;
  for (int c = 0; c < num_cells_of(mesh); ++c) parts += root(c) == c ? 1 : 0;
  return parts;
}

/// The piece of the vertices `flags` flags holds, besides what expect_piece_of checks, every
/// cell of the whole holding one of them, and is one connected body as the whole is.
template <class M>
void expect_flagged_piece_of(const M& piece, const std::vector<int>& cells, const M& whole, const std::vector<char>& flags,
                             const std::set<std::vector<int>>& facets) {
  expect_piece_of(piece, cells, whole, 0, 0, facets, true);
  EXPECT_EQ(parts_of(piece), 1);
  const std::set<int> held(cells.begin(), cells.end());
  for (int c = 0; c < num_cells_of(whole); ++c)
    for (const auto& loop : loops_of(whole, c))
      for (int v : loop)
        if (flags[static_cast<std::size_t>(v)]) EXPECT_TRUE(held.count(c)) << "cell " << c << " holds flagged vertex " << v;
}

// a share flagged vertex by vertex, a third of the mesh's Hilbert order: the piece holds the
// cells of its vertices and of the boxes next to them, fewer than the whole
TEST(BoxPiece, APieceOfFlaggedVerticesHoldsTheirCells) {
  const Box box{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  const Rectangle rectangle{0.0, 2.0, 0.0, 1.0};
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("third " + std::to_string(rank));
    for (const std::string generator : {"cubes", "tetrahedra"}) {
      SCOPED_TRACE(generator);
      const GridSize3 n(6, 5, 7);
      const Mesh3D whole = make_mesh3d(generator, n, box);
      const auto [first, end] = vertex_share(whole.num_vertices(), rank, 3);
      const std::vector<char> flags = VertexShare{first, end, hilbert_vertex_order(whole)}.mask(whole.num_vertices());
      const BoxPiece piece{0, 0, {"bottom"}, flags};
      expect_flagged_piece_of(make_mesh3d_piece(generator, n, box, piece), piece_cells(generator, n, piece), whole, flags,
                              sorted_facets(whole, select_box_side(whole, box, "bottom")));
    }
    for (const std::string generator : {"squares", "triangles"}) {
      SCOPED_TRACE(generator);
      const GridSize n(9, 8);
      const Mesh whole = make_mesh(generator, n, rectangle);
      const auto [first, end] = vertex_share(whole.num_vertices(), rank, 3);
      const std::vector<char> flags = VertexShare{first, end, hilbert_vertex_order(whole)}.mask(whole.num_vertices());
      const BoxPiece piece{0, 0, {"top"}, flags};
      expect_flagged_piece_of(make_mesh_piece(generator, n, rectangle, piece), piece_cells(generator, n, piece), whole, flags,
                              sorted_facets(whole, select_boundary_edges(whole, {rectangle_side(whole.bounding_box(), "top")})));
    }
  }
  // the 64ths of a cube of 12 x 12 x 12 boxes without sides: many lie inside, apart from the
  // first column, and are joined to it
  const Mesh3D cube = make_cubes(GridSize3(12, 12, 12));
  const std::vector<int> order = hilbert_vertex_order(cube);
  for (int rank = 0; rank < 64; ++rank) {
    SCOPED_TRACE("64th " + std::to_string(rank));
    const auto [first, end] = vertex_share(cube.num_vertices(), rank, 64);
    const std::vector<char> flags = VertexShare{first, end, order}.mask(cube.num_vertices());
    const BoxPiece piece{0, 0, {}, flags};
    expect_flagged_piece_of(make_mesh3d_piece("cubes", GridSize3(12, 12, 12), Box{}, piece),
                            piece_cells("cubes", GridSize3(12, 12, 12), piece), cube, flags, {});
  }
  EXPECT_NE(test::input_error_of([] { (void)make_mesh3d_piece("cubes", 1, Box{}, BoxPiece{0, 0, {}, std::vector<char>(5, 1)}); })
                .find("flags 5 vertices: not one flag per vertex of the mesh's 8"),
            std::string::npos);
}

/// Each edge group of `piece` is the whole's edges of that group that a cell of the piece holds,
/// by their vertices.
void expect_groups_of_the_whole(const Mesh& piece, const Mesh& whole) {
  ASSERT_EQ(piece.edge_groups().size(), whole.edge_groups().size());
  std::set<std::pair<int, int>> piece_edges;
  for (int e = 0; e < piece.num_edges(); ++e)
    piece_edges.insert(std::minmax(piece.edge(e).v0, piece.edge(e).v1));
  for (const auto& [name, edges] : whole.edge_groups()) {
    SCOPED_TRACE(name);
    std::set<std::pair<int, int>> expected;
    for (int e : edges) {
      const auto key = std::minmax(whole.edge(e).v0, whole.edge(e).v1);
      if (piece_edges.count(key)) expected.insert(key);
    }
    std::set<std::pair<int, int>> got;
    for (int e : piece.edge_group(name)) got.insert(std::minmax(piece.edge(e).v0, piece.edge(e).v1));
    EXPECT_EQ(got, expected);
  }
}

// a polar grid (a ring or a disk, whole or a sector of it) is a grid of boxes, sector along x and
// ring along y: a full turn's last column of vertices is its first, a disk's first row its centre.
// Each vertex lies at its grid point; a piece of a range of them, or of flagged vertices (a third
// of the Hilbert order, across the first and last sectors of a turn, at the centre), holds the
// cells around them, those of a named side and those around a vertex held, joined into one body,
// and the edge groups of the whole
TEST(BoxPiece, APolarPieceHoldsTheCellsOfItsVerticesItsSidesAndItsHeldVertex) {
  const double pi = std::numbers::pi;
  std::vector<double> ring, disk, turn, quarter;
  for (int k = 0; k <= 9; ++k) {
    ring.push_back(0.5 + 0.5 * std::pow(k / 9.0, 1.2));
    disk.push_back(k / 9.0);
  }
  for (int k = 0; k <= 16; ++k) turn.push_back(2.0 * pi * k / 16);
  for (int k = 0; k <= 7; ++k) quarter.push_back(0.5 * pi * k / 7);
  const Vec2 centre(0.25, -0.5);
  for (const auto* radii : {&ring, &disk})
    for (const auto* angles : {&turn, &quarter}) {
      SCOPED_TRACE((radii == &ring ? "ring, " : "disk, ") + std::string(angles == &turn ? "a full turn" : "a quarter"));
      const Mesh whole = make_polar(centre, *radii, *angles);
      const int m = static_cast<int>(radii->size()) - 1, n = static_cast<int>(angles->size()) - 1;
      const GridClosure closure{angles == &turn, radii == &disk};
      const BoxGridVertices grid("polar", 2, {n, m, 1}, closure);
      ASSERT_EQ(grid.count(), whole.num_vertices());
      for (int v = 0; v < whole.num_vertices(); ++v) {
        const auto p = grid.point(v);
        const double r = (*radii)[static_cast<std::size_t>(p[1])], a = (*angles)[static_cast<std::size_t>(p[0])];
        EXPECT_LT((whole.vertex(v) - centre - r * Vec2(std::cos(a), std::sin(a))).norm(), 1e-14) << "vertex " << v;
        EXPECT_EQ(grid.corner(p), v);
      }
      EXPECT_EQ(grid.corner({n, m, 0}), closure.around ? grid.corner({0, m, 0}) : whole.num_vertices() - 1);
      const std::set<std::vector<int>> outer = sorted_facets(whole, whole.edge_group("outer"));
      for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
        const BoxPiece piece{v0, v1, {"top"}};
        const Mesh made = make_polar_piece(centre, *radii, *angles, piece);
        expect_piece_of(made, polar_piece_cells(*radii, *angles, piece), whole, v0, v1, outer, v1 - v0 > 0);
        expect_groups_of_the_whole(made, whole);
        expect_cut_facets(made, polar_piece_cells(*radii, *angles, piece), whole, grid, true);
      }
      const std::vector<int> order = hilbert_vertex_order(whole);
      for (int rank = 0; rank < 3; ++rank) {
        SCOPED_TRACE("third " + std::to_string(rank));
        const auto [first, end] = vertex_share(whole.num_vertices(), rank, 3);
        const std::vector<char> flags = VertexShare{first, end, order}.mask(whole.num_vertices());
        const BoxPiece piece{0, 0, {}, flags};
        const Mesh made = make_polar_piece(centre, *radii, *angles, piece);
        expect_flagged_piece_of(made, polar_piece_cells(*radii, *angles, piece), whole, flags, {});
        expect_groups_of_the_whole(made, whole);
        expect_cut_facets(made, polar_piece_cells(*radii, *angles, piece), whole, grid, true);
      }
      // a vertex of the last sector, and the centre or a vertex of the first ring, flagged or held
      const int last = static_cast<int>(grid.corner({n - 1, m - 1, 0})), inside = static_cast<int>(grid.corner({1, 0, 0}));
      std::vector<char> flags(static_cast<std::size_t>(whole.num_vertices()), 0);
      flags[static_cast<std::size_t>(last)] = 1;
      const BoxPiece flagged{0, 0, {}, flags, {inside}};
      expect_flagged_piece_of(make_polar_piece(centre, *radii, *angles, flagged), polar_piece_cells(*radii, *angles, flagged),
                              whole, flags, {});
      flags[static_cast<std::size_t>(inside)] = 1;  // the held vertex's cells are the piece's as a flagged one's
      const std::vector<int> cells = polar_piece_cells(*radii, *angles, flagged);
      const std::set<int> held(cells.begin(), cells.end());
      for (int c = 0; c < whole.num_elements(); ++c)
        for (int v : whole.element(c))
          if (flags[static_cast<std::size_t>(v)]) EXPECT_TRUE(held.count(c)) << "cell " << c << " holds vertex " << v;
    }
}

// a piece of all the vertices is the whole mesh
TEST(BoxPiece, APieceOfEveryVertexIsTheWholeMesh) {
  const Mesh3D whole = make_cubes(GridSize3(3, 2, 4));
  const Mesh3D piece = make_mesh3d_piece("cubes", GridSize3(3, 2, 4), Box{}, BoxPiece{0, whole.num_vertices(), {}});
  EXPECT_EQ(piece.num_cells(), whole.num_cells());
  EXPECT_EQ(piece.num_faces(), whole.num_faces());
}

TEST(BoxPiece, WhatMakesNoPieceIsRefusedByName) {
  const auto error = [](auto&& f) { return test::input_error_of(f); };
  EXPECT_NE(error([] { (void)make_mesh3d_piece("voronoi", 4, Box{}, BoxPiece{0, 5, {}}); }).find("cubes and tetrahedra"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh_piece("voronoi", 4, Rectangle{}, BoxPiece{0, 5, {}}); }).find("squares, triangles, distorted and nonconvex"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh3d_piece("cubes", 4, Box{}, BoxPiece{0, 5, {"left"}}); }).find("unknown side 'left'"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh_piece("squares", 4, Rectangle{}, BoxPiece{0, 5, {"x0"}}); }).find("unknown side 'x0'"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh_piece("squares", 4, Rectangle{}, BoxPiece{0, 26, {}}); }).find("25 vertices"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh3d_piece("cubes", 0, Box{}, BoxPiece{0, 1, {}}); }).find("cubes mesh"),
            std::string::npos);
  EXPECT_NE(error([] { (void)piece_cells("voronoi", GridSize3(4), BoxPiece{0, 5, {}}); }).find("cubes and tetrahedra"),
            std::string::npos);
  EXPECT_NE(error([] { (void)make_mesh_piece("squares", 4, Rectangle{}, BoxPiece{0, 5, {}, {}, {25}}); }).find("holds the vertex 25"),
            std::string::npos);
  EXPECT_TRUE(makes_pieces("tetrahedra"));
  EXPECT_FALSE(makes_pieces("voronoi"));
  EXPECT_NE(error([] { (void)cells_per_box("voronoi"); }).find("'voronoi' makes no grid of boxes"), std::string::npos);
}

// Example 4.1: a process posing its share from its piece poses the share of the whole mesh
TEST(BoxPiece, TheShareOfAPlanePieceIsTheShareOfTheWholeMesh) {
  const GridSize n(12, 12);
  const Mesh whole = make_squares(n);
  const ContactProblem from_whole = example_4_1(whole);
  for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
    SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
    const Mesh piece = make_mesh_piece("squares", n, Rectangle{}, BoxPiece{v0, v1, {"left", "right", "top", "bottom"}});
    ASSERT_LT(piece.num_elements(), whole.num_elements());
    expect_same_share(pose_share(example_4_1(piece), v0, v1), pose_share(from_whole, v0, v1));
  }
}

TEST(BoxPiece, TheShareOfASolidPieceIsTheShareOfTheWholeMesh) {
  const GridSize3 n(6, 3, 15);
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  for (const std::string generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    const Mesh3D whole = make_mesh3d(generator, n, domain);
    const ContactProblem3D from_whole = test::example_4_1_3d(whole);
    for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
      SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
      const Mesh3D piece = make_mesh3d_piece(generator, n, domain, BoxPiece{v0, v1, {"x0", "x1", "top", "bottom"}});
      ASSERT_LT(piece.num_cells(), whole.num_cells());
      expect_same_share(pose_share(test::example_4_1_3d(piece), v0, v1), pose_share(from_whole, v0, v1));
    }
  }
}

// what the supports leave free is named alike on a piece and on the whole mesh: a rotation about
// the body's centre, whatever the piece's cells
TEST(BoxPiece, WhatThePiecesSupportsLeaveFreeIsNamedAsOnTheWholeMesh) {
  const GridSize3 n(6, 3, 15);
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  const Mesh3D whole = make_cubes(n, domain);
  ContactProblem3D from_whole = test::example_4_1_3d(whole);
  from_whole.elasticity.dirichlet.clear();
  const std::string expected = test::input_error_of([&] { (void)pose_share(from_whole, 0, 10); });
  ASSERT_NE(expected.find("rotation"), std::string::npos) << expected;
  for (const auto& [v0, v1] : thirds(whole.num_vertices())) {
    SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
    const Mesh3D piece = make_mesh3d_piece("cubes", n, domain, BoxPiece{v0, v1, {"top", "bottom"}});
    ContactProblem3D on_piece = test::example_4_1_3d(piece);
    on_piece.elasticity.dirichlet.clear();
    EXPECT_EQ(test::input_error_of([&] { (void)pose_share(on_piece, v0, v1); }), expected);
  }
}

/// The pieces `size` processes make of the scene's generated box (scene_piece,
/// build_problem_piece, the processes played by threads), without the whole mesh: each a piece
/// of the whole holding every cell of the process's vertices, of the contact, and around every
/// vertex a support at a point holds; of the supports and loads the whole's facets among its
/// cells, and every vertex each support holds of the whole; the share it poses the whole mesh's to
/// the bit. Returns how many pieces hold fewer facets of the supports and loads than the whole.
template <int dim>
int expect_scene_pieces_pose_the_whole_share(const Scene& scene, int size) {
  const auto whole = build_problem<dim>(scene);
  const WholeParts<dim> parts(*whole);
  std::set<int> pinned;  // the vertices supported alone
  for (const auto& d : whole->problem.elasticity.dirichlet) pinned.insert(d.vertices.begin(), d.vertices.end());
  const auto pieces = test::on_threads(size, [&](const test::ThreadRows& rows) {
    return build_problem_piece<dim>(scene, *scene_piece(scene, rows.rank(), size), rows);
  });
  int apart = 0;  // pieces whose own vertices' cells miss a pinned vertex's
  int fewer = 0;  // pieces holding fewer of the supports' and loads' facets than the whole
  for (int rank = 0; rank < size; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank) + " of " + std::to_string(size));
    const std::optional<BoxPiece> piece = scene_piece(scene, rank, size);
    if (!piece) {
      ADD_FAILURE() << "no piece";
      return fewer;
    }
    const PieceOfMesh where = scene_piece_of_mesh(scene, *piece);
    const auto& built = pieces[static_cast<std::size_t>(rank)];
    expect_piece_of(built->mesh, where.cells, whole->mesh, piece->first_vertex, piece->end_vertex, parts.contact, true);
    // one connected body, every vertex of which lies on it (piece_bodies)
    expect_whole_bodies(*built, *whole);
    EXPECT_EQ(BasicRigidMotions<dim>(built->mesh, make_dof_map(built->mesh, {})).num_pieces(), 1);
    const std::set<int> held(where.cells.begin(), where.cells.end());
    for (const int v : pinned) {
      bool slab = true;
      for (int c = 0; c < num_cells_of(whole->mesh); ++c) {
        if (!holds_vertex(whole->mesh, c, v, v + 1)) continue;
        EXPECT_TRUE(held.count(c)) << "cell " << c << " around the supported vertex " << v;
        slab = slab && holds_vertex(whole->mesh, c, piece->first_vertex, piece->end_vertex);
      }
      apart += slab ? 0 : 1;
    }
    fewer += parts.expect_held_by(*built, whole->mesh, held, true, true) ? 1 : 0;
    expect_same_share(pose_share(built->problem, piece->first_vertex, piece->end_vertex),
                      pose_share(whole->problem, piece->first_vertex, piece->end_vertex));
  }
  if (!pinned.empty()) EXPECT_GT(apart, 0) << "every piece held the supported vertices' cells among its own";
  return fewer;
}

// clamped on its top alone, or on a segment of it, of which the middle slab's piece holds the
// first column's facet or none: each piece holds the clamped vertices of the others besides its
// own facets, and the body held whole (its free motions judged of every vertex the support
// holds, every vertex of a piece lying on the body)
TEST(BoxPiece, APieceThatMeetsNoFacetOfASupportIsHeldByIt) {
  Scene plane = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  plane.mesh.n = 12;
  plane.clamped.sides = {"top"};
  plane.tractions[0].boundary.sides = {"right"};
  plane.tractions[0].value = {SceneScalar{-2.0}, SceneScalar{0.0}, SceneScalar{0.0}};
  {
    SCOPED_TRACE("a plane clamped on its top");
    EXPECT_EQ(expect_scene_pieces_pose_the_whole_share<2>(plane, 3), 3);
  }
  plane.clamped.sides.clear();
  plane.clamped.segments = {{0.4, 1.0, 0.6, 1.0}};
  {
    SCOPED_TRACE("a plane clamped on a segment of its top");
    EXPECT_EQ(expect_scene_pieces_pose_the_whole_share<2>(plane, 3), 3);
  }
  Scene solid = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  solid.mesh.n = 4, solid.mesh.ny = 3, solid.mesh.nz = 12;
  solid.clamped.sides = {"top"};
  solid.tractions[0].boundary.sides = {"x1"};
  solid.tractions[0].value = {SceneScalar{-2.0}, SceneScalar{0.0}, SceneScalar{0.0}};
  for (const char* generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(std::string("a solid of ") + generator + " clamped on its top");
    solid.mesh.generator = generator;
    EXPECT_EQ(expect_scene_pieces_pose_the_whole_share<3>(solid, 3), 3);
  }
}

// supports at points, and loads on segments along a side: every piece holds the cells around
// each supported vertex (the grid vertex nearest the point) and every cell along the side
TEST(BoxPiece, APieceHoldsTheCellsAroundEachPointSupportAndAlongEachSegmentsSide) {
  Scene plate = parse_scene(test::scenes_dir() / "plate-friction-benchmark.toml");  // a corner held at a point
  plate.mesh.n = 12;
  {
    SCOPED_TRACE("plate-friction-benchmark");
    // the top's traction on the top piece alone
    EXPECT_GT(expect_scene_pieces_pose_the_whole_share<2>(plate, 3), 0);
  }
  ASSERT_EQ(plate.tractions.size(), 2u);  // the top's pressure on a segment of it
  plate.tractions[0].boundary = BoundarySelector{};
  plate.tractions[0].boundary.segments = {{0.01, 0.04, 0.04, 0.04}};
  {
    SCOPED_TRACE("a pressure on a segment of the top");
    expect_scene_pieces_pose_the_whole_share<2>(plate, 3);
  }
  // held inside at a vertex off the grid points: a nonconvex mesh's mid-point of a box's side, a
  // quarter of a box inside (5.75 and 6.25 boxes along), and a distorted mesh's inner vertex at
  // the grid point (6, 6), moved
  for (const char* name : {"paper-example-4.1-nonconvex.toml", "paper-example-4.1-distorted.toml"}) {
    SCOPED_TRACE(name);
    Scene held = parse_scene(test::scenes_dir() / name);
    held.mesh.n = 12;
    const bool nonconvex = held.mesh.generator == "nonconvex";
    const Vec2 at = nonconvex ? Vec2(5.75 / 12, 6.25 / 12) : build_problem<2>(held)->mesh.vertex(6 * 13 + 6);
    EXPECT_GT((at - Vec2(0.5, 0.5)).norm(), 1e-3) << "off the grid point";
    SceneDirichlet inside;
    inside.boundary.points = {{at.x(), at.y(), 0.0}};
    inside.ux = SceneScalar{0.0};
    held.dirichlet.push_back(inside);
    expect_scene_pieces_pose_the_whole_share<2>(held, 3);
  }
  // a polar grid of one body: a disk (its centre held at a point), a half-disk held along its
  // start and end groups, pressed on its outer arc by a traction and on its contact along the arc
  for (const double start : {0.0, 180.0}) {
    SCOPED_TRACE(start == 0.0 ? "a disk" : "a half-disk");
    std::string text = R"(schema_version = 1
[mesh]
generator = "polar"
center = [0.5, 0.5]
radii = [0.0, 0.5]
angles = [ANGLES]
n = [12, 24]
[material]
E = 65.0
nu = 0.29
[[dirichlet]]
point = [0.5, 0.5]
ux = 0.0
uy = 0.0
[[dirichlet]]
point = [0.5, 0.0]
ux = 0.0
[[loads.traction]]
group = "outer"
value = [0.0, -1.0]
[contact]
group = "outer"
law = "zero"
)";
    text.replace(text.find("ANGLES"), 6, start == 0.0 ? "0.0, 360.0" : "180.0, 360.0");
    if (start != 0.0) text += "\n[[dirichlet]]\ngroup = [\"start\", \"end\"]\nuy = 0.0\n";
    const Scene polar = parse_scene_string(text, "polar.toml");
    EXPECT_FALSE(cuts_pieces(polar));
    expect_scene_pieces_pose_the_whole_share<2>(polar, 3);
    // by segments: the half-disk held along its diameter (its start and end rays); the disk's
    // traction on its first ray too, inside the disk, which the pieces' first column of boxes
    // meets the others along (a segment there picks no edge)
    const std::string by = start != 0.0 ? "group = [\"start\", \"end\"]" : "group = \"outer\"\nvalue";
    const std::string to = start != 0.0 ? "segments = [[0.0, 0.5, 1.0, 0.5]]"
                                        : "group = \"outer\"\nsegments = [[0.5, 0.5, 1.0, 0.5]]\nvalue";
    text.replace(text.find(by), by.size(), to);
    const Scene segments = parse_scene_string(text, "polar-segments.toml");
    ASSERT_TRUE(scene_piece(segments, 0, 3));
    expect_scene_pieces_pose_the_whole_share<2>(segments, 3);
  }
  // a solid on a roller at x = 0, held at two points of its far side against the rigid motions
  // the roller leaves free
  Scene solid = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  solid.clamped = BoundarySelector{};
  SceneDirichlet roller{BoundarySelector{{"x0"}}, {}, {}, {}};
  roller.ux = SceneScalar{0.0};
  SceneDirichlet corner;
  corner.boundary.points = {{1.0, 0.0, 0.5}};
  corner.uy = corner.uz = SceneScalar{0.0};
  SceneDirichlet far;
  far.boundary.points = {{1.0, 0.5, 0.5}};
  far.uz = SceneScalar{0.0};
  solid.dirichlet = {roller, corner, far};
  solid.mesh.nz = 12;  // thirds of the layers whose middle one misses some
  for (const char* generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    solid.mesh.generator = generator;
    // the roller along x = 0, which every slab meets, on its slab's cells alone
    for (const int size : {3, 8}) EXPECT_EQ(expect_scene_pieces_pose_the_whole_share<3>(solid, size), size);
  }
}

/// The pieces three processes keep of the scene's mesh made whole (cut_problem_piece): each
/// holds every vertex, fewer cells than the whole and among them every cell of its vertices
/// (in the mesh's Hilbert order) and of its contact; of a mesh whose every body is one connected
/// piece of cells (`one_piece_each`) its supports and loads hold the whole's facets among its
/// cells and each support every vertex it holds of the whole, and it holds each body in one
/// piece (piece_bodies); otherwise it holds every cell of their supports and loads, which hold
/// the whole's facets. Its groups hold their facets, and the
/// share it poses along that order is the whole mesh's to the bit. Returns how many pieces hold
/// fewer facets of the supports and loads than the whole.
template <int dim>
int expect_cut_pieces_pose_the_whole_share(const Scene& scene, bool cut_route, bool one_piece_each) {
  EXPECT_EQ(cuts_pieces(scene), cut_route);
  const auto whole = build_problem<dim>(scene);
  const std::vector<int> order = hilbert_vertex_order(whole->mesh);
  const int n = whole->mesh.num_vertices();
  const WholeParts<dim> parts(*whole);
  EXPECT_FALSE(parts.contact.empty());
  int fewer = 0;
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    PieceOfMesh where;
    const auto piece = cut_problem_piece<dim>(build_problem<dim>(scene), rank, 3, where);
    const auto [first, end] = vertex_share(n, rank, 3);
    EXPECT_EQ(where.vertices.first, first);
    EXPECT_EQ(where.vertices.end, end);
    EXPECT_EQ(where.vertices.order, order);
    EXPECT_EQ(where.whole_cells, num_cells_of(whole->mesh));
    const std::vector<int> bodies = body_vertex_starts(whole->bodies, n);
    if (one_piece_each) expect_whole_bodies(*piece, *whole);
    else EXPECT_TRUE(piece->problem.elasticity.piece_bodies.empty());
    if (one_piece_each)
      EXPECT_EQ(BasicRigidMotions<dim>(piece->mesh, make_dof_map(piece->mesh, {})).num_pieces(),
                static_cast<int>(bodies.size()) - 1);
    if (static_cast<int>(where.cells.size()) != num_cells_of(piece->mesh)) {
      ADD_FAILURE() << "a piece of " << num_cells_of(piece->mesh) << " cells named by " << where.cells.size();
      return fewer;
    }
    EXPECT_LT(num_cells_of(piece->mesh), num_cells_of(whole->mesh));
    // the piece's cells are the whole's `where.cells`, each holding the whole's vertex loops
    for (std::size_t c = 0; c < where.cells.size(); ++c)
      EXPECT_EQ(loops_of(piece->mesh, static_cast<int>(c)), loops_of(whole->mesh, where.cells[c])) << "cell " << c;
    const std::vector<char> mine = where.vertices.mask(n);
    const std::set<int> kept(where.cells.begin(), where.cells.end());
    for (int c = 0; c < num_cells_of(whole->mesh); ++c) {
      bool holds = false;
      for (const auto& loop : loops_of(whole->mesh, c))
        for (int v : loop) holds = holds || mine[static_cast<std::size_t>(v)] != 0;
      if (holds) EXPECT_TRUE(kept.count(c)) << "cell " << c << " holds one of the process's vertices";
    }
    fewer += parts.expect_held_by(*piece, whole->mesh, kept, one_piece_each, one_piece_each) ? 1 : 0;
    expect_same_share(pose_share(piece->problem, order, first, end), pose_share(whole->problem, order, first, end));
  }
  return fewer;
}
/// The same of a shipped scene, which the route across processes makes or reads in pieces (the
/// cut holds of any mesh).
template <int dim>
int expect_cut_pieces_pose_the_whole_share(const std::string& scene_file) {
  SCOPED_TRACE(scene_file);
  return expect_cut_pieces_pose_the_whole_share<dim>(parse_scene(test::scenes_dir() / scene_file), false, true);
}

TEST(MeshPiece, ThePiecesKeptOfAPlaneMeshMadeWholePoseTheWholeMeshsShares) {
  expect_cut_pieces_pose_the_whole_share<2>("polygon-bracket.toml");  // edge groups
  // its sides clamped and its top pressed, of which each piece holds the facets among its cells
  EXPECT_EQ(expect_cut_pieces_pose_the_whole_share<2>("paper-example-4.1-voronoi.toml"), 3);
  expect_cut_pieces_pose_the_whole_share<2>("rollers-pressure.toml");  // a contact part on a segment
}

// a segment picks on a piece what it picks on the whole mesh, though the piece's boundary holds
// edges inside the mesh that the segment runs along: on pieces cut from the whole mesh and on
// pieces made of the generated box (which hold every side, and know where they meet the others)
TEST(MeshPiece, APiecesSegmentsPickTheWholeMeshsEdges) {
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");  // squares on the unit square
  scene.mesh.n = 16;
  scene.contact->boundary = BoundarySelector{};
  scene.contact->boundary.segments = {{0.0, 0.0, 1.0, 0.0}};  // the bottom, and lines across the body
  for (int k = 1; k < 16; ++k) scene.contact->boundary.segments.push_back({0.0, k / 16.0, 1.0, k / 16.0});
  SceneDirichlet inside;  // held at a vertex inside
  inside.boundary.points = {{0.75, 0.25, 0.0}};
  inside.ux = SceneScalar{0.0};
  scene.dirichlet.push_back(inside);
  ASSERT_TRUE(scene_piece(scene, 0, 3));
  expect_cut_pieces_pose_the_whole_share<2>(scene, false, true);
  expect_scene_pieces_pose_the_whole_share<2>(scene, 3);
  // the pieces' boundary edges along the lines across, which the whole mesh's segments do not pick
  const auto across = [](const Mesh& mesh) {
    int out = 0;
    for (int f : mesh.boundary_edges()) {
      const double y = mesh.vertex(mesh.edge(f).v0).y();
      out += y > 0.0 && y < 1.0 && mesh.vertex(mesh.edge(f).v1).y() == y ? 1 : 0;
    }
    return out;
  };
  int cut = 0, made = 0;
  for (const int edges : test::on_threads(3, [&](const test::ThreadRows& rows) {
         return across(build_problem_piece<2>(scene, *scene_piece(scene, rows.rank(), 3), rows)->mesh);
       }))
    made += edges;
  for (int rank = 0; rank < 3; ++rank) {
    PieceOfMesh where;
    cut += across(cut_problem_piece<2>(build_problem<2>(scene), rank, 3, where)->mesh);
  }
  EXPECT_GT(cut, 0);
  EXPECT_GT(made, 0);
}

TEST(MeshPiece, ThePiecesKeptOfAGmshSolidPoseTheWholeMeshsShares) {
  expect_cut_pieces_pose_the_whole_share<3>("gmsh-bracket-3d.toml");  // a file's face groups
}

// each body's kept cells one, the pairs across the bodies' contact posed as on the whole mesh
TEST(MeshPiece, ThePiecesKeptOfSeveralBodiesPoseTheWholeMeshsShares) {
  {
    // (made in pieces: BodyPieces below; a piece cut from the whole is what any other bodies take)
    SCOPED_TRACE("two-blocks, the lower read from a .poly2d file of triangles with a region box");
    Scene blocks = parse_scene(test::scenes_dir() / "two-blocks.toml");
    ASSERT_EQ(blocks.bodies.size(), 2u);
    blocks.bodies[0].mesh.n = 12, blocks.bodies[0].mesh.ny = 6;
    const std::filesystem::path poly = test::scratch("lower-block-regions.poly2d");
    write_poly2d(poly, make_mesh("triangles", GridSize(14, 6), Rectangle{0.0, 1.0, 0.0, 0.5}));
    blocks.bodies[1].mesh.file = poly;
    blocks.bodies[1].material.regions.push_back(
        SceneRegionMaterial{1, 20.0, 0.3, std::array<double, 4>{0.0, 0.5, 0.0, 0.5}});
    EXPECT_GT(expect_cut_pieces_pose_the_whole_share<2>(blocks, false, true), 0);
    std::filesystem::remove(poly);
  }
  // two boxes, the upper pressed down by its top's displacement (the full-space route needs
  // supports that hold each body)
  Scene boxes = parse_scene(test::scenes_dir() / "two-boxes-3d.toml");
  ASSERT_EQ(boxes.bodies.size(), 2u);
  boxes.bodies[0].tractions.clear();
  boxes.bodies[0].dirichlet.push_back(SceneDirichlet{BoundarySelector{{"top"}}, {}, {}, SceneScalar{-0.01}});
  boxes.bodies[0].mesh.n = 4, boxes.bodies[0].mesh.ny = 4, boxes.bodies[0].mesh.nz = 3;
  boxes.bodies[1].mesh.n = 3, boxes.bodies[1].mesh.ny = 3, boxes.bodies[1].mesh.nz = 3;
  // the lower held at a far corner too: a point, whose cells a piece cut from the whole holds
  // (the route of these bodies makes them in pieces, BodyPieces below; a piece cut from the
  // whole mesh is what bodies of other meshes take)
  SceneDirichlet corner;
  corner.boundary.points = {{1.0, 1.0, 0.0}};
  corner.ux = corner.uy = corner.uz = SceneScalar{0.0};
  boxes.bodies[1].dirichlet.push_back(corner);
  EXPECT_GT(expect_cut_pieces_pose_the_whole_share<3>(boxes, false, true), 0);
}

/// The pieces three processes make of the bodies of `scene` (build_bodies_piece, no whole mesh
/// made) are pieces of the whole mesh (build_problem): every vertex where the whole has it (the
/// vertices matching adds included), the whole's cells `where.cells` in its order, among them
/// every cell of the process's vertices (its share of the whole mesh's hilbert_vertex_order),
/// every neighbour of a cell it owns, every cell of the contact (both its sides) and around
/// each vertex a support at a point holds; each body in one piece, every vertex of each lying on
/// it (piece_bodies), its supports' and loads' facets the whole's among its cells and each support
/// every vertex it holds of the whole; each body's vertices the whole's and its cells the
/// piece's of the whole's; and the share it poses is the whole mesh's to the bit. So are the
/// pieces made across `size` processes played by threads, of whose bodies made or read as lists
/// the first process makes or reads them alone and sends each its pieces: each the same cells as
/// the piece its process makes by itself. Returns how many pieces hold fewer facets of the
/// supports and loads than the whole (the same of either).
template <int dim>
int expect_body_pieces_are_the_whole_meshs(const Scene& scene, int size = 3) {
  int fewer = 0;
  EXPECT_TRUE(makes_body_pieces(scene));
  EXPECT_FALSE(cuts_pieces(scene));
  EXPECT_FALSE(scene_piece(scene, 0, 3));
  const auto whole = build_problem<dim>(scene);
  const int n = whole->mesh.num_vertices();
  const std::vector<int> order = hilbert_vertex_order(whole->mesh);
  const WholeParts<dim> parts(*whole);
  std::set<std::vector<int>> contact, against;  // the facets of the contact, both sides of it
  for (const auto& p : whole->problem.parts) {
    contact.merge(sorted_facets(whole->mesh, p.facets));
    against.merge(sorted_facets(whole->mesh, p.against));
  }
  const std::vector<int> bodies = body_vertex_starts(whole->bodies, n);
  std::map<std::vector<int>, std::vector<int>> cells_of_facet;
  for (int c = 0; c < num_cells_of(whole->mesh); ++c)
    for (const auto& f : facets_of_cell(whole->mesh, c)) cells_of_facet[f].push_back(c);
  using Made = std::pair<std::shared_ptr<BasicBuiltProblem<dim>>, PieceOfMesh>;
  const std::vector<Made> sent = test::on_threads(size, [&](const test::ThreadRows& rows) {
    Made made;
    made.first = build_bodies_piece<dim>(scene, rows.rank(), rows.size(), made.second, &rows);
    return made;
  });
  int owners = 0, fewer_sent = 0;
  std::vector<std::vector<int>> own_cells(static_cast<std::size_t>(size));
  for (int turn = 0; turn < 2 * size; ++turn) {
    const int rank = turn % size;
    const bool by_first = turn >= size;  // the pieces across processes, after each process's own
    SCOPED_TRACE("rank " + std::to_string(rank) + (by_first ? ", across processes" : ""));
    PieceOfMesh where;
    std::shared_ptr<BasicBuiltProblem<dim>> piece;
    if (by_first) {
      piece = sent[static_cast<std::size_t>(rank)].first;
      where = sent[static_cast<std::size_t>(rank)].second;
      EXPECT_EQ(where.cells, own_cells[static_cast<std::size_t>(rank)]);
    } else {
      piece = build_bodies_piece<dim>(scene, rank, size, where);
      own_cells[static_cast<std::size_t>(rank)] = where.cells;
    }
    const auto [first, end] = vertex_share(n, rank, size);
    EXPECT_EQ(where.vertices.first, first);
    EXPECT_EQ(where.vertices.end, end);
    EXPECT_EQ(where.vertices.order, order);
    EXPECT_EQ(where.whole_cells, num_cells_of(whole->mesh));
    std::set<std::vector<int>> both = contact;
    both.insert(against.begin(), against.end());
    expect_piece_of(piece->mesh, where.cells, whole->mesh, 0, 0, both, true);  // the vertices' cells below
    expect_whole_bodies(*piece, *whole);
    EXPECT_EQ(BasicRigidMotions<dim>(piece->mesh, make_dof_map(piece->mesh, {})).num_pieces(),
              static_cast<int>(whole->bodies.size()));
    for (int c = 0; c < num_cells_of(piece->mesh); ++c)  // each cell in the whole's region, the bodies' offsets its
      EXPECT_EQ(piece->mesh.region(c), whole->mesh.region(where.cells[static_cast<std::size_t>(c)])) << "cell " << c;
    const std::set<int> held(where.cells.begin(), where.cells.end());
    const std::vector<char> mine = where.vertices.mask(n);
    bool owns = false;
    for (int c = 0; c < num_cells_of(whole->mesh); ++c) {
      const auto loops = loops_of(whole->mesh, c);
      int smallest = n;
      bool holds = false;
      for (const auto& loop : loops)
        for (int v : loop) {
          smallest = std::min(smallest, v);
          holds = holds || mine[static_cast<std::size_t>(v)] != 0;
        }
      if (holds) EXPECT_TRUE(held.count(c)) << "cell " << c << " holds one of the process's vertices";
      if (!mine[static_cast<std::size_t>(smallest)]) continue;
      owns = true;
      for (const auto& f : facets_of_cell(whole->mesh, c))
        for (int other : cells_of_facet[f]) EXPECT_TRUE(held.count(other)) << "cell " << other << " next to owned cell " << c;
    }
    if (!by_first) owners += owns ? 1 : 0;
    for (const auto& d : whole->problem.elasticity.dirichlet)  // the cells around each vertex supported alone
      for (const int v : d.vertices)
        for (int c = 0; c < num_cells_of(whole->mesh); ++c)
          if (holds_vertex(whole->mesh, c, v, v + 1)) EXPECT_TRUE(held.count(c)) << "cell " << c << " around the supported vertex " << v;
    if (piece->bodies.size() != whole->bodies.size()) {
      ADD_FAILURE() << piece->bodies.size() << " bodies on the piece, " << whole->bodies.size() << " on the whole";
      return fewer;
    }
    for (std::size_t b = 0; b < whole->bodies.size(); ++b) {
      const BodyRange& mine = piece->bodies[b];
      const BodyRange& all = whole->bodies[b];
      EXPECT_EQ(mine.name, all.name);
      EXPECT_EQ(mine.first_vertex, all.first_vertex);
      EXPECT_EQ(mine.vertices, all.vertices);
      const auto from = std::lower_bound(where.cells.begin(), where.cells.end(), all.first_cell);
      const auto to = std::lower_bound(where.cells.begin(), where.cells.end(), all.first_cell + all.cells);
      EXPECT_EQ(mine.first_cell, from - where.cells.begin());
      EXPECT_EQ(mine.cells, to - from);
      EXPECT_GT(mine.cells, 0);
    }
    (by_first ? fewer_sent : fewer) += parts.expect_held_by(*piece, whole->mesh, held, true, true) ? 1 : 0;
    std::set<std::vector<int>> facets;
    for (const auto& p : piece->problem.parts) facets.merge(sorted_facets(piece->mesh, p.against));
    EXPECT_EQ(facets, against);
    expect_same_share(pose_share(piece->problem, order, first, end), pose_share(whole->problem, order, first, end));
  }
  EXPECT_EQ(owners, size) << "a process owns no cell";
  EXPECT_EQ(fewer_sent, fewer);
  return fewer;
}

// two boxes whose meshes do not match along their contact: each process makes its piece of each
// body and matches the pieces, which add the vertices matching the whole meshes adds
TEST(BodyPieces, ThePiecesEachProcessMakesOfSeveralBodiesAreTheWholeMeshs) {
  Scene boxes = parse_scene(test::scenes_dir() / "two-boxes-3d.toml");  // tetrahedra on cubes
  ASSERT_EQ(boxes.bodies.size(), 2u);
  boxes.bodies[0].tractions.clear();  // the upper pressed down by its top's displacement
  boxes.bodies[0].dirichlet.push_back(SceneDirichlet{BoundarySelector{{"top"}}, {}, {}, SceneScalar{-0.01}});
  boxes.bodies[0].mesh.n = 8, boxes.bodies[0].mesh.ny = 8, boxes.bodies[0].mesh.nz = 6;
  boxes.bodies[1].mesh.n = 7, boxes.bodies[1].mesh.ny = 7, boxes.bodies[1].mesh.nz = 6;
  {
    SCOPED_TRACE("two-boxes-3d");
    // the top of the upper and the bottom of the lower held: each piece holds their facets among its cells
    EXPECT_EQ(expect_body_pieces_are_the_whole_meshs<3>(boxes), 3);
  }
  {
    SCOPED_TRACE("two-boxes-3d, the lower held at a point of its far edge too");
    Scene corner_held = boxes;
    SceneDirichlet corner;
    corner.boundary.points = {{1.0, 1.0, 0.25}};
    corner.ux = corner.uy = corner.uz = SceneScalar{0.0};
    corner_held.bodies[1].dirichlet.push_back(corner);
    expect_body_pieces_are_the_whole_meshs<3>(corner_held);
  }
  {
    SCOPED_TRACE("two-boxes-3d on 128 processes: shares inside the bodies, away from their sides");
    boxes = parse_scene(test::scenes_dir() / "two-boxes-3d.toml");  // the upper held by its contact alone
    boxes.bodies[0].mesh.generator = "cubes";
    boxes.bodies[0].mesh.n = 12, boxes.bodies[0].mesh.ny = 12, boxes.bodies[0].mesh.nz = 36;
    boxes.bodies[1].mesh.n = 12, boxes.bodies[1].mesh.ny = 12, boxes.bodies[1].mesh.nz = 36;
    expect_body_pieces_are_the_whole_meshs<3>(boxes, 128);
  }
  Scene blocks = parse_scene(test::scenes_dir() / "two-blocks.toml");  // triangles on squares
  ASSERT_EQ(blocks.bodies.size(), 2u);
  blocks.bodies[0].mesh.generator = "triangles";
  blocks.bodies[0].mesh.n = 5, blocks.bodies[0].mesh.ny = 4;
  blocks.bodies[1].mesh.ny = 4;
  {
    SCOPED_TRACE("two-blocks, triangles");
    EXPECT_GT(expect_body_pieces_are_the_whole_meshs<2>(blocks), 0);
  }
  {
    SCOPED_TRACE("two-blocks, nonconvex cells on distorted squares");
    blocks.bodies[0].mesh.generator = "nonconvex";
    blocks.bodies[1].mesh.generator = "distorted";
    expect_body_pieces_are_the_whole_meshs<2>(blocks);
  }
  {
    SCOPED_TRACE("two-blocks, the lower loaded along the rows of its squares and a segment of its right side");
    Scene across = blocks;
    across.bodies[0].mesh.generator = "triangles";
    across.bodies[1].mesh.generator = "squares";
    across.bodies[1].mesh.n = 14, across.bodies[1].mesh.ny = 6;
    SceneTraction row;  // the rows pick no edge of the whole mesh, and the pieces' edges along them are cut
    row.boundary.segments = {{1.0, 0.0, 1.0, 0.25}};
    for (int k = 1; k < 6; ++k) row.boundary.segments.push_back({0.0, k / 12.0, 1.0, k / 12.0});
    row.pressure = SceneScalar{1.0};
    across.bodies[1].tractions.push_back(row);
    expect_body_pieces_are_the_whole_meshs<2>(across);
  }
  // polar grids in contact along their edge groups: two rings around a full turn, each held at
  // three points of its inner circle
  Scene rings = parse_scene(test::scenes_dir() / "shrink-fit.toml");
  ASSERT_EQ(rings.bodies.size(), 2u);
  rings.bodies[0].mesh.ny = rings.bodies[1].mesh.ny = 96;
  {
    SCOPED_TRACE("shrink-fit");
    expect_body_pieces_are_the_whole_meshs<2>(rings);
  }
  {
    SCOPED_TRACE("shrink-fit, a quarter of each ring held along its straight sides");
    Scene quarter = rings;
    for (SceneBody& body : quarter.bodies) {
      body.mesh.angles = {0.0, 90.0};
      body.mesh.ny = 24;
      body.dirichlet.clear();
      SceneDirichlet start, end;
      start.boundary.groups = {"start"};
      start.uy = SceneScalar{0.0};
      end.boundary.groups = {"end"};
      end.ux = SceneScalar{0.0};
      body.dirichlet = {start, end};
    }
    expect_body_pieces_are_the_whole_meshs<2>(quarter);
  }
  {
    SCOPED_TRACE("shrink-fit, a disk in the ring held at its centre");
    Scene disk = rings;
    disk.bodies[0].mesh.radii = {0.0, 1.001};
    disk.bodies[0].dirichlet.clear();
    SceneDirichlet centre, side;
    centre.boundary.points = {{0.0, 0.0, 0.0}};
    centre.ux = centre.uy = SceneScalar{0.0};
    side.boundary.points = {{1.001, 0.0, 0.0}};
    side.uy = SceneScalar{0.0};
    disk.bodies[0].dirichlet = {centre, side};
    expect_body_pieces_are_the_whole_meshs<2>(disk);
  }
  // two half-disks (a centre each) held along a side of their bounding boxes, their straight
  // sides: every piece holds every box along the grid's sides
  Scene cylinders = parse_scene(test::scenes_dir() / "two-cylinders.toml");
  ASSERT_EQ(cylinders.bodies.size(), 2u);
  cylinders.bodies[0].mesh.n = 16, cylinders.bodies[0].mesh.ny = 32;
  cylinders.bodies[1].mesh.n = 16, cylinders.bodies[1].mesh.ny = 36;
  {
    SCOPED_TRACE("two-cylinders");
    expect_body_pieces_are_the_whole_meshs<2>(cylinders);
  }
}

// bodies whose generators make their cells' lists (Voronoi cells, a polygon's mesh): each
// process makes its piece of each around its vertices among the body's, as it makes a box's
TEST(BodyPieces, ThePiecesEachProcessMakesOfBodiesMadeAsListsAreTheWholeMeshs) {
  Scene blocks = parse_scene(test::scenes_dir() / "two-blocks.toml");  // Voronoi cells on squares
  ASSERT_EQ(blocks.bodies.size(), 2u);
  blocks.bodies[0].mesh.n = 12, blocks.bodies[0].mesh.ny = 6;
  blocks.bodies[1].mesh.n = 14, blocks.bodies[1].mesh.ny = 6;
  {
    SCOPED_TRACE("two-blocks");
    expect_body_pieces_are_the_whole_meshs<2>(blocks);
  }
  {
    SCOPED_TRACE("two-blocks, the Voronoi block held at a vertex inside and loaded along a segment of its top");
    Scene held = blocks;
    const Mesh whole = build_problem<2>(blocks)->mesh;  // the Voronoi block's vertices first
    const Vec2 v = whole.vertex(nearest_point<2>(whole.vertices(), Vec2(0.4, 0.8)).first);
    ASSERT_GT(v.y(), 0.6);
    ASSERT_LT(v.y(), 0.95);
    SceneDirichlet inside;
    inside.boundary.points = {{v.x(), v.y(), 0.0}};
    inside.ux = SceneScalar{0.0};
    held.bodies[0].dirichlet.push_back(inside);
    held.bodies[0].tractions.front().boundary = BoundarySelector{};
    held.bodies[0].tractions.front().boundary.segments = {{0.2, 1.0, 0.7, 1.0}};
    expect_body_pieces_are_the_whole_meshs<2>(held);
  }
  for (const char* generator : {"triangles", "voronoi"}) {
    SCOPED_TRACE(std::string("two-blocks, the upper block ") + generator + " in its polygon, an L");
    Scene polygon = blocks;
    SceneMesh& m = polygon.bodies[0].mesh;
    m.generator = generator;
    m.n = 10;
    m.polygon = {{0.0, 0.5}, {1.0, 0.5}, {1.0, 0.75}, {0.5, 0.75}, {0.5, 1.0}, {0.0, 1.0}};
    polygon.bodies[0].tractions.front().boundary = BoundarySelector{};
    polygon.bodies[0].tractions.front().boundary.groups = {"edge3"};  // the L's inner top, (0.5, 0.75)-(0.5, 1)
    expect_body_pieces_are_the_whole_meshs<2>(polygon);
  }
  {
    SCOPED_TRACE("two-blocks, a region box inside each block");
    Scene regions = blocks;
    regions.bodies[0].material.regions.push_back(SceneRegionMaterial{3, 30.0, 0.3, std::array<double, 4>{0.4, 0.6, 0.65, 0.85}});
    regions.bodies[1].material.regions.push_back(SceneRegionMaterial{2, 1.0, 0.2, std::array<double, 4>{0.4, 0.6, 0.15, 0.35}});
    expect_body_pieces_are_the_whole_meshs<2>(regions);
    // a piece without a cell of the upper block's region 3 still shifts the lower block's regions
    // past it, as the whole mesh does
    int without = 0;
    for (int rank = 0; rank < 3; ++rank) {
      PieceOfMesh where;
      const auto piece = build_bodies_piece<2>(regions, rank, 3, where);
      const BodyRange& upper = piece->bodies.front();
      bool holds = false;
      for (int c = upper.first_cell; c < upper.first_cell + upper.cells; ++c) holds = holds || piece->mesh.region(c) == 3;
      without += holds ? 0 : 1;
      EXPECT_EQ(piece->bodies.back().first_region, 4);
    }
    EXPECT_GT(without, 0);
  }
  Scene boxes = parse_scene(test::scenes_dir() / "two-boxes-3d.toml");
  ASSERT_EQ(boxes.bodies.size(), 2u);
  boxes.bodies[0].tractions.clear();  // the upper pressed down by its top's displacement
  boxes.bodies[0].dirichlet.push_back(SceneDirichlet{BoundarySelector{{"top"}}, {}, {}, SceneScalar{-0.01}});
  boxes.bodies[0].mesh.generator = "voronoi";
  boxes.bodies[0].mesh.n = 10, boxes.bodies[0].mesh.ny = 10, boxes.bodies[0].mesh.nz = 5;
  boxes.bodies[1].mesh.n = 4, boxes.bodies[1].mesh.ny = 4, boxes.bodies[1].mesh.nz = 3;
  {
    SCOPED_TRACE("two-boxes-3d, Voronoi cells on cubes");
    expect_body_pieces_are_the_whole_meshs<3>(boxes);
  }
}

/// A scene of a generated upper body (`upper`, its [body.mesh] and supports) resting on a lower
/// body read from `file` (`lower`, its supports), their contact `upper.bottom` against `against`.
Scene upper_on_file(const std::string& upper, const std::filesystem::path& file, const std::string& lower,
                    const std::string& against) {
  const std::string text = "schema_version = 1\n[[body]]\nname = \"upper\"\n" + upper +
                           "[body.material]\nE = 10.0\nnu = 0.3\n\n[[body]]\nname = \"lower\"\n[body.mesh]\nfile = \"" +
                           file.string() + "\"\n[body.material]\nE = 4.0\nnu = 0.1\n" + lower +
                           "\n[[contact]]\nname = \"interface\"\nside = \"upper.bottom\"\nagainst = \"" + against +
                           "\"\nlaw = \"zero\"\n";
  return parse_scene_string(text, "upper-on-file.toml");
}

// a body read from a file among several: each process reads the file whole once and makes its
// piece of it around its vertices, with the cells of the file's facet groups and a cell of each
// of its regions, as a single body's piece read from a file
TEST(BodyPieces, ThePiecesEachProcessReadsOfBodiesFromFilesAreTheWholeMeshs) {
  const std::string voronoi = "[body.mesh]\ngenerator = \"voronoi\"\nn = [9, 5]\ndomain = [0.0, 1.0, 1.0, 1.5]\n"
                              "[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n"
                              "[[body.loads.traction]]\nside = \"top\"\npressure = 2.0\n";
  // the unit square of triangles, its groups clamped (left, right), load (top) and contact (bottom)
  const std::filesystem::path square = test::data_dir() / "gmsh" / "unit_square_triangles.msh";
  const std::string by_groups = "[[body.dirichlet]]\ngroup = \"clamped\"\nux = 0.0\n"
                                "[[body.dirichlet]]\ngroup = \"contact\"\nuy = 0.0\n";
  {
    SCOPED_TRACE("Voronoi cells on a Gmsh file's triangles, supported and met along its groups");
    expect_body_pieces_are_the_whole_meshs<2>(upper_on_file(voronoi, square, by_groups, "lower.load"));
  }
  {
    SCOPED_TRACE("the same, the file's body held at a point inside and met along its top side");
    const std::string held = by_groups + "[[body.dirichlet]]\npoint = [0.375, 0.375]\nux = 0.0\n";
    expect_body_pieces_are_the_whole_meshs<2>(upper_on_file(voronoi, square, held, "lower.top"));
  }
  {
    // a quad in region 7 and two triangles in region 3 on [0, 2] x [0, 1]; a box puts the quad
    // in region 1, so that no cell is left in the file's largest region: each body's regions
    // still shift the next past it, in the whole mesh as in each piece
    SCOPED_TRACE("Voronoi cells on a Gmsh file in two regions, one covered by a region box");
    const std::string wide = "[body.mesh]\ngenerator = \"voronoi\"\nn = [12, 3]\ndomain = [0.0, 2.0, 1.0, 1.5]\n"
                             "[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n"
                             "[[body.loads.traction]]\nside = \"top\"\npressure = 2.0\n";
    Scene scene = upper_on_file(wide, test::data_dir() / "gmsh" / "two_regions.msh",
                                "[[body.dirichlet]]\ngroup = \"bottom\"\nuy = 0.0\n[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n",
                                "lower.top");
    scene.bodies[1].material.regions.push_back(SceneRegionMaterial{1, 20.0, 0.3, std::array<double, 4>{0.0, 1.0, 0.0, 1.0}});
    std::swap(scene.bodies[0], scene.bodies[1]);  // the file's body first
    ASSERT_TRUE(makes_body_pieces(scene));
    const auto whole = build_problem<2>(scene);
    const std::set<int> regions(whole->mesh.regions().begin(), whole->mesh.regions().end());
    EXPECT_EQ(regions, (std::set<int>{1, 3, 8}));  // the lower's 1 and 3, the upper's past 1 + max(7, 1)
    EXPECT_EQ(whole->bodies.back().first_region, 8);
    expect_body_pieces_are_the_whole_meshs<2>(scene);
  }
  {
    SCOPED_TRACE("squares on a .poly2d file's triangles");
    const std::filesystem::path poly = test::scratch("lower-block.poly2d");
    write_poly2d(poly, make_mesh("triangles", GridSize(9, 6), Rectangle{0.0, 1.0, 0.0, 1.0}, 7));
    const std::string squares = "[body.mesh]\ngenerator = \"squares\"\nn = [5, 3]\ndomain = [0.0, 1.0, 1.0, 1.5]\n"
                                "[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n"
                                "[[body.loads.traction]]\nside = \"top\"\npressure = 2.0\n";
    expect_body_pieces_are_the_whole_meshs<2>(
        upper_on_file(squares, poly, "[[body.dirichlet]]\nside = \"bottom\"\nuy = 0.0\n[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n",
                      "lower.top"));
    std::filesystem::remove(poly);
  }
  {
    SCOPED_TRACE("cubes on a Gmsh file's tetrahedra in two regions");
    // two boxes [0, 1] and [1, 2] x [0, 2] x [0, 0.5] of tetrahedra, regions 5 and 7
    const std::filesystem::path boxes = test::data_dir() / "gmsh3d" / "two_boxes_tetrahedra.msh";
    const std::string rollers = "[[body.dirichlet]]\nside = \"x0\"\nux = 0.0\n[[body.dirichlet]]\nside = \"y0\"\nuy = 0.0\n";
    const std::string cubes = "[body.mesh]\ngenerator = \"cubes\"\nn = [6, 6, 2]\ndomain = [0.0, 2.0, 0.0, 2.0, 0.5, 1.0]\n" + rollers +
                              "[[body.dirichlet]]\nside = \"top\"\nuz = -0.01\n";
    const Scene scene = upper_on_file(cubes, boxes, rollers + "[[body.dirichlet]]\nside = \"bottom\"\nuz = 0.0\n", "lower.top");
    const auto whole = build_problem<3>(scene);
    const std::set<int> regions(whole->mesh.regions().begin(), whole->mesh.regions().end());
    EXPECT_EQ(regions, (std::set<int>{0, 6, 8}));  // the upper's, then the file's 5 and 7 past it
    expect_body_pieces_are_the_whole_meshs<3>(scene);
  }
  {
    // across processes the first reads the file alone: a defect of one cell inside it, which a
    // process's piece meets, is named by the first as the whole reader names it, and every other
    // process ends saying so
    SCOPED_TRACE("Voronoi cells on a Gmsh file of squares, one of which repeats a vertex");
    const std::filesystem::path defect = test::scratch("lower-defect.msh");
    std::ofstream(defect) << test::squares_msh_repeating_a_vertex(12);
    const Scene scene = upper_on_file(
        voronoi, defect, "[[body.dirichlet]]\ngroup = \"bottom\"\nuy = 0.0\n[[body.dirichlet]]\nside = \"left\"\nux = 0.0\n",
        "lower.top");
    const std::string whole = test::input_error_of([&] { (void)build_problem<2>(scene); });
    EXPECT_NE(whole.find("lower-defect.msh"), std::string::npos) << whole;
    const std::vector<std::string> met = test::on_threads(3, [&](const test::ThreadRows& rows) {
      PieceOfMesh where;
      return test::input_error_of([&] { (void)build_bodies_piece<2>(scene, rows.rank(), rows.size(), where, &rows); });
    });
    EXPECT_EQ(met[0], whole);
    for (std::size_t rank = 1; rank < met.size(); ++rank) EXPECT_EQ(met[rank], "process 0 stopped: " + whole) << rank;
    std::filesystem::remove(defect);
  }
}

// a body's file whose whole mesh's estimate does not fit is refused before any piece but the one
// along its sides is made, as the whole mesh is refused: naming the file, with the same estimate
TEST(BodyPieces, ABodysFileThatDoesNotFitIsRefusedAsItsWholeMeshIs) {
  const std::filesystem::path poly = test::scratch("lower-block-large.poly2d");
  const Mesh lower = make_mesh("triangles", GridSize(200, 100), Rectangle{0.0, 1.0, 0.0, 0.5});
  write_poly2d(poly, lower);
  Scene blocks = parse_scene(test::scenes_dir() / "two-blocks.toml");  // 5 x 3 Voronoi cells on it
  blocks.bodies[1].mesh.file = poly;
  const double generated = estimate_memory("voronoi", 5, 3).solve_bytes, file = estimate_memory(lower).solve_bytes;
  ASSERT_LT(2.0 * generated, file);
  const std::string limit = std::to_string(static_cast<long long>(0.5 * (generated + file)));
  ::setenv("HEMIVEM_MEMORY_LIMIT", limit.c_str(), 1);
  const std::string whole = test::input_error_of([&] { (void)build_problem<2>(blocks); });
  EXPECT_NE(whole.find("needs an estimated"), std::string::npos) << whole;
  EXPECT_NE(whole.find(poly.string() + ": 20301 vertices"), std::string::npos) << whole;
  for (int rank = 0; rank < 2; ++rank) {
    PieceOfMesh where;
    EXPECT_EQ(test::input_error_of([&] { (void)build_bodies_piece<2>(blocks, rank, 2, where); }), whole) << "rank " << rank;
  }
  ::unsetenv("HEMIVEM_MEMORY_LIMIT");
  std::filesystem::remove(poly);
}

TEST(MeshPiece, APieceIsRefusedCellsOutOfOrderAndFlagsOfAnotherMesh) {
  const Mesh3D whole = make_cubes(GridSize3(3, 2, 4));
  const std::vector<int> backwards{3, 1};
  EXPECT_NE(test::input_error_of([&] { (void)cut_mesh_piece(whole, backwards); }).find("not increasing"), std::string::npos);
  const std::vector<char> flags(5, 1);
  EXPECT_NE(test::input_error_of([&] { (void)piece_cells_around(whole, flags, {}); }).find("given flags for 5"),
            std::string::npos);
  // every vertex: the whole mesh
  const std::vector<int> all = piece_cells_around(whole, std::vector<char>(static_cast<std::size_t>(whole.num_vertices()), 1), {});
  EXPECT_EQ(cut_mesh_piece(whole, all).num_faces(), whole.num_faces());
}

}  // namespace
