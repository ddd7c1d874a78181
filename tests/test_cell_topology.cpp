// The cells of a mesh not made (core/mesh/src/cell_topology.hpp): the facets their loops share,
// found among the cells around each loop's smallest vertex, against the facets the meshes
// themselves find (Mesh's edges, Mesh3D's faces) and against hand counts.
#include <hemivem/mesh/generators.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators3d.hpp>

#include <gtest/gtest.h>

#include "cell_topology.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace {

using namespace hemivem;
using detail::CellTopology;

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

// every facet of the topology, with its cells
int count_facets(const CellTopology& cells, int* boundary) {
  int count = 0;
  *boundary = 0;
  for (int f = 0; f < cells.num_facets(); ++f)
    if (cells.is_facet(f)) {
      ++count;
      if (cells.facet_cells(f)[1] < 0) ++*boundary;
    }
  return count;
}

// The facets of a solid mesh's cells are its faces: each face found by its vertices in any
// order, its two cells the face's (the lower cell first), each cell's facets its faces.
void expect_solid_topology(const Mesh3D& mesh) {
  std::vector<CellFaces> lists;
  for (int c = 0; c < mesh.num_cells(); ++c) lists.push_back(mesh.cell(c));
  const CellTopology cells = detail::solid_topology(mesh.num_vertices(), lists);
  int boundary = 0;
  EXPECT_EQ(count_facets(cells, &boundary), mesh.num_faces());
  EXPECT_EQ(boundary, static_cast<int>(mesh.boundary_faces().size()));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    std::vector<int> key = mesh.face(f).vertices;
    std::reverse(key.begin(), key.end());
    const int g = cells.find_facet(key);
    ASSERT_GE(g, 0) << "face " << f;
    EXPECT_TRUE(cells.is_facet(g));
    const MeshFace& face = mesh.face(f);
    const std::array<int, 2> expected =
        face.outer < 0 ? std::array<int, 2>{face.inner, -1}
                       : std::array<int, 2>{std::min(face.inner, face.outer), std::max(face.inner, face.outer)};
    EXPECT_EQ(cells.facet_cells(g), expected) << "face " << f;
    const auto loop = cells.facet_loop(g);
    EXPECT_EQ(sorted({loop.begin(), loop.end()}), sorted(face.vertices));
  }
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto vs = cells.cell_vertices(c);
    EXPECT_EQ(std::vector<int>(vs.begin(), vs.end()), sorted(mesh.cell_vertices(c)));
    for (int f : cells.cell_facets(c)) {
      const auto two = cells.facet_cells(f);
      EXPECT_TRUE(two[0] == c || two[1] == c);
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int c : cells.vertex_cells().of(v)) {
      const std::vector<int>& vs = mesh.cell_vertices(c);
      EXPECT_NE(std::find(vs.begin(), vs.end(), v), vs.end());
    }
}

TEST(CellTopology, TheFacetsOfASolidMeshsCellsAreItsFaces) {
  expect_solid_topology(make_cubes(GridSize3(3, 2, 2)));
  expect_solid_topology(make_tetrahedra(GridSize3(2, 2, 3)));
  expect_solid_topology(make_voronoi3d(GridSize3(3)));
}

TEST(CellTopology, TheFacetsOfAPlaneMeshsElementsAreItsEdges) {
  for (const Mesh& mesh : {make_squares(GridSize{4, 3}), make_triangles(3), make_voronoi(5)}) {
    const CellTopology cells = detail::plane_topology(mesh.num_vertices(), mesh.elements());
    int boundary = 0;
    EXPECT_EQ(count_facets(cells, &boundary), mesh.num_edges());
    int mesh_boundary = 0;
    for (int e = 0; e < mesh.num_edges(); ++e) {
      const MeshEdge& edge = mesh.edge(e);
      mesh_boundary += edge.on_boundary() ? 1 : 0;
      const int g = cells.find_facet({edge.v1, edge.v0});
      ASSERT_GE(g, 0) << "edge " << e;
      const std::array<int, 2> expected =
          edge.right < 0 ? std::array<int, 2>{edge.left, -1}
                         : std::array<int, 2>{std::min(edge.left, edge.right), std::max(edge.left, edge.right)};
      EXPECT_EQ(cells.facet_cells(g), expected) << "edge " << e;
    }
    EXPECT_EQ(boundary, mesh_boundary);
  }
}

// By hand: two unit squares side by side, and three triangles around one edge (a defect a mesh
// refuses): the loops of the same vertices are one facet, its cells the first two holding it.
TEST(CellTopology, LoopsOfTheSameVerticesAreOneFacetOfTheFirstTwoCells) {
  const CellTopology squares = detail::plane_topology(6, {{0, 1, 4, 3}, {1, 2, 5, 4}});
  int boundary = 0;
  EXPECT_EQ(count_facets(squares, &boundary), 7);
  EXPECT_EQ(boundary, 6);
  const int shared = squares.find_facet({4, 1});
  ASSERT_GE(shared, 0);
  EXPECT_EQ(squares.facet_cells(shared), (std::array<int, 2>{0, 1}));
  EXPECT_EQ(squares.cell_facets(0)[1], shared);
  EXPECT_EQ(squares.cell_facets(1)[3], shared);
  EXPECT_EQ(squares.find_facet({0, 2}), -1);
  EXPECT_EQ(squares.find_facet({0, 7}), -1);
  EXPECT_EQ(squares.find_facet({}), -1);
  const auto around = squares.vertex_cells().of(4);
  EXPECT_EQ(std::vector<int>(around.begin(), around.end()), (std::vector<int>{0, 1}));

  const CellTopology fan = detail::plane_topology(5, {{0, 1, 2}, {1, 0, 3}, {0, 4, 1}});
  const int edge = fan.find_facet({0, 1});
  ASSERT_GE(edge, 0);
  EXPECT_EQ(fan.facet_cells(edge), (std::array<int, 2>{0, 1}));
  for (int c = 0; c < 3; ++c) {
    const auto facets = fan.cell_facets(c);
    EXPECT_EQ(std::count(facets.begin(), facets.end(), edge), 1) << "cell " << c;
  }
  EXPECT_EQ(count_facets(fan, &boundary), 7);
  EXPECT_EQ(boundary, 6);
}

// Cells of two kinds sharing their shapes (two hexahedra side by side and a prism lying on the
// first, a quadrilateral face on its top; their corners in Gmsh's order, as a file's elements
// give them) have the facets the same cells
// have, each given its faces' loops and a shape of its own: the same loops, facets, cells and
// vertices, loop by loop. A cell whose corners its shape does not run through is refused.
TEST(CellTopology, CellsOfAKindShareAShapeAndHaveTheFacetsTheirLoopsGive) {
  const std::vector<std::vector<int>> hexahedron{{0, 3, 2, 1}, {0, 1, 5, 4}, {0, 4, 7, 3},
                                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {4, 5, 6, 7}};
  const std::vector<std::vector<int>> prism{{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {0, 3, 5, 2}, {1, 2, 5, 4}};
  const std::vector<std::vector<int>> corners{
      {0, 1, 2, 3, 4, 5, 6, 7}, {1, 11, 12, 2, 5, 13, 14, 6}, {4, 5, 8, 7, 6, 9}};
  const std::vector<int> kind{0, 0, 1};
  detail::CellShapes shapes;
  ASSERT_EQ(shapes.add(hexahedron), 0);
  ASSERT_EQ(shapes.add(prism), 1);
  EXPECT_EQ(shapes.corners(0), 8);
  EXPECT_EQ(shapes.corners(1), 6);
  std::vector<int> start{0}, flat;
  std::vector<CellFaces> lists;
  for (std::size_t c = 0; c < corners.size(); ++c) {
    flat.insert(flat.end(), corners[c].begin(), corners[c].end());
    start.push_back(static_cast<int>(flat.size()));
    CellFaces faces;
    for (const auto& loop : kind[c] == 0 ? hexahedron : prism) {
      faces.emplace_back();
      for (int k : loop) faces.back().push_back(corners[c][static_cast<std::size_t>(k)]);
    }
    lists.push_back(faces);
  }
  const CellTopology shared(3, 15, shapes, kind, start, flat);
  const CellTopology own = detail::solid_topology(15, lists);
  ASSERT_EQ(shared.num_cells(), 3);
  ASSERT_EQ(shared.num_facets(), own.num_facets());
  EXPECT_EQ(shared.num_facets(), 17);  // 6 + 6 + 5 loops
  int boundary = 0;
  EXPECT_EQ(count_facets(shared, &boundary), 15);  // two faces shared
  EXPECT_EQ(boundary, 13);
  for (int c = 0; c < 3; ++c) {
    const auto a = shared.cell_facets(c), b = own.cell_facets(c);
    EXPECT_EQ(std::vector<int>(a.begin(), a.end()), std::vector<int>(b.begin(), b.end())) << "cell " << c;
    EXPECT_EQ(shared.cell_vertices(c), own.cell_vertices(c)) << "cell " << c;
    EXPECT_EQ(shared.cell_vertices(c), sorted(corners[static_cast<std::size_t>(c)])) << "cell " << c;
  }
  for (int f = 0; f < own.num_facets(); ++f) {
    EXPECT_EQ(shared.is_facet(f), own.is_facet(f)) << "loop " << f;
    if (!own.is_facet(f)) continue;
    EXPECT_EQ(shared.facet_cells(f), own.facet_cells(f)) << "facet " << f;
    EXPECT_EQ(shared.facet_loop(f), own.facet_loop(f)) << "facet " << f;
  }
  for (int v = 0; v < 15; ++v) {
    const auto a = shared.vertex_cells().of(v), b = own.vertex_cells().of(v);
    EXPECT_EQ(std::vector<int>(a.begin(), a.end()), std::vector<int>(b.begin(), b.end())) << "vertex " << v;
  }
  // the faces the cells share: the cubes' side x = 1, and the first cube's top, a side of the prism
  const int side = shared.find_facet({1, 2, 5, 6});
  ASSERT_GE(side, 0);
  EXPECT_EQ(shared.facet_cells(side), (std::array<int, 2>{0, 1}));
  EXPECT_EQ(shared.facet_loop(side), (std::vector<int>{1, 2, 6, 5}));
  const int top = shared.find_facet({7, 6, 5, 4});
  ASSERT_GE(top, 0);
  EXPECT_EQ(shared.facet_cells(top), (std::array<int, 2>{0, 2}));
  EXPECT_EQ(shared.facet_loop(top), (std::vector<int>{4, 5, 6, 7}));
  const int end = shared.find_facet({5, 8, 4});  // the prism's triangle at y = 0
  ASSERT_GE(end, 0);
  EXPECT_EQ(shared.facet_cells(end), (std::array<int, 2>{2, -1}));
  EXPECT_EQ(shared.facet_loop(end), (std::vector<int>{4, 8, 5}));
  EXPECT_EQ(shared.find_facet({4, 5, 6}), -1);

  std::vector<int> short_start{0, 8, 15, 21};  // the second hexahedron given 7 corners
  std::vector<int> short_flat(flat.begin(), flat.begin() + 15);
  short_flat.insert(short_flat.end(), corners[2].begin(), corners[2].end());
  EXPECT_THROW(CellTopology(3, 15, shapes, kind, short_start, short_flat), InternalError);
  EXPECT_THROW(CellTopology(3, 14, shapes, kind, start, flat), InternalError);  // vertex 14 named
}

}  // namespace
