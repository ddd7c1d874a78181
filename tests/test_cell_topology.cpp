// The cells of a mesh not made (core/mesh/src/cell_topology.hpp): the facets their loops share,
// found among the cells around each loop's smallest vertex, against the facets the meshes
// themselves find (Mesh's edges, Mesh3D's faces) and against hand counts.
#include <hemivem/mesh/generators.hpp>
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

}  // namespace
