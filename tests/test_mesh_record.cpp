// MeshRecord (hemivem/mesh/mesh_record.hpp): a mesh made again from its record is the mesh,
// to the bit, in both dimensions: generated, read from files with groups and regions, and
// refined (hanging vertices, polygons and polyhedra).
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/mesh/mesh_record.hpp>
#include <hemivem/mesh/refine.hpp>
#include <hemivem/mesh/refine3d.hpp>

#include <gtest/gtest.h>

#include "test_support.hpp"

#include <vector>

namespace {

using namespace hemivem;

// every other cell marked
std::vector<int> every_other(int cells) {
  std::vector<int> marked;
  for (int c = 0; c < cells; c += 2) marked.push_back(c);
  return marked;
}

void expect_same(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_elements(), b.num_elements());
  ASSERT_EQ(a.num_edges(), b.num_edges());
  for (int v = 0; v < a.num_vertices(); ++v) ASSERT_EQ(a.vertex(v), b.vertex(v)) << "vertex " << v;
  for (int e = 0; e < a.num_elements(); ++e) {
    const auto x = a.element(e), y = b.element(e);
    ASSERT_EQ(std::vector<int>(x.begin(), x.end()), std::vector<int>(y.begin(), y.end())) << "element " << e;
    const auto p = a.element_edges(e), q = b.element_edges(e);
    ASSERT_EQ(std::vector<int>(p.begin(), p.end()), std::vector<int>(q.begin(), q.end())) << "element " << e;
    // to the bit
    ASSERT_EQ(a.area(e), b.area(e));
    ASSERT_EQ(a.centroid(e), b.centroid(e));
    ASSERT_EQ(a.diameter(e), b.diameter(e));
  }
  for (int f = 0; f < a.num_edges(); ++f) {
    const MeshEdge &x = a.edge(f), &y = b.edge(f);
    ASSERT_TRUE(x.v0 == y.v0 && x.v1 == y.v1 && x.left == y.left && x.right == y.right) << "edge " << f;
  }
  EXPECT_EQ(a.boundary_edges(), b.boundary_edges());
  EXPECT_EQ(a.regions(), b.regions());
  EXPECT_EQ(a.edge_groups(), b.edge_groups());
  EXPECT_EQ(a.h(), b.h());
}

void expect_same(const Mesh3D& a, const Mesh3D& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_cells(), b.num_cells());
  ASSERT_EQ(a.num_faces(), b.num_faces());
  for (int v = 0; v < a.num_vertices(); ++v) ASSERT_EQ(a.vertex(v), b.vertex(v)) << "vertex " << v;
  for (int c = 0; c < a.num_cells(); ++c) {
    ASSERT_EQ(a.cell_faces(c), b.cell_faces(c)) << "cell " << c;
    ASSERT_EQ(a.cell_vertices(c), b.cell_vertices(c)) << "cell " << c;
    ASSERT_EQ(a.volume(c), b.volume(c));
    ASSERT_EQ(a.centroid(c), b.centroid(c));
    ASSERT_EQ(a.diameter(c), b.diameter(c));
  }
  for (int f = 0; f < a.num_faces(); ++f) {
    ASSERT_EQ(a.face(f).vertices, b.face(f).vertices) << "face " << f;
    ASSERT_EQ(a.face(f).inner, b.face(f).inner) << "face " << f;
    ASSERT_EQ(a.face(f).outer, b.face(f).outer) << "face " << f;
    ASSERT_EQ(a.face_area(f), b.face_area(f));
    ASSERT_EQ(a.face_normal(f), b.face_normal(f));
    ASSERT_EQ(a.face_centroid(f), b.face_centroid(f));
  }
  EXPECT_EQ(a.boundary_faces(), b.boundary_faces());
  EXPECT_EQ(a.regions(), b.regions());
  EXPECT_EQ(a.face_groups(), b.face_groups());
  EXPECT_EQ(a.h(), b.h());
}

template <int dim>
void expect_made_again(const MeshOf<dim>& mesh) {
  expect_same(MeshRecord<dim>(mesh).make(), mesh);
}

TEST(MeshRecord, APlaneMeshMadeAgainFromItsRecordIsTheMesh) {
  const Mesh file = read_gmsh(test::data_dir() / "gmsh" / "unit_square_triangles.msh");
  ASSERT_FALSE(file.edge_groups().empty());
  for (const Mesh& mesh : {make_squares(6), make_voronoi(GridSize{9, 7}), file}) {
    SCOPED_TRACE(mesh.num_elements());
    expect_made_again<2>(mesh);
    // refined twice: elements with hanging vertices, the groups and regions inherited
    const Mesh once = refine_mesh(mesh, every_other(mesh.num_elements())).mesh;
    const Mesh twice = refine_mesh(once, every_other(once.num_elements())).mesh;
    expect_made_again<2>(twice);
  }
  Mesh regions = make_squares(4);
  std::vector<int> ids(static_cast<std::size_t>(regions.num_elements()));
  for (std::size_t e = 0; e < ids.size(); ++e) ids[e] = static_cast<int>(e % 3);
  regions.set_regions(ids);
  expect_made_again<2>(regions);
}

TEST(MeshRecord, ASolidMeshMadeAgainFromItsRecordIsTheMesh) {
  const Mesh3D file = read_gmsh3d(test::data_dir() / "gmsh3d" / "two_boxes_tetrahedra.msh");
  ASSERT_FALSE(file.face_groups().empty());
  for (const Mesh3D& mesh : {make_cubes({3, 4, 2}), file}) {
    SCOPED_TRACE(mesh.num_cells());
    expect_made_again<3>(mesh);
    // refined twice: polyhedra whose faces hold hanging vertices, faces stored from either side
    const Mesh3D once = refine_mesh(mesh, every_other(mesh.num_cells())).mesh;
    const Mesh3D twice = refine_mesh(once, every_other(once.num_cells())).mesh;
    expect_made_again<3>(twice);
  }
}

}  // namespace
