#include <hemivem/mesh/mesh.hpp>

#include <gtest/gtest.h>

using hemivem::Mesh;
using hemivem::Vec2;

namespace {

// Two unit squares side by side: vertices 0..5, shared edge 1-4.
Mesh two_squares() {
  return Mesh({{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}}, {{0, 1, 4, 3}, {1, 2, 5, 4}});
}

std::string first_defect(std::vector<Vec2> v, std::vector<std::vector<int>> e) {
  auto d = hemivem::find_mesh_defects(v, e);
  return d.empty() ? std::string() : std::to_string(d[0].element) + ": " + d[0].message;
}

}  // namespace

TEST(Mesh, TopologyAndGeometryOfTwoSquares) {
  const Mesh m = two_squares();
  EXPECT_EQ(m.num_vertices(), 6);
  EXPECT_EQ(m.num_elements(), 2);
  EXPECT_EQ(m.num_edges(), 7);
  EXPECT_EQ(m.boundary_edges().size(), 6u);
  EXPECT_EQ(m.boundary_vertices().size(), 6u);
  int interior = 0;
  for (const auto& e : m.edges()) {
    if (!e.on_boundary()) {
      ++interior;
      EXPECT_EQ(std::min(e.v0, e.v1), 1);
      EXPECT_EQ(std::max(e.v0, e.v1), 4);
      EXPECT_NE(e.left, e.right);
    }
  }
  EXPECT_EQ(interior, 1);
  EXPECT_DOUBLE_EQ(m.area(0), 1.0);
  EXPECT_DOUBLE_EQ(m.area(1), 1.0);
  EXPECT_NEAR(m.centroid(1).x(), 1.5, 1e-15);
  EXPECT_NEAR(m.centroid(1).y(), 0.5, 1e-15);
  EXPECT_DOUBLE_EQ(m.diameter(0), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(m.h(), std::sqrt(2.0));
  // local edge i of an element runs from local vertex i to i+1
  for (int e = 0; e < 2; ++e) {
    const auto vs = m.element(e);
    const auto es = m.element_edges(e);
    for (std::size_t i = 0; i < vs.size(); ++i) {
      const auto& ed = m.edge(es[i]);
      const int a = vs[i], b = vs[(i + 1) % vs.size()];
      EXPECT_TRUE((ed.v0 == a && ed.v1 == b && ed.left == e) || (ed.v0 == b && ed.v1 == a && ed.right == e));
    }
  }
}

TEST(Mesh, CentroidOfNonConvexLShape) {
  // L-shape made of three unit squares: centroid (5/6, 5/6), area 3.
  const Mesh m({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}, {{0, 1, 2, 3, 4, 5}});
  EXPECT_DOUBLE_EQ(m.area(0), 3.0);
  EXPECT_NEAR(m.centroid(0).x(), 5.0 / 6.0, 1e-15);
  EXPECT_NEAR(m.centroid(0).y(), 5.0 / 6.0, 1e-15);
}

TEST(Mesh, DefectsAreNamed) {
  const std::vector<Vec2> sq{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_EQ(first_defect(sq, {{0, 1, 2, 3}}), "");
  EXPECT_NE(first_defect(sq, {{0, 3, 2, 1}}).find("clockwise"), std::string::npos);
  EXPECT_NE(first_defect(sq, {{0, 1, 1, 3}}).find("repeats vertex 1"), std::string::npos);
  EXPECT_NE(first_defect(sq, {{0, 1, 7}}).find("out of range"), std::string::npos);
  EXPECT_NE(first_defect(sq, {{0, 1}}).find("at least 3"), std::string::npos);
  // bow-ties are self-intersecting whatever the sign of their net area
  const std::vector<Vec2> bow{{0, 0}, {3, 0}, {0, 1}, {1, -0.2}};
  EXPECT_NE(first_defect(bow, {{0, 1, 2, 3}}).find("self-intersecting"), std::string::npos);
  EXPECT_NE(first_defect(bow, {{0, 3, 2, 1}}).find("self-intersecting"), std::string::npos);
  const std::vector<Vec2> sym_bow{{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  EXPECT_NE(first_defect(sym_bow, {{0, 1, 2, 3}}).find("self-intersecting"), std::string::npos);
  // a crack: the second square uses its own copies of vertices 1 and 4
  const std::vector<Vec2> crack{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {1, 0}, {1, 1}};
  EXPECT_NE(first_defect(crack, {{0, 1, 4, 3}, {6, 2, 5, 7}}).find("coincides with vertex 1"), std::string::npos);
  // the same crack with the vertices in rows, (y, x) increasing up to the copy of vertex 1,
  // which follows it: row order alone proves nothing
  const std::vector<Vec2> rows{{0, 0}, {1, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}};
  EXPECT_NE(first_defect(rows, {{0, 1, 5, 4}, {2, 3, 6, 5}}).find("vertex 2 (1, 0), which coincides with vertex 1"),
            std::string::npos);
  // in rows and distinct, an unused copy of a used vertex between them: no defect
  const std::vector<Vec2> unused{{0, 0}, {1, 0}, {0, 0}, {0, 1}, {1, 1}};
  EXPECT_EQ(first_defect(unused, {{0, 1, 4, 3}}), "");
  // a clockwise sliver is reported with a readable area
  const std::vector<Vec2> sliver{{0, 0}, {1, 1e-300}, {2, 0}};
  EXPECT_NE(first_defect(sliver, {{0, 1, 2}}).find("clockwise (signed area -1e-300)"), std::string::npos);
  // hanging vertex: one big square next to two half squares
  const std::vector<Vec2> hv{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {1, 0.5}, {2, 0.5}};
  EXPECT_NE(first_defect(hv, {{0, 1, 4, 3}, {1, 2, 7, 6}, {6, 7, 5, 4}}).find("hanging"), std::string::npos);
  // same edge twice in the same direction
  EXPECT_NE(first_defect(sq, {{0, 1, 2}, {0, 1, 3}}).find("same direction"), std::string::npos);
  // collinear points: zero area
  EXPECT_NE(first_defect({{0, 0}, {1, 0}, {2, 0}}, {{0, 1, 2}}).find("zero area"), std::string::npos);
}

TEST(Mesh, ConstructorThrowsWithElement) {
  try {
    Mesh m({{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{0, 1, 2, 3}, {0, 3, 2}});
    FAIL() << "expected MeshError";
  } catch (const hemivem::MeshError& e) {
    EXPECT_EQ(e.element(), 1);
    EXPECT_NE(std::string(e.what()).find("element 1"), std::string::npos);
  }
}

TEST(Mesh, TinyEdgesAreLegal) {
  // a pentagon with an edge of 1e-13 next to a neighbour sharing it
  const std::vector<Vec2> v{{0, 0}, {1, 0}, {1, 1}, {1 - 1e-13, 1}, {0, 1}, {2, 0}, {2, 1}};
  EXPECT_EQ(first_defect(v, {{0, 1, 2, 3, 4}, {1, 5, 6, 2}}), "");
}

TEST(Mesh, NamedEdgeGroups) {
  Mesh m = two_squares();
  std::vector<int> bottom;
  for (int id : m.boundary_edges())
    if (m.vertex(m.edge(id).v0).y() == 0.0 && m.vertex(m.edge(id).v1).y() == 0.0) bottom.push_back(id);
  m.set_edge_group("contact", bottom);
  EXPECT_EQ(m.edge_group("contact").size(), 2u);
  try {
    m.edge_group("top");
    FAIL() << "expected InputError";
  } catch (const hemivem::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no edge group 'top'; its groups: contact"), std::string::npos) << e.what();
  }
  EXPECT_THROW(m.set_edge_group("bad", {99}), hemivem::InputError);
}
