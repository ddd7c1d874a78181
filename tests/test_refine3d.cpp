// Adaptive refinement of polyhedral meshes (hemivem/mesh/refine3d.hpp): the split of cubes,
// tetrahedra, Voronoi cells, prisms and pyramids, hanging vertices with at most one per side,
// what follows the refinement (regions, face groups, boundary, volume), the prolongation, the
// shape of the cells over ten levels, and the patch test on refined meshes.
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/mesh/refine3d.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <numeric>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "test_support.hpp"

using namespace hemivem;

namespace {

struct LinearCase {
  Vec3 a{0.3, -0.7, 0.2};
  Eigen::Matrix3d G =
      (Eigen::Matrix3d() << 0.011, -0.027, 0.004, 0.019, 0.005, -0.013, -0.008, 0.017, 0.009).finished();
  Vec3 operator()(const Vec3& x) const { return a + G * x; }
};

std::vector<int> all_cells(const Mesh3D& mesh) {
  std::vector<int> all(static_cast<std::size_t>(mesh.num_cells()));
  std::iota(all.begin(), all.end(), 0);
  return all;
}

std::vector<Vec3> points_of(const Mesh3D& mesh, const std::vector<int>& ids) {
  std::vector<Vec3> p;
  for (int v : ids) p.push_back(mesh.vertex(v));
  return p;
}

double diameter_of(const std::vector<Vec3>& p) {
  double d = 0.0;
  for (const Vec3& a : p)
    for (const Vec3& b : p) d = std::max(d, (a - b).norm());
  return d;
}

// The largest number of vertices strictly inside a side of a face: the longest run of
// consecutive vertices each lying between its two neighbours, within 1e-10 of the face's
// diameter of the segment joining them (an independent count of hanging vertices).
int most_vertices_inside_a_side(const Mesh3D& mesh, int f) {
  const std::vector<Vec3> p = points_of(mesh, mesh.face(f).vertices);
  const std::size_t n = p.size();
  const double d = diameter_of(p);
  std::vector<char> straight(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& a = p[(i + n - 1) % n];
    const Vec3& v = p[i];
    const Vec3& b = p[(i + 1) % n];
    const Vec3 w = b - a;
    straight[i] = (v - a).dot(w) > 0.0 && (v - b).dot(a - b) > 0.0 && w.cross(v - a).norm() <= 1e-10 * w.norm() * d;
  }
  int most = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!straight[i] || straight[(i + n - 1) % n]) continue;
    int run = 0;
    for (std::size_t j = i; straight[j % n] && run < static_cast<int>(n); ++j) ++run;
    most = std::max(most, run);
  }
  return most;
}

// The number of corners of a face (vertices that are not inside a side).
int face_corner_count(const Mesh3D& mesh, int f) {
  const std::vector<Vec3> p = points_of(mesh, mesh.face(f).vertices);
  const std::size_t n = p.size();
  const double d = diameter_of(p);
  int corners = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 w = p[(i + 1) % n] - p[(i + n - 1) % n];
    if (w.cross(p[i] - p[(i + n - 1) % n]).norm() > 1e-10 * w.norm() * d) ++corners;
  }
  return corners;
}

// Everything a refinement must keep, checked on any parent and refined mesh: parent vertices
// in place; volumes per parent and in total; regions; the refined set; the pieces of each
// parent face on its plane and covering its area; faces inside a split cell; the boundary and
// the bounding box; face groups; at most one vertex inside each side of a face; the
// prolongation (rows summing to 1, linear fields exact); determinism.
void expect_sound_refinement(const Mesh3D& parent, const RefinedMesh3D& r, std::span<const int> marked) {
  const Mesh3D& m = r.mesh;
  // round-off of coordinates of magnitude R on quantities of a cell or face of size d
  const Box box = parent.bounding_box();
  const double R = std::max({std::abs(box.x0), std::abs(box.x1), std::abs(box.y0), std::abs(box.y1), std::abs(box.z0),
                             std::abs(box.z1), box.size(0), box.size(1), box.size(2)});
  ASSERT_EQ(static_cast<int>(r.parent_cell.size()), m.num_cells());
  ASSERT_EQ(static_cast<int>(r.parent_face.size()), m.num_faces());
  ASSERT_EQ(r.prolongation.rows(), m.num_vertices());
  ASSERT_EQ(r.prolongation.cols(), parent.num_vertices());
  for (int v = 0; v < parent.num_vertices(); ++v)
    EXPECT_TRUE(m.vertex(v) == parent.vertex(v)) << "vertex " << v << " moved";

  EXPECT_NEAR(m.total_volume(), parent.total_volume(), 1e-12 * parent.total_volume());
  std::vector<double> child_volume(static_cast<std::size_t>(parent.num_cells()), 0.0);
  std::vector<int> count(static_cast<std::size_t>(parent.num_cells()), 0);
  for (int c = 0; c < m.num_cells(); ++c) {
    const int p = r.parent_cell[static_cast<std::size_t>(c)];
    ASSERT_TRUE(p >= 0 && p < parent.num_cells());
    EXPECT_GT(m.volume(c), 0.0);
    EXPECT_EQ(m.region(c), parent.region(p));
    child_volume[static_cast<std::size_t>(p)] += m.volume(c);
    ++count[static_cast<std::size_t>(p)];
  }
  for (int p = 0; p < parent.num_cells(); ++p)
    EXPECT_NEAR(child_volume[static_cast<std::size_t>(p)], parent.volume(p),
                1e-12 * parent.volume(p) + 1e-14 * std::pow(parent.diameter(p), 2) * R)
        << "parent " << p;

  EXPECT_TRUE(std::is_sorted(r.refined.begin(), r.refined.end()));
  EXPECT_TRUE(std::adjacent_find(r.refined.begin(), r.refined.end()) == r.refined.end());
  for (int c : marked) EXPECT_TRUE(std::binary_search(r.refined.begin(), r.refined.end(), c)) << c;
  for (int p = 0; p < parent.num_cells(); ++p) {
    const bool split = std::binary_search(r.refined.begin(), r.refined.end(), p);
    if (split) {
      EXPECT_GE(count[static_cast<std::size_t>(p)], 4) << "parent " << p;
    } else {
      EXPECT_EQ(count[static_cast<std::size_t>(p)], 1) << "parent " << p;
    }
  }

  // faces: each piece on its parent face's plane, the pieces covering its area; the faces
  // inside a split cell between two of its children
  std::vector<double> piece_area(static_cast<std::size_t>(parent.num_faces()), 0.0);
  for (int f = 0; f < m.num_faces(); ++f) {
    const int g = r.parent_face[static_cast<std::size_t>(f)];
    const MeshFace& face = m.face(f);
    if (g < 0) {
      ASSERT_FALSE(face.on_boundary()) << "face " << f << " inside a split cell is on the boundary";
      const int p = r.parent_cell[static_cast<std::size_t>(face.inner)];
      EXPECT_EQ(r.parent_cell[static_cast<std::size_t>(face.outer)], p);
      EXPECT_TRUE(std::binary_search(r.refined.begin(), r.refined.end(), p));
      continue;
    }
    ASSERT_LT(g, parent.num_faces());
    piece_area[static_cast<std::size_t>(g)] += m.face_area(f);
    const Vec3 n = parent.face_normal(g);
    EXPECT_GT(std::abs(n.dot(m.face_normal(f))), 1.0 - 1e-9) << "face " << f;
    const double size = std::sqrt(parent.face_area(g));
    for (int v : face.vertices)
      EXPECT_LE(std::abs(n.dot(m.vertex(v) - parent.face_centroid(g))), 1e-10 * size + 1e-14 * R)
          << "face " << f << " vertex " << v;
    EXPECT_EQ(face.on_boundary(), parent.face(g).on_boundary()) << "face " << f;
    EXPECT_LE(most_vertices_inside_a_side(m, f), 1) << "face " << f;
    EXPECT_LE(static_cast<int>(face.vertices.size()), 2 * face_corner_count(m, f)) << "face " << f;
  }
  for (int g = 0; g < parent.num_faces(); ++g)
    EXPECT_NEAR(piece_area[static_cast<std::size_t>(g)], parent.face_area(g),
                1e-12 * parent.face_area(g) + 1e-14 * std::sqrt(parent.face_area(g)) * R)
        << "parent face " << g;

  const Box a = parent.bounding_box(), b = m.bounding_box();
  EXPECT_TRUE(a.x0 == b.x0 && a.x1 == b.x1 && a.y0 == b.y0 && a.y1 == b.y1 && a.z0 == b.z0 && a.z1 == b.z1)
      << "bounding box changed";

  // face groups: the pieces of the group's faces
  ASSERT_EQ(m.face_groups().size(), parent.face_groups().size());
  for (const auto& [name, group] : parent.face_groups()) {
    std::vector<int> expected;
    for (int f = 0; f < m.num_faces(); ++f) {
      const int g = r.parent_face[static_cast<std::size_t>(f)];
      if (g >= 0 && std::binary_search(group.begin(), group.end(), g)) expected.push_back(f);
    }
    EXPECT_EQ(m.face_group(name), expected) << name;
  }

  // prolongation: rows sum to 1, linear fields exact at every vertex
  const LinearCase field;
  Eigen::VectorXd u(3 * parent.num_vertices());
  for (int v = 0; v < parent.num_vertices(); ++v) u.segment<3>(3 * v) = field(parent.vertex(v));
  const Eigen::VectorXd uf = prolongate(r, u);
  double err = 0.0, ref = 0.0;
  for (int v = 0; v < m.num_vertices(); ++v) {
    EXPECT_NEAR(r.prolongation.row(v).sum(), 1.0, 1e-13) << "row " << v;
    const Vec3 e = field(m.vertex(v));
    err = std::max(err, (uf.segment<3>(3 * v) - e).cwiseAbs().maxCoeff());
    ref = std::max(ref, e.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(err, 1e-12 * ref) << "prolongation of a linear field";

  const RefinedMesh3D again = refine_mesh(parent, marked);
  EXPECT_TRUE(again.mesh.vertices() == m.vertices()) << "not deterministic";
  bool same_cells = again.mesh.num_cells() == m.num_cells();
  for (int c = 0; same_cells && c < m.num_cells(); ++c) same_cells = again.mesh.cell(c) == m.cell(c);
  EXPECT_TRUE(same_cells) << "not deterministic";
}

// The patch test: a linear displacement prescribed on the whole boundary; the largest error
// at the vertices relative to the field's largest value.
double patch_dirichlet(const Mesh3D& mesh) {
  const LinearCase exact;
  ElasticityProblem3D p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{210.0, 0.3}, PlaneModel::strain);
  p.dirichlet.push_back({mesh.boundary_faces(), exact, {true, true, true}, "all"});
  const Eigen::VectorXd u = test::solve(assemble(p));
  double err = 0.0, ref = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    err = std::max(err, (u.segment<3>(3 * v) - exact(mesh.vertex(v))).cwiseAbs().maxCoeff());
    ref = std::max(ref, exact(mesh.vertex(v)).cwiseAbs().maxCoeff());
  }
  return err / ref;
}

// The cells that have vertex v.
std::vector<int> cells_at(const Mesh3D& mesh, int v) {
  std::vector<int> out;
  for (int c = 0; c < mesh.num_cells(); ++c)
    if (std::binary_search(mesh.cell_vertices(c).begin(), mesh.cell_vertices(c).end(), v)) out.push_back(c);
  return out;
}

int vertex_at(const Mesh3D& mesh, const Vec3& p) {
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if ((mesh.vertex(v) - p).norm() <= 1e-12) return v;
  return -1;
}

// The distance from p to the polygon of face f, and the solid angle the face subtends at p
// (signed: positive when p is on the inner side of the face of `cell`).
double distance_to_face(const Mesh3D& mesh, int f, const Vec3& p) {
  const auto& loop = mesh.face(f).vertices;
  const Vec3 n = mesh.face_normal(f);
  const Vec3 c = mesh.face_centroid(f);
  const Vec3 u = (mesh.vertex(loop[0]) - c).normalized(), v = n.cross(u);
  const Vec3 q = p - c;
  bool inside = false;
  double edge = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
    const Vec3 a = mesh.vertex(loop[j]) - c, b = mesh.vertex(loop[i]) - c;
    const double ay = a.dot(v), by = b.dot(v), ax = a.dot(u), bx = b.dot(u);
    if ((ay > q.dot(v)) != (by > q.dot(v)) && q.dot(u) < ax + (q.dot(v) - ay) / (by - ay) * (bx - ax)) inside = !inside;
    const Vec3 d = b - a;
    const double t = std::clamp((q - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    edge = std::min(edge, (a + t * d - q).norm());
  }
  return inside ? std::abs(n.dot(q)) : edge;
}

// The number of times the boundary of cell c winds around p (1 inside, 0 outside): its signed
// solid angle over 4 pi, from triangles fanned out of each face's first vertex.
double winding_number(const Mesh3D& mesh, int c, const Vec3& p) {
  double total = 0.0;
  for (const auto& loop : mesh.cell(c))
    for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
      const Vec3 a = mesh.vertex(loop[0]) - p, b = mesh.vertex(loop[i]) - p, d = mesh.vertex(loop[i + 1]) - p;
      const double la = a.norm(), lb = b.norm(), ld = d.norm();
      total += 2.0 * std::atan2(a.dot(b.cross(d)), la * lb * ld + a.dot(b) * ld + a.dot(d) * lb + b.dot(d) * la);
    }
  return total / (4.0 * std::numbers::pi);
}

// Shape measures of some cells of a mesh: the largest diameter^3 / volume, the largest ratio of
// the diameter to the radius of the largest ball around the centroid inside the cell
// (infinite when the centroid is not inside), the most vertices of a face, faces of a cell.
struct Shape {
  double cube_ratio = 0.0;
  double ball_ratio = 0.0;
  int face_vertices = 0;
  int cell_faces = 0;
};

Shape shape_of(const Mesh3D& mesh, const std::vector<int>& cells) {
  Shape s;
  for (int c : cells) {
    const double d = mesh.diameter(c);
    s.cube_ratio = std::max(s.cube_ratio, d * d * d / mesh.volume(c));
    double radius = std::numeric_limits<double>::infinity();
    for (int f : mesh.cell_faces(c)) {
      radius = std::min(radius, distance_to_face(mesh, f, mesh.centroid(c)));
      s.face_vertices = std::max(s.face_vertices, static_cast<int>(mesh.face(f).vertices.size()));
    }
    const bool inside = std::abs(winding_number(mesh, c, mesh.centroid(c)) - 1.0) < 1e-6;
    s.ball_ratio =
        std::max(s.ball_ratio, inside && radius > 0.0 ? d / radius : std::numeric_limits<double>::infinity());
    s.cell_faces = std::max(s.cell_faces, static_cast<int>(mesh.cell_faces(c).size()));
  }
  return s;
}

// Levels of refinement towards vertex v (the cells that have it, each level): every third level
// checked sound; the shape measures of the mesh, then of the cells each level made.
std::vector<Shape> refine_towards(Mesh3D mesh, int v, int levels) {
  std::vector<Shape> shapes{shape_of(mesh, all_cells(mesh))};
  for (int level = 0; level < levels; ++level) {
    const std::vector<int> marked = cells_at(mesh, v);
    RefinedMesh3D r = refine_mesh(mesh, marked);
    if (level % 3 == 2) expect_sound_refinement(mesh, r, marked);
    std::vector<int> children;
    for (int c = 0; c < r.mesh.num_cells(); ++c)
      if (std::binary_search(r.refined.begin(), r.refined.end(), r.parent_cell[static_cast<std::size_t>(c)]))
        children.push_back(c);
    mesh = std::move(r.mesh);
    shapes.push_back(shape_of(mesh, children));
  }
  return shapes;
}

void report(const std::string& name, const std::vector<Shape>& shapes) {
  std::string line = name + ": diameter^3/volume, diameter/ball radius, vertices per face, faces per cell by level:";
  for (const Shape& s : shapes) {
    char buf[96];
    std::snprintf(buf, sizeof buf, " (%.3g, %.3g, %d, %d)", s.cube_ratio, s.ball_ratio, s.face_vertices, s.cell_faces);
    line += buf;
  }
  std::printf("%s\n", line.c_str());
}

Mesh3D gmsh_mesh(const std::string& name) { return read_gmsh3d(test::data_dir() / "gmsh3d" / name); }

}  // namespace

// ---- the split ----------------------------------------------------------------------------

TEST(Refine3DSplit, UniformRefinementOfCubesIsTheFinerCubes) {
  const Box box{-1.0, 1.0, 0.0, 2.0, 0.5, 2.5};
  const Mesh3D coarse = make_cubes(2, box);
  const RefinedMesh3D r = refine_uniformly(coarse);
  expect_sound_refinement(coarse, r, all_cells(coarse));
  const Mesh3D& m = r.mesh;
  ASSERT_EQ(m.num_cells(), 8 * coarse.num_cells());
  EXPECT_EQ(m.num_vertices(), 5 * 5 * 5);
  EXPECT_EQ(r.refined, all_cells(coarse));
  for (int c = 0; c < m.num_cells(); ++c) {
    ASSERT_EQ(m.cell_vertices(c).size(), 8u) << c;
    ASSERT_EQ(m.cell_faces(c).size(), 6u) << c;
    Vec3 lo = m.vertex(m.cell_vertices(c)[0]), hi = lo;
    for (int v : m.cell_vertices(c)) {
      lo = lo.cwiseMin(m.vertex(v));
      hi = hi.cwiseMax(m.vertex(v));
    }
    EXPECT_LE((hi - lo - Vec3(0.5, 0.5, 0.5)).cwiseAbs().maxCoeff(), 1e-15)
        << "cell " << c << " is not a cube of half the side";
    EXPECT_NEAR(m.volume(c), 0.125, 1e-15);
    for (int f : m.cell_faces(c)) EXPECT_EQ(m.face(f).vertices.size(), 4u);
    // a child lies in its parent and holds the parent's corner
    const int p = r.parent_cell[static_cast<std::size_t>(c)];
    const Vec3 centre = m.centroid(c);
    EXPECT_LT((centre - coarse.centroid(p)).cwiseAbs().maxCoeff(), 0.5) << c;
  }
  // the eight children of a parent, in increasing id of their corner
  for (int p = 0; p < coarse.num_cells(); ++p)
    for (int k = 0; k < 8; ++k) {
      const int c = 8 * p + k;
      EXPECT_EQ(r.parent_cell[static_cast<std::size_t>(c)], p);
      EXPECT_TRUE(std::binary_search(m.cell_vertices(c).begin(), m.cell_vertices(c).end(),
                                     coarse.cell_vertices(p)[static_cast<std::size_t>(k)]));
    }
}

TEST(Refine3DSplit, TetrahedraSplitIntoFourHexahedraWithPlanarFaces) {
  const Box box{0.0, 1.0, 0.0, 0.6, 0.0, 0.8};
  const Mesh3D coarse = make_tetrahedra({2, 1, 2}, box);
  const RefinedMesh3D r = refine_uniformly(coarse);
  expect_sound_refinement(coarse, r, all_cells(coarse));
  ASSERT_EQ(r.mesh.num_cells(), 4 * coarse.num_cells());
  for (int c = 0; c < r.mesh.num_cells(); ++c) {
    EXPECT_EQ(r.mesh.cell_vertices(c).size(), 8u) << c;
    EXPECT_EQ(r.mesh.cell_faces(c).size(), 6u) << c;
    EXPECT_NEAR(r.mesh.volume(c), coarse.volume(r.parent_cell[static_cast<std::size_t>(c)]) / 4.0, 1e-14) << c;
  }
}

TEST(Refine3DSplit, VoronoiCellsSplitIntoOneCellPerCorner) {
  const Box box{0.0, 2.0, -1.0, 0.0, 0.0, 1.0};
  const Mesh3D coarse = make_voronoi3d({4, 2, 2}, box);
  const RefinedMesh3D r = refine_uniformly(coarse);
  expect_sound_refinement(coarse, r, all_cells(coarse));
  std::vector<int> children(static_cast<std::size_t>(coarse.num_cells()), 0);
  for (int p : r.parent_cell) ++children[static_cast<std::size_t>(p)];
  for (int p = 0; p < coarse.num_cells(); ++p) {
    // a Voronoi cell of the generator has no vertex inside a side: every vertex is a corner
    EXPECT_EQ(children[static_cast<std::size_t>(p)], static_cast<int>(coarse.cell_vertices(p).size())) << p;
  }
  SCOPED_TRACE("second level");
  const RefinedMesh3D r2 = refine_uniformly(r.mesh);
  expect_sound_refinement(r.mesh, r2, all_cells(r.mesh));
}

TEST(Refine3DSplit, PrismsAndPyramidsOfGmshMeshes) {
  for (const char* name : {"cube_prisms.msh", "hexahedra_pyramids_tetrahedra.msh"}) {
    SCOPED_TRACE(name);
    const Mesh3D coarse = gmsh_mesh(name);
    const RefinedMesh3D r = refine_uniformly(coarse);
    expect_sound_refinement(coarse, r, all_cells(coarse));
    for (int c = 0; c < r.mesh.num_cells(); ++c) {
      const int p = r.parent_cell[static_cast<std::size_t>(c)];
      // one child per corner: 6 for a prism, 5 for a pyramid, 4 for a tetrahedron, 8 for a hexahedron
      EXPECT_EQ(std::count(r.parent_cell.begin(), r.parent_cell.end(), p),
                static_cast<long>(coarse.cell_vertices(p).size()));
    }
    const std::vector<int> marked{0, coarse.num_cells() / 2};
    const RefinedMesh3D local = refine_mesh(coarse, marked);
    expect_sound_refinement(coarse, local, marked);
    EXPECT_LE(patch_dirichlet(local.mesh), 1e-10);
  }
}

TEST(Refine3DSplit, MarkedIdsAreCheckedAndDuplicatesAllowed) {
  const Mesh3D mesh = make_cubes(2);
  const std::vector<int> twice{3, 3, 3};
  const RefinedMesh3D r = refine_mesh(mesh, twice);
  EXPECT_EQ(r.refined, std::vector<int>{3});
  EXPECT_EQ(r.mesh.num_cells(), 7 + 8);
  EXPECT_EQ(r.mesh.num_vertices(), refine_mesh(mesh, std::vector<int>{3}).mesh.num_vertices());
  const std::vector<int> none;
  const RefinedMesh3D same = refine_mesh(mesh, none);
  EXPECT_EQ(same.mesh.num_cells(), mesh.num_cells());
  EXPECT_TRUE(same.mesh.vertices() == mesh.vertices());
  EXPECT_TRUE(same.refined.empty());
  EXPECT_NE(
      test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{8}); }).find("marked cell id 8 is out of range"),
      std::string::npos);
  EXPECT_NE(test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{-1}); }).find("out of range"),
            std::string::npos);
}

// ---- hanging vertices ---------------------------------------------------------------------

TEST(Refine3DHanging, NeighboursOfASplitCubeCarryHangingVertices) {
  const Mesh3D mesh = make_cubes(3);
  const int centre = 13;  // cell (1, 1, 1)
  const std::vector<int> marked{centre};
  const RefinedMesh3D r = refine_mesh(mesh, marked);
  expect_sound_refinement(mesh, r, marked);
  EXPECT_EQ(r.refined, marked);
  const Mesh3D& m = r.mesh;
  ASSERT_EQ(m.num_cells(), 26 + 8);
  // new vertices: 12 edge midpoints, 6 face centres, the centre
  EXPECT_EQ(m.num_vertices(), mesh.num_vertices() + 19);
  const Vec3 mid = mesh.centroid(centre);
  for (int c = 0; c < m.num_cells(); ++c) {
    const int p = r.parent_cell[static_cast<std::size_t>(c)];
    if (p == centre) continue;
    // cells sharing a face (1 axis off), an edge (2) or a corner (3) with the split cube
    const Vec3 off = (mesh.centroid(p) - mid).cwiseAbs() * 3.0;
    const int axes_off = (off.array() > 0.5).count();
    const std::size_t vertices = axes_off == 1 ? 8 + 4 + 1 : axes_off == 2 ? 8 + 1 : 8;
    const std::size_t faces = axes_off == 1 ? 6 - 1 + 4 : 6;
    EXPECT_EQ(m.cell_vertices(c).size(), vertices) << "cell " << c;
    EXPECT_EQ(m.cell_faces(c).size(), faces) << "cell " << c;
  }
  EXPECT_LE(patch_dirichlet(m), 1e-10);
}

TEST(Refine3DHanging, ANeighbourThatWouldCarryTwoHangingVerticesOnASideIsSplitToo) {
  const Mesh3D mesh = make_cubes(2);  // cell 0 = [0, 1/2]^3, cell 1 its neighbour along x
  const RefinedMesh3D r1 = refine_mesh(mesh, std::vector<int>{0});
  // the child of cell 0 at its corner (1/2, 0, 0), on the face shared with cell 1
  const int corner = vertex_at(r1.mesh, Vec3(0.5, 0.0, 0.0));
  ASSERT_GE(corner, 0);
  int child = -1;
  for (int c = 0; c < 8; ++c)
    if (std::binary_search(r1.mesh.cell_vertices(c).begin(), r1.mesh.cell_vertices(c).end(), corner)) child = c;
  ASSERT_GE(child, 0);
  const int neighbour = 8;  // cell 1 of the parent, after the 8 children of cell 0
  ASSERT_EQ(r1.parent_cell[static_cast<std::size_t>(neighbour)], 1);
  // its side from (1/2, 0, 0) to (1/2, 1/2, 0) carries the midpoint (1/2, 1/4, 0)
  EXPECT_GE(vertex_at(r1.mesh, Vec3(0.5, 0.25, 0.0)), 0);
  const std::vector<int> marked{child};
  const RefinedMesh3D r2 = refine_mesh(r1.mesh, marked);
  expect_sound_refinement(r1.mesh, r2, marked);
  EXPECT_EQ(r2.refined, (std::vector<int>{child, neighbour}));
  EXPECT_LE(patch_dirichlet(r2.mesh), 1e-10);
  // without the rule the side would carry (1/2, 1/8, 0) and (1/2, 1/4, 0): both are there, and
  // the neighbour's children have at most one vertex inside each side
  EXPECT_GE(vertex_at(r2.mesh, Vec3(0.5, 0.125, 0.0)), 0);
}

TEST(Refine3DHanging, AtMostOneHangingVertexPerSideRefiningTowardsACorner) {
  Mesh3D mesh = make_cubes(2);
  for (int level = 0; level < 4; ++level) {
    const std::vector<int> marked = cells_at(mesh, 0);
    RefinedMesh3D r = refine_mesh(mesh, marked);
    expect_sound_refinement(mesh, r, marked);
    mesh = std::move(r.mesh);
  }
  EXPECT_LE(patch_dirichlet(mesh), 1e-10);
}

// ---- what follows the refinement ----------------------------------------------------------

TEST(Refine3DFollows, RegionsAndFaceGroupsFollow) {
  Mesh3D mesh = gmsh_mesh("hexahedra_pyramids_tetrahedra.msh");
  ASSERT_FALSE(mesh.face_groups().empty());
  std::vector<int> marked;
  for (int c = 0; c < mesh.num_cells(); c += 3) marked.push_back(c);
  const RefinedMesh3D r = refine_mesh(mesh, marked);
  expect_sound_refinement(mesh, r, marked);
  for (const auto& [name, group] : mesh.face_groups()) {
    double before = 0.0, after = 0.0;
    for (int f : group) before += mesh.face_area(f);
    for (int f : r.mesh.face_group(name)) after += r.mesh.face_area(f);
    EXPECT_NEAR(after, before, 1e-13 * before) << name;
    EXPECT_GT(r.mesh.face_group(name).size(), group.size()) << name;
  }
  for (int c = 0; c < r.mesh.num_cells(); ++c)
    EXPECT_EQ(r.mesh.region(c), mesh.region(r.parent_cell[static_cast<std::size_t>(c)]));
}

TEST(Refine3DFollows, TheSameTopologyAtEveryScale) {
  const Mesh3D base = make_voronoi3d(2);
  const std::vector<int> marked{0, 3, 5};
  const RefinedMesh3D reference = refine_mesh(base, marked);
  for (const int exponent : {-60, 60}) {
    std::vector<Vec3> vertices = base.vertices();
    for (Vec3& p : vertices)
      p = Vec3(std::ldexp(p.x(), exponent), std::ldexp(p.y(), exponent), std::ldexp(p.z(), exponent));
    std::vector<CellFaces> cells;
    for (int c = 0; c < base.num_cells(); ++c) cells.push_back(base.cell(c));
    const Mesh3D scaled(vertices, cells);
    const RefinedMesh3D r = refine_mesh(scaled, marked);
    ASSERT_EQ(r.mesh.num_vertices(), reference.mesh.num_vertices()) << exponent;
    ASSERT_EQ(r.mesh.num_cells(), reference.mesh.num_cells()) << exponent;
    for (int c = 0; c < r.mesh.num_cells(); ++c) EXPECT_EQ(r.mesh.cell(c), reference.mesh.cell(c)) << exponent;
    double err = 0.0;
    for (int v = 0; v < r.mesh.num_vertices(); ++v) {
      const Vec3 p = r.mesh.vertex(v);
      err = std::max(err,
                     (Vec3(std::ldexp(p.x(), -exponent), std::ldexp(p.y(), -exponent), std::ldexp(p.z(), -exponent)) -
                      reference.mesh.vertex(v))
                         .norm());
    }
    EXPECT_LE(err, 1e-14) << exponent;
  }
}

// ---- interior points ----------------------------------------------------------------------

namespace {

// One prism over a plane polygon (counter-clockwise seen from above), from z = 0 to z = 1.
Mesh3D prism_over(const std::vector<std::array<double, 2>>& polygon) {
  const int n = static_cast<int>(polygon.size());
  std::vector<Vec3> vertices;
  for (int level = 0; level < 2; ++level)
    for (const auto& p : polygon) vertices.emplace_back(p[0], p[1], level);
  CellFaces faces;
  std::vector<int> bottom, top;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  for (int i = 0; i < n; ++i) top.push_back(n + i);
  faces.push_back(bottom);
  faces.push_back(top);
  for (int i = 0; i < n; ++i) faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return Mesh3D(vertices, {faces});
}

}  // namespace

TEST(Refine3DStarShaped, ACellWhoseCentroidIsOutsideItsKernelIsSplitAroundTheKernelsCentroid) {
  // an L with long arms: its centroid (1.1, 1.1) is outside its kernel [0, 1]^2
  const Mesh3D mesh = prism_over({{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}});
  ASSERT_GT(mesh.centroid(0).x(), 1.0);
  const RefinedMesh3D r = refine_uniformly(mesh);
  expect_sound_refinement(mesh, r, std::vector<int>{0});
  EXPECT_EQ(r.mesh.num_cells(), 12);
  EXPECT_GE(vertex_at(r.mesh, Vec3(0.5, 0.5, 0.5)), 0) << "the kernel's centroid";
  EXPECT_GE(vertex_at(r.mesh, Vec3(0.5, 0.5, 0.0)), 0) << "the bottom face's kernel's centroid";
  EXPECT_LE(patch_dirichlet(r.mesh), 1e-10);
}

TEST(Refine3DStarShaped, ACellWithAnEmptyKernelIsRefusedByName) {
  const Mesh3D mesh = prism_over({{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}});  // a U
  const std::string message = test::input_error_of([&] { refine_uniformly(mesh); });
  EXPECT_NE(message.find("cell 0 is not star-shaped"), std::string::npos) << message;
  EXPECT_NE(message.find("kernel is empty"), std::string::npos) << message;
}

TEST(Refine3DStarShaped, ACellWhoseFacesDoNotMeetAlongWholeSidesIsRefusedByName) {
  // a box [0, 2] x [0, 1] x [0, 1] under two unit cubes: its top is two squares, so the point
  // (1, 0, 1) is a corner of its top faces but lies inside a side of its front face
  std::vector<Vec3> vertices;
  for (int k = 0; k <= 2; ++k)
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 2; ++i) vertices.emplace_back(i, j, k);
  auto v = [](int i, int j, int k) { return (k * 2 + j) * 3 + i; };
  const CellFaces box{{v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)},
                      {v(2, 0, 0), v(2, 1, 0), v(2, 1, 1), v(2, 0, 1)},
                      {v(0, 0, 0), v(1, 0, 0), v(2, 0, 0), v(2, 0, 1), v(1, 0, 1), v(0, 0, 1)},
                      {v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(2, 1, 1), v(2, 1, 0), v(1, 1, 0)},
                      {v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(2, 1, 0), v(2, 0, 0), v(1, 0, 0)},
                      {v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)},
                      {v(1, 0, 1), v(2, 0, 1), v(2, 1, 1), v(1, 1, 1)}};
  auto cube = [&](int i) {
    return CellFaces{{v(i, 0, 1), v(i, 0, 2), v(i, 1, 2), v(i, 1, 1)},
                     {v(i + 1, 0, 1), v(i + 1, 1, 1), v(i + 1, 1, 2), v(i + 1, 0, 2)},
                     {v(i, 0, 1), v(i + 1, 0, 1), v(i + 1, 0, 2), v(i, 0, 2)},
                     {v(i, 1, 1), v(i, 1, 2), v(i + 1, 1, 2), v(i + 1, 1, 1)},
                     {v(i, 0, 1), v(i, 1, 1), v(i + 1, 1, 1), v(i + 1, 0, 1)},
                     {v(i, 0, 2), v(i + 1, 0, 2), v(i + 1, 1, 2), v(i, 1, 2)}};
  };
  const Mesh3D mesh(vertices, {box, cube(0), cube(1)});
  // a cube on top splits, the box gaining the pieces of its top face
  const RefinedMesh3D r = refine_mesh(mesh, std::vector<int>{1});
  EXPECT_EQ(r.mesh.num_cells(), 2 + 8);
  EXPECT_NEAR(r.mesh.total_volume(), 4.0, 1e-14);
  const std::string message = test::input_error_of([&] { refine_mesh(mesh, std::vector<int>{0}); });
  EXPECT_NE(message.find("cell 0 cannot be split"), std::string::npos) << message;
  EXPECT_NE(message.find("do not meet along whole sides"), std::string::npos) << message;
}

// ---- the shape over ten levels ------------------------------------------------------------

namespace {

// The worst shape of each level stays bounded: no larger over the last five levels than 1.2
// times the worst of the first five (levels 0 to 5), and below the given bounds, as are the
// vertices of a face and the faces of a cell.
void expect_no_degeneration(const std::vector<Shape>& s, double cube_ratio, double ball_ratio, int face_vertices,
                            int cell_faces) {
  ASSERT_EQ(s.size(), 11u);
  double early_cube = 0.0, early_ball = 0.0, late_cube = 0.0, late_ball = 0.0;
  for (std::size_t level = 0; level < s.size(); ++level) {
    (level <= 5 ? early_cube : late_cube) = std::max(level <= 5 ? early_cube : late_cube, s[level].cube_ratio);
    (level <= 5 ? early_ball : late_ball) = std::max(level <= 5 ? early_ball : late_ball, s[level].ball_ratio);
    EXPECT_LE(s[level].cube_ratio, cube_ratio) << "level " << level;
    EXPECT_LE(s[level].ball_ratio, ball_ratio) << "level " << level;
    EXPECT_LE(s[level].face_vertices, face_vertices) << "level " << level;
    EXPECT_LE(s[level].cell_faces, cell_faces) << "level " << level;
  }
  EXPECT_LE(late_cube, 1.2 * early_cube);
  EXPECT_LE(late_ball, 1.2 * early_ball);
}

int nearest_vertex(const Mesh3D& mesh, const Vec3& p) {
  int v = 0;
  for (int i = 1; i < mesh.num_vertices(); ++i)
    if ((mesh.vertex(i) - p).norm() < (mesh.vertex(v) - p).norm()) v = i;
  return v;
}

}  // namespace

TEST(Refine3DShape, CubesStayCubesOverTenLevels) {
  const std::vector<Shape> s = refine_towards(make_cubes(2), 0, 10);
  report("cubes", s);
  for (const Shape& x : s) {
    EXPECT_NEAR(x.cube_ratio, 3.0 * std::sqrt(3.0), 1e-9);
    EXPECT_NEAR(x.ball_ratio, 2.0 * std::sqrt(3.0), 1e-9);
  }
  expect_no_degeneration(s, 5.3, 3.5, 5, 9);
}

TEST(Refine3DShape, TetrahedraDoNotDegenerateOverTenLevels) {
  const Mesh3D mesh = make_tetrahedra(2);
  const std::vector<Shape> corner = refine_towards(mesh, 0, 10);
  report("tetrahedra towards a corner", corner);
  expect_no_degeneration(corner, 60.0, 12.0, 5, 14);
  const std::vector<Shape> inside = refine_towards(mesh, nearest_vertex(mesh, Vec3(0.5, 0.5, 0.5)), 10);
  report("tetrahedra towards the centre", inside);
  expect_no_degeneration(inside, 60.0, 12.0, 5, 14);
}

TEST(Refine3DShape, VoronoiCellsDoNotDegenerateOverTenLevels) {
  const Mesh3D mesh = make_voronoi3d(3);
  for (const Vec3& target : {Vec3(0.0, 0.0, 0.0), Vec3(0.5, 0.5, 0.5), Vec3(0.3, 0.6, 0.4)}) {
    const std::vector<Shape> s = refine_towards(mesh, nearest_vertex(mesh, target), 10);
    report("voronoi towards a vertex", s);
    expect_no_degeneration(s, 40.0, 300.0, 8, 24);
  }
}

// ---- the prolongation and the patch test --------------------------------------------------

TEST(Refine3DProlongate, InterpolatesComponentwiseAndChecksTheSize) {
  const Mesh3D mesh = make_voronoi3d({3, 2, 2});
  const RefinedMesh3D r = refine_mesh(mesh, std::vector<int>{1, 4, 7});
  const LinearCase field;
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<3>(3 * v) = field(mesh.vertex(v));
  const Eigen::VectorXd uf = prolongate(r, u);
  ASSERT_EQ(uf.size(), 3 * r.mesh.num_vertices());
  for (int v = 0; v < r.mesh.num_vertices(); ++v)
    EXPECT_LE((uf.segment<3>(3 * v) - field(r.mesh.vertex(v))).norm(), 1e-13) << "vertex " << v;
  for (int v = 0; v < mesh.num_vertices(); ++v) EXPECT_EQ(uf.segment<3>(3 * v), u.segment<3>(3 * v));
  const std::string message =
      test::input_error_of([&] { prolongate(r, Eigen::VectorXd::Zero(2 * mesh.num_vertices())); });
  EXPECT_NE(message.find("needs " + std::to_string(3 * mesh.num_vertices())), std::string::npos) << message;
}

TEST(Refine3DPatch, RefinedMeshesPassThePatchTest) {
  {
    SCOPED_TRACE("cubes");
    const Mesh3D mesh = make_cubes({3, 2, 2}, Box{-1.0, 1.0, 0.0, 1.0, 0.0, 0.5});
    const RefinedMesh3D r1 = refine_mesh(mesh, std::vector<int>{0, 4});
    const RefinedMesh3D r2 = refine_mesh(r1.mesh, std::vector<int>{1, 3, 10});
    expect_sound_refinement(r1.mesh, r2, std::vector<int>{1, 3, 10});
    EXPECT_LE(patch_dirichlet(r1.mesh), 1e-10);
    EXPECT_LE(patch_dirichlet(r2.mesh), 1e-10);
  }
  {
    SCOPED_TRACE("voronoi");
    const Mesh3D mesh = make_voronoi3d({3, 2, 2}, Box{-1.0, 1.0, 0.0, 1.0, 0.0, 0.5});
    std::vector<int> marked1{0, 5, 9}, marked2;
    const RefinedMesh3D r1 = refine_mesh(mesh, marked1);
    for (int c = 0; c < r1.mesh.num_cells(); c += 5) marked2.push_back(c);
    const RefinedMesh3D r2 = refine_mesh(r1.mesh, marked2);
    expect_sound_refinement(mesh, r1, marked1);
    expect_sound_refinement(r1.mesh, r2, marked2);
    EXPECT_LE(patch_dirichlet(r1.mesh), 1e-10);
    EXPECT_LE(patch_dirichlet(r2.mesh), 1e-10);
  }
}
