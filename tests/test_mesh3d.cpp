// Polyhedral meshes: the checks of Mesh3D, the box generators and the selection of box sides.
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh3d.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace hemivem;

namespace {

std::vector<Vec3> unit_cube_vertices() {
  std::vector<Vec3> v;
  for (int b = 0; b < 8; ++b) v.emplace_back(b & 1, b >> 1 & 1, b >> 2 & 1);
  return v;
}

CellFaces unit_cube() {
  return {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
}

std::string defect_of(const std::vector<Vec3>& v, const std::vector<CellFaces>& cells) {
  const auto d = find_mesh3d_defects(v, cells);
  return d.empty() ? std::string() : d.front().message;
}

}  // namespace

TEST(Mesh3D, OneCubeHasItsGeometry) {
  const Mesh3D mesh(unit_cube_vertices(), {unit_cube()});
  EXPECT_EQ(mesh.num_cells(), 1);
  EXPECT_EQ(mesh.num_faces(), 6);
  EXPECT_EQ(mesh.boundary_faces().size(), 6u);
  EXPECT_NEAR(mesh.volume(0), 1.0, 1e-15);
  EXPECT_TRUE(mesh.centroid(0).isApprox(Vec3(0.5, 0.5, 0.5), 1e-15));
  EXPECT_NEAR(mesh.diameter(0), std::sqrt(3.0), 1e-15);
  for (int f = 0; f < 6; ++f) {
    EXPECT_NEAR(mesh.face_area(f), 1.0, 1e-15);
    // outward: the normal points away from the centroid
    EXPECT_GT(mesh.face_normal(f).dot(mesh.face_centroid(f) - mesh.centroid(0)), 0.49);
  }
}

TEST(Mesh3D, DefectsNameTheCell) {
  auto v = unit_cube_vertices();
  // inward faces
  CellFaces inward = unit_cube();
  for (auto& f : inward) std::reverse(f.begin(), f.end());
  EXPECT_NE(defect_of(v, {inward}).find("negative volume"), std::string::npos) << defect_of(v, {inward});
  // a face turned alone: not consistently oriented
  CellFaces turned = unit_cube();
  std::reverse(turned[2].begin(), turned[2].end());
  EXPECT_NE(defect_of(v, {turned}).find("consistently oriented"), std::string::npos);
  // a missing face: not closed
  CellFaces open = unit_cube();
  open.pop_back();
  open.push_back({4, 5, 7});
  EXPECT_NE(defect_of(v, {open}).find("not closed"), std::string::npos);
  // a vertex lifted off its face's plane
  auto bent = v;
  bent[7] = Vec3(1, 1, 1.01);
  EXPECT_NE(defect_of(bent, {unit_cube()}).find("not planar"), std::string::npos);
  // an index out of range, a repeated vertex
  CellFaces bad = unit_cube();
  bad[0][0] = 8;
  EXPECT_NE(defect_of(v, {bad}).find("out of range"), std::string::npos);
  CellFaces rep = unit_cube();
  rep[0][1] = rep[0][0];
  EXPECT_NE(defect_of(v, {rep}).find("repeats"), std::string::npos);
  EXPECT_THROW(Mesh3D(v, {inward}), MeshError);
  try {
    Mesh3D(v, {unit_cube(), inward});
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_EQ(e.element(), 1);
    EXPECT_NE(std::string(e.what()).find("cell 1"), std::string::npos);
  }
}

TEST(Mesh3D, HangingVertexAndSameOrientationAreRefused) {
  // two cubes side by side, sharing the face x = 1, given with the same orientation by both
  std::vector<Vec3> v;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) v.emplace_back(i, j, k);
  auto id = [](int i, int j, int k) { return (k * 2 + j) * 3 + i; };
  auto cube = [&](int i) -> CellFaces {
    const int c[8] = {id(i, 0, 0), id(i + 1, 0, 0), id(i, 1, 0), id(i + 1, 1, 0),
                      id(i, 0, 1), id(i + 1, 0, 1), id(i, 1, 1), id(i + 1, 1, 1)};
    return {{c[0], c[4], c[6], c[2]}, {c[1], c[3], c[7], c[5]}, {c[0], c[1], c[5], c[4]},
            {c[2], c[6], c[7], c[3]}, {c[0], c[2], c[3], c[1]}, {c[4], c[5], c[7], c[6]}};
  };
  const Mesh3D two(v, {cube(0), cube(1)});
  EXPECT_EQ(two.num_faces(), 11);
  EXPECT_EQ(two.boundary_faces().size(), 10u);
  EXPECT_NEAR(two.total_volume(), 2.0, 1e-14);
  // a cube beside a cube whose shared face is split in two: non-matching faces
  std::vector<Vec3> w = v;
  w.emplace_back(1, 0.5, 0);
  w.emplace_back(1, 0.5, 1);
  const int m0 = 12, m1 = 13;
  CellFaces split = cube(1);
  // the second cube's x = 1 face with the midpoints of its edges y: a hexagon in its plane
  split[0] = {id(1, 0, 0), id(1, 0, 1), m1, id(1, 1, 1), id(1, 1, 0), m0};
  split[2] = {id(1, 0, 0), id(2, 0, 0), id(2, 0, 1), id(1, 0, 1)};
  split[4] = {id(1, 0, 0), m0, id(1, 1, 0), id(2, 1, 0), id(2, 0, 0)};
  split[5] = {id(1, 0, 1), id(2, 0, 1), id(2, 1, 1), id(1, 1, 1), m1};
  const std::string d = defect_of(w, {cube(0), split});
  EXPECT_NE(d.find("hanging vertex"), std::string::npos) << d;
}

TEST(Mesh3D, CubesAndTetrahedraTileTheBox) {
  const Box box{0.0, 2.0, -1.0, 0.5, 1.0, 1.75};
  for (const Mesh3D& mesh : {make_cubes({3, 2, 4}, box), make_tetrahedra({3, 2, 4}, box)}) {
    EXPECT_NEAR(mesh.total_volume(), 2.0 * 1.5 * 0.75, 1e-13);
    EXPECT_EQ(mesh.num_vertices(), 4 * 3 * 5);
    // every boundary face lies on a side, and the sides hold them all
    std::size_t on_sides = 0;
    for (const std::string side : {"x0", "x1", "y0", "y1", "z0", "z1"}) {
      const auto faces = select_box_side(mesh, box, side);
      double area = 0.0;
      for (int f : faces) area += mesh.face_area(f);
      const double expected = side[0] == 'x' ? 1.5 * 0.75 : side[0] == 'y' ? 2.0 * 0.75 : 2.0 * 1.5;
      EXPECT_NEAR(area, expected, 1e-13) << side;
      on_sides += faces.size();
    }
    EXPECT_EQ(on_sides, mesh.boundary_faces().size());
    EXPECT_EQ(select_box_side(mesh, box, "top"), select_box_side(mesh, box, "z1"));
  }
  EXPECT_EQ(make_tetrahedra(2).num_cells(), 48);
  EXPECT_THROW(select_box_side(make_cubes(1), Box{}, "left"), InputError);
}

TEST(Mesh3D, GeneratorsCheckTheirArguments) {
  EXPECT_THROW(make_cubes(0), InputError);
  EXPECT_THROW(make_cubes({2, 2, 1001}), InputError);
  EXPECT_THROW(make_tetrahedra(2, Box{1, 0, 0, 1, 0, 1}), InputError);
  EXPECT_THROW(make_cubes(2, Box{0, 1, 0, 1, 0, std::nan("")}), InputError);
  EXPECT_THROW(make_mesh3d("squares", 2), InputError);
  EXPECT_EQ(GridSize3(4).text(), "4");
  EXPECT_EQ(GridSize3(4, 3, 2).text(), "[4, 3, 2]");
}

TEST(Mesh3D, FaceGroupsAndLocalFaces) {
  Mesh3D mesh = make_cubes(2);
  const auto top = select_box_side(mesh, Box{}, "top");
  mesh.set_face_group("lid", top);
  EXPECT_EQ(select_boundary_faces(mesh, "lid"), top);
  EXPECT_THROW(mesh.face_group("nothing"), InputError);
  EXPECT_THROW(mesh.set_face_group("bad", {1000}), InputError);
  // an interior face in a group is refused as a boundary part
  int interior = -1;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (!mesh.face(f).on_boundary()) interior = f;
  mesh.set_face_group("inside", {interior});
  EXPECT_THROW(select_boundary_faces(mesh, "inside"), InputError);
  // local faces index the cell's sorted vertices and run outward
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto local = mesh.local_faces(c);
    const auto& cv = mesh.cell_vertices(c);
    ASSERT_EQ(local.size(), 6u);
    for (const auto& loop : local) {
      std::vector<Vec3> z;
      for (int i : loop) z.push_back(mesh.vertex(cv[static_cast<std::size_t>(i)]));
      EXPECT_GT(polygon_area_vector(z).dot(polygon_centroid(z) - mesh.centroid(c)), 0.0);
    }
  }
}
