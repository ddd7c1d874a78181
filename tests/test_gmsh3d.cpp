// Gmsh 4.1 ASCII files of solid meshes: reading tetrahedra, hexahedra, prisms and pyramids with
// regions and face groups, writing them back, and the errors of malformed files.
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using hemivem::Box;
using hemivem::Mesh3D;
using hemivem::Vec3;
using hemivem::test::input_error_of;

namespace {

std::filesystem::path mixed_path() { return hemivem::test::data_dir() / "gmsh3d" / "mixed.msh"; }

std::string mixed_text() {
  std::ifstream in(mixed_path(), std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Mesh3D read_text(const std::string& text, const std::string& name = "mixed.msh") {
  std::istringstream in(text);
  return hemivem::read_gmsh3d(in, name);
}

/// The text with its line `number` (1-based) replaced by `line`.
std::string with_line(std::string text, int number, const std::string& line) {
  std::size_t start = 0;
  for (int i = 1; i < number; ++i) start = text.find('\n', start) + 1;
  const std::size_t end = text.find('\n', start);
  return text.replace(start, end - start, line);
}

/// The first `count` lines of the text.
std::string first_lines(const std::string& text, int count) {
  std::size_t end = 0;
  for (int i = 0; i < count; ++i) end = text.find('\n', end) + 1;
  return text.substr(0, end);
}

/// A cell as the set of its faces, each face as its loop rotated to start at its smallest vertex.
std::set<std::vector<int>> face_set(const hemivem::CellFaces& faces) {
  std::set<std::vector<int>> out;
  for (auto f : faces) {
    std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
    out.insert(f);
  }
  return out;
}

/// The same vertices (bit for bit), cells (the same oriented faces), regions and face groups
/// (the same faces by their vertex sets).
void expect_same_mesh(const Mesh3D& a, const Mesh3D& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_cells(), b.num_cells());
  for (int v = 0; v < a.num_vertices(); ++v) EXPECT_EQ(a.vertex(v), b.vertex(v)) << "vertex " << v;
  for (int c = 0; c < a.num_cells(); ++c) EXPECT_EQ(face_set(a.cell(c)), face_set(b.cell(c))) << "cell " << c;
  EXPECT_EQ(a.regions(), b.regions());
  ASSERT_EQ(a.face_groups().size(), b.face_groups().size());
  auto keys = [](const Mesh3D& m, const std::vector<int>& faces) {
    std::set<std::vector<int>> out;
    for (int f : faces) {
      auto k = m.face(f).vertices;
      std::sort(k.begin(), k.end());
      out.insert(k);
    }
    return out;
  };
  for (const auto& [name, faces] : a.face_groups()) {
    ASSERT_TRUE(b.face_groups().count(name)) << name;
    EXPECT_EQ(keys(a, faces), keys(b, b.face_group(name))) << name;
  }
}

Mesh3D round_trip(const Mesh3D& m) {
  std::ostringstream out;
  hemivem::write_gmsh3d(m, out);
  return read_text(out.str(), "written.msh");
}

TEST(Gmsh3D, ReadsMixedElements) {
  const Mesh3D m = hemivem::read_gmsh3d(mixed_path());
  // a hexahedron, a pyramid on its side x = 1, a prism on its side y = 1 and a tetrahedron on
  // a face of the pyramid; node 13 (a geometry point) is in no cell
  EXPECT_EQ(m.num_vertices(), 12);
  ASSERT_EQ(m.num_cells(), 4);
  EXPECT_EQ(m.num_faces(), 6 + 5 + 5 + 4 - 3);
  const double volumes[4] = {1.0, 1.0 / 6.0, 0.25, 1.0 / 12.0};
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(m.volume(c), volumes[c], 1e-15) << "cell " << c;
  EXPECT_NEAR(m.total_volume(), 1.5, 1e-14);
  EXPECT_EQ(m.regions(), (std::vector<int>{1, 2, 1, 0}));
  EXPECT_EQ(m.cell_faces(0).size(), 6u);
  EXPECT_EQ(m.cell_faces(1).size(), 5u);
  EXPECT_EQ(m.cell_faces(2).size(), 5u);
  EXPECT_EQ(m.cell_faces(3).size(), 4u);
  EXPECT_EQ(m.vertex(8), Vec3(1.5, 0.5, 0.5));

  ASSERT_EQ(m.face_groups().size(), 3u);
  const auto& bottom = m.face_group("bottom");
  ASSERT_EQ(bottom.size(), 2u);
  double area = 0.0;
  for (int f : bottom) {
    EXPECT_TRUE(m.face(f).on_boundary());
    EXPECT_EQ(m.face_normal(f), Vec3(0, 0, -1));
    area += m.face_area(f);
  }
  EXPECT_DOUBLE_EQ(area, 1.25);
  ASSERT_EQ(m.face_group("tip").size(), 1u);
  EXPECT_EQ(m.face(m.face_group("tip")[0]).inner, 3);
  ASSERT_EQ(m.face_group("12").size(), 1u);  // an unnamed physical surface: its tag
  EXPECT_EQ(m.face_normal(m.face_group("12")[0]), Vec3(0, 0, 1));
  EXPECT_DOUBLE_EQ(m.face_area(m.face_group("12")[0]), 1.0);
}

/// The total area of a face group.
double group_area(const Mesh3D& m, const std::string& name) {
  double a = 0.0;
  for (int f : m.face_group(name)) a += m.face_area(f);
  return a;
}

/// Cells per number of faces.
std::map<std::size_t, int> cell_kinds(const Mesh3D& m) {
  std::map<std::size_t, int> kinds;
  for (int c = 0; c < m.num_cells(); ++c) ++kinds[m.cell_faces(c).size()];
  return kinds;
}

TEST(Gmsh3D, ReadsFilesMadeByGmsh) {
  // tests/data/gmsh3d/*.geo made each .msh
  const auto dir = hemivem::test::data_dir() / "gmsh3d";
  {
    // two boxes side by side, their interface in the physical surface with all their surfaces
    const Mesh3D m = hemivem::read_gmsh3d(dir / "two_boxes_tetrahedra.msh");
    EXPECT_NEAR(m.total_volume(), 2.0, 1e-14);
    EXPECT_EQ(cell_kinds(m), (std::map<std::size_t, int>{{4, m.num_cells()}}));
    for (int c = 0; c < m.num_cells(); ++c)
      EXPECT_EQ(m.region(c), m.centroid(c).x() < 1.0 ? 5 : 7);
    EXPECT_NEAR(group_area(m, "bottom"), 2.0 * (2.0 * 2.0 + 2.0 * 0.5 + 2.0 * 0.5) + 2.0 * 0.5, 1e-13);
    std::size_t inner = 0;
    for (int f : m.face_group("bottom")) inner += m.face(f).on_boundary() ? 0 : 1;
    EXPECT_GT(inner, 0u);
    expect_same_mesh(round_trip(m), m);
  }
  {
    const Mesh3D m = hemivem::read_gmsh3d(dir / "cube_hexahedra.msh");
    EXPECT_EQ(cell_kinds(m), (std::map<std::size_t, int>{{6, 27}}));
    EXPECT_NEAR(m.total_volume(), 1.0, 1e-14);
    EXPECT_EQ(m.regions(), std::vector<int>(27, 2));
    EXPECT_EQ(m.face_group("base").size(), 9u);
    EXPECT_NEAR(group_area(m, "top"), 1.0, 1e-14);
    expect_same_mesh(round_trip(m), m);
  }
  {
    const Mesh3D m = hemivem::read_gmsh3d(dir / "cube_prisms.msh");
    EXPECT_EQ(cell_kinds(m), (std::map<std::size_t, int>{{5, m.num_cells()}}));
    EXPECT_NEAR(m.total_volume(), 1.0, 1e-14);
    EXPECT_NEAR(group_area(m, "top"), 1.0, 1e-14);
    expect_same_mesh(round_trip(m), m);
  }
  {
    // hexahedra below, tetrahedra above, pyramids between
    const Mesh3D m = hemivem::read_gmsh3d(dir / "hexahedra_pyramids_tetrahedra.msh");
    const auto kinds = cell_kinds(m);
    EXPECT_EQ(kinds.at(6), 8);
    EXPECT_EQ(kinds.at(5), 4);
    EXPECT_GT(kinds.at(4), 0);
    EXPECT_NEAR(m.total_volume(), 2.0, 1e-14);
    for (int c = 0; c < m.num_cells(); ++c) EXPECT_EQ(m.region(c), m.cell_faces(c).size() == 6 ? 1 : 2);
    EXPECT_NEAR(group_area(m, "bottom"), 1.0, 1e-14);
    EXPECT_NEAR(group_area(m, "top"), 1.0, 1e-14);
    expect_same_mesh(round_trip(m), m);
  }
}

TEST(Gmsh3D, ElementsOfNegativeOrientationAreTurnedOutward) {
  // the hexahedron with its bottom and top squares clockwise, the tetrahedron with two nodes swapped
  std::string text = with_line(mixed_text(), 71, "8 1 4 3 2 5 8 7 6");
  text = with_line(text, 77, "11 3 2 9 12");
  const Mesh3D m = read_text(text);
  const Mesh3D ref = hemivem::read_gmsh3d(mixed_path());
  expect_same_mesh(m, ref);
}

TEST(Gmsh3D, RoundTrips) {
  const Mesh3D mixed = hemivem::read_gmsh3d(mixed_path());
  expect_same_mesh(round_trip(mixed), mixed);

  Mesh3D tets = hemivem::make_tetrahedra(hemivem::GridSize3(2, 1, 3), Box{0, 2, -1, 0, 0, 3});
  std::vector<int> regions(static_cast<std::size_t>(tets.num_cells()));
  for (int c = 0; c < tets.num_cells(); ++c) regions[static_cast<std::size_t>(c)] = tets.centroid(c).z() < 1.5 ? 7 : 0;
  tets.set_regions(regions);
  tets.set_face_group("bottom", hemivem::select_box_side(tets, Box{0, 2, -1, 0, 0, 3}, "bottom"));
  tets.set_face_group("sides and top", hemivem::select_boundary_faces(tets, [](const Vec3& p) { return p.z() > 0; }));
  tets.set_face_group("empty", {});
  expect_same_mesh(round_trip(tets), tets);

  Mesh3D cubes = hemivem::make_cubes(hemivem::GridSize3(3, 2, 1), Box{-1, 0.5, 0, 0.25, 1e3, 1e3 + 1});
  cubes.set_face_group("x1", hemivem::select_box_side(cubes, Box{-1, 0.5, 0, 0.25, 1e3, 1e3 + 1}, "x1"));
  // an interior face in a group too
  for (int f = 0; f < cubes.num_faces(); ++f)
    if (!cubes.face(f).on_boundary()) {
      cubes.set_face_group("inner", {f});
      break;
    }
  expect_same_mesh(round_trip(cubes), cubes);

  // through a file
  const auto path = std::filesystem::temp_directory_path() / "hemivem_test_gmsh3d_round_trip.msh";
  hemivem::write_gmsh3d(tets, path);
  expect_same_mesh(hemivem::read_gmsh3d(path), tets);
  std::filesystem::remove(path);
}

/// The volume of a Gmsh volume element of `type` on the points `x` (in Gmsh's node order), from
/// its faces as Gmsh's reference elements give them (positive for Gmsh's orientation).
double gmsh_volume(int type, const std::vector<Vec3>& x) {
  static const std::map<int, std::vector<std::vector<int>>> faces = {
      {4, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}},
      {5, {{0, 3, 2, 1}, {0, 1, 5, 4}, {0, 4, 7, 3}, {1, 2, 6, 5}, {2, 3, 7, 6}, {4, 5, 6, 7}}},
      {6, {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {0, 3, 5, 2}, {1, 2, 5, 4}}},
      {7, {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}}};
  double v = 0.0;
  for (const auto& f : faces.at(type))
    for (std::size_t k = 1; k + 1 < f.size(); ++k)
      v += x[static_cast<std::size_t>(f[0])].dot(x[static_cast<std::size_t>(f[k])].cross(x[static_cast<std::size_t>(f[k + 1])])) / 6.0;
  return v;
}

TEST(Gmsh3D, WritesElementsInGmshNodeOrder) {
  // every volume element written, read with Gmsh's node ordering, has its cell's volume
  const Mesh3D m = hemivem::read_gmsh3d(mixed_path());
  std::ostringstream out;
  hemivem::write_gmsh3d(m, out);
  std::istringstream in(out.str());
  std::string line;
  while (std::getline(in, line) && line != "$Elements") {
  }
  std::getline(in, line);
  int blocks = 0, total = 0;
  std::istringstream(line) >> blocks >> total;
  EXPECT_EQ(total, 4 + 4);  // 4 cells, 4 faces in groups
  int cells = 0;
  std::map<int, int> types;
  for (int b = 0; b < blocks; ++b) {
    int dim = 0, entity = 0, type = 0, n = 0;
    std::getline(in, line);
    std::istringstream(line) >> dim >> entity >> type >> n;
    for (int i = 0; i < n; ++i) {
      std::getline(in, line);
      if (dim != 3) continue;
      std::istringstream e(line);
      int tag = 0, node = 0;
      e >> tag;
      std::vector<Vec3> x;
      while (e >> node) x.push_back(m.vertex(node - 1));
      EXPECT_EQ(tag, cells + 1);  // the cells first, in their order
      EXPECT_NEAR(gmsh_volume(type, x), m.volume(cells), 1e-15) << line;
      ++types[type];
      ++cells;
    }
  }
  EXPECT_EQ(cells, 4);
  EXPECT_EQ(types, (std::map<int, int>{{4, 1}, {5, 1}, {6, 1}, {7, 1}}));
}

TEST(Gmsh3D, PolyhedraCannotBeWritten) {
  const Mesh3D voronoi = hemivem::make_voronoi3d(2, Box{}, {});
  std::ostringstream out;
  const std::string e = input_error_of([&] { hemivem::write_gmsh3d(voronoi, out); });
  EXPECT_NE(e.find("cell "), std::string::npos) << e;
  EXPECT_NE(e.find("Gmsh has no polyhedron element"), std::string::npos) << e;
  EXPECT_EQ(out.str(), "");  // nothing written

  Mesh3D cubes = hemivem::make_cubes(1);
  cubes.set_face_group("a \"quoted\" name", {0});
  EXPECT_NE(input_error_of([&] { hemivem::write_gmsh3d(cubes, out); }).find("double quote"), std::string::npos);
  cubes = hemivem::make_cubes(1);
  cubes.set_regions({1000001});
  EXPECT_NE(input_error_of([&] { hemivem::write_gmsh3d(cubes, out); }).find("cell 0"), std::string::npos);
}

TEST(Gmsh3D, MalformedFilesNameTheFileAndLine) {
  const std::string text = mixed_text();
  struct Case {
    std::string text;
    int line;
    std::string says;
  };
  const std::vector<Case> cases = {
      {with_line(text, 1, "$Mesh"), 1, "$MeshFormat"},
      {with_line(text, 2, "2.2 0 8"), 2, "version"},
      {with_line(text, 2, "4.1 1 8"), 2, "binary"},
      {with_line(text, 19, "1 0 0 0 1 1.5 1 1 0 0"), 19, "region"},
      {with_line(text, 30, "1"), 30, "appears twice"},
      {with_line(text, 41, "0 0 x"), 41, "not a finite number"},
      {with_line(text, 55, "11 12 1 11"), 55, "declares 12"},
      {with_line(text, 65, "5 1 12 9"), 65, "not a face"},
      {with_line(text, 71, "8 1 2 3 4 5 6 7"), 71, "lists 7 node tags"},
      {with_line(text, 71, "8 1 2 4 3 5 6 7 8"), 71, "Gmsh element 8"},
      {with_line(text, 76, "3 3 11 1"), 76, "second-order tetrahedron"},
      {with_line(text, 76, "3 3 3 1"), 76, "dimension"},
      {with_line(text, 76, "3 9 4 1"), 76, "volume entity 9"},
      {with_line(text, 77, "11 2 3 9 14"), 77, "node tag 14"},
      // truncated files
      {first_lines(text, 60), 55, "the element count 11 exceeds what the rest of the file can hold"},
      {first_lines(text, 30), 24, "the node count 13 exceeds what the rest of the file can hold"},
      {first_lines(text, 76), 76, "the file ends inside $Elements"},
      {first_lines(text, 77), 77, "the file ends before $EndElements"},
      {first_lines(text, 12), 12, "the file ends inside $Entities"},
      {"", 1, "no data"},
      // no volume element: a surface mesh
      {with_line(first_lines(text, 69) + "$EndElements\n", 55, "7 7 1 7"), 55, "no volume elements"},
  };
  for (const auto& c : cases) {
    const std::string e = input_error_of([&] { read_text(c.text); });
    EXPECT_NE(e.find("mixed.msh:" + std::to_string(c.line) + ":"), std::string::npos)
        << "expected line " << c.line << ": " << e;
    EXPECT_NE(e.find(c.says), std::string::npos) << "expected '" << c.says << "': " << e;
  }
  EXPECT_NE(input_error_of([] { hemivem::read_gmsh3d("/nonexistent/mesh.msh"); }).find("/nonexistent/mesh.msh"),
            std::string::npos);
}

}  // namespace
