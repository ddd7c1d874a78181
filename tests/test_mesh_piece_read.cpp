// A process's piece of a Gmsh file's mesh read without making the whole mesh
// (read_gmsh_piece, read_gmsh3d_piece; hemivem/mesh/mesh_piece.hpp) is the piece cut from the
// whole mesh (piece_cells_around, cut_mesh_piece) by the same rule, to the bit; a file the
// whole reader refuses is refused; and the problem a scene builds on it (read_problem_piece)
// poses the share of the whole problem.
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/bodies.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/scene_pieces.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "gmsh_squares.hpp"
#include "piece_parts.hpp"
#include "posed_share_checks.hpp"
#include "test_support.hpp"
#include "thread_rows.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {

std::vector<int> facet_vertices(const Mesh& mesh, int e) { return {mesh.edge(e).v0, mesh.edge(e).v1}; }
std::vector<int> facet_vertices(const Mesh3D& mesh, int f) { return mesh.face(f).vertices; }
std::vector<int> first_facet(const Mesh& mesh, int c) { return {mesh.element_edges(c)[0]}; }
std::vector<int> first_facet(const Mesh3D& mesh, int c) { return {mesh.cell_faces(c)[0]}; }
bool on_boundary(const Mesh& mesh, int e) { return mesh.edge(e).right < 0; }
bool on_boundary(const Mesh3D& mesh, int f) { return mesh.face(f).outer < 0; }
int num_cells_of(const Mesh& mesh) { return mesh.num_elements(); }
int num_cells_of(const Mesh3D& mesh) { return mesh.num_cells(); }
const std::map<std::string, std::vector<int>>& groups_of(const Mesh& mesh) { return mesh.edge_groups(); }
const std::map<std::string, std::vector<int>>& groups_of(const Mesh3D& mesh) { return mesh.face_groups(); }
/// A cell's vertex loops in its order, each from its smallest vertex.
std::vector<std::vector<int>> cell_loops(const Mesh& mesh, int e) { return {{mesh.element(e).begin(), mesh.element(e).end()}}; }
std::vector<std::vector<int>> cell_loops(const Mesh3D& mesh, int c) {
  std::vector<std::vector<int>> loops = mesh.cell(c);  // each from its smallest vertex
  for (auto& l : loops) std::rotate(l.begin(), std::min_element(l.begin(), l.end()), l.end());
  return loops;
}
int cell_size(const Mesh& mesh, int e) { return mesh.element_size(e); }
int cell_size(const Mesh3D& mesh, int c) { return static_cast<int>(mesh.cell_vertices(c).size()); }
double measure(const Mesh& mesh, int e) { return mesh.area(e); }
double measure(const Mesh3D& mesh, int c) { return mesh.volume(c); }

/// Each group's facets by their sorted vertices.
template <class M>
std::map<std::string, std::set<std::vector<int>>> group_facets(const M& mesh) {
  std::map<std::string, std::set<std::vector<int>>> out;
  for (const auto& [name, facets] : groups_of(mesh)) {
    auto& held = out[name];
    for (int f : facets) {
      std::vector<int> v = facet_vertices(mesh, f);
      std::sort(v.begin(), v.end());
      held.insert(v);
    }
  }
  return out;
}

/// The piece of `whole` process `rank` of `size` keeps by the rule of MeshPieceRead, cut from
/// the whole mesh: its cells. Given the facets `picked` (of a BoundaryPick), those in place of the
/// boundary's and the groups'.
template <class M>
std::vector<int> cut_rule_cells(const M& whole, int rank, int size, const std::vector<int>* picked = nullptr) {
  const std::vector<int> order = hilbert_vertex_order(whole);
  const auto [first, end] = vertex_share(whole.num_vertices(), rank, size);
  const std::vector<char> owned = VertexShare{first, end, order}.mask(whole.num_vertices());
  std::vector<int> facets;
  const int num_facets = static_cast<int>(whole.num_facets());
  if (picked) facets = *picked;
  for (int f = 0; f < num_facets && !picked; ++f)
    if (on_boundary(whole, f)) facets.push_back(f);
  for (const auto& [name, group] : groups_of(whole))
    if (!picked) facets.insert(facets.end(), group.begin(), group.end());
  std::set<int> regions;
  for (int c = 0; c < num_cells_of(whole); ++c)
    if (regions.insert(whole.region(c)).second) facets.push_back(first_facet(whole, c)[0]);
  return piece_cells_around(whole, owned, facets);
}

/// Every process's piece of `size` read from the file is the piece cut from the whole mesh:
/// the same cells in the whole's order, each with the whole's loops, volume and region, every
/// vertex, the groups' facets it holds, the share along the whole mesh's Hilbert order; and
/// some piece is smaller than the whole when `smaller`. Given `picked`, the piece is cut with
/// those facets of the whole in place of the boundary's and the groups' (MeshPieceRead::picked).
/// The number of cells of the pieces together into `held` when given.
template <class M, class ReadWhole, class ReadPiece>
void expect_read_pieces_are_cut_pieces(const fs::path& file, int size, bool smaller, ReadWhole read_whole,
                                       ReadPiece read_piece, const std::vector<int>* picked = nullptr,
                                       std::size_t* held = nullptr) {
  SCOPED_TRACE(file.filename().string() + " in " + std::to_string(size) + " pieces");
  const M whole = read_whole(file);
  bool some_smaller = false;
  if (held) *held = 0;
  for (int rank = 0; rank < size; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    const MeshPieceRead<M> read = read_piece(file, rank, size);
    const std::vector<int> cells = cut_rule_cells(whole, rank, size, picked);
    EXPECT_EQ(read.picked, picked != nullptr);
    ASSERT_EQ(read.cells, cells);
    if (held) *held += cells.size();
    EXPECT_EQ(read.whole_cells, num_cells_of(whole));
    EXPECT_EQ(read.order, hilbert_vertex_order(whole));
    const auto [first, end] = vertex_share(whole.num_vertices(), rank, size);
    EXPECT_EQ(read.first, first);
    EXPECT_EQ(read.end, end);
    std::vector<int> facet_of;
    const M cut = cut_mesh_piece(whole, cells, &facet_of);
    // the piece's boundary facets inside the whole mesh, by their vertices
    std::set<std::vector<int>> inside, read_inside;
    for (int f = 0; f < static_cast<int>(whole.num_facets()); ++f)
      if (const int g = facet_of[static_cast<std::size_t>(f)]; g >= 0 && !on_boundary(whole, f) && on_boundary(cut, g)) {
        std::vector<int> v = facet_vertices(whole, f);
        std::sort(v.begin(), v.end());
        inside.insert(v);
      }
    for (std::size_t k = 0; k < read.cut_facets.size(); ++k) {
      const int f = read.cut_facets[k];
      ASSERT_TRUE(on_boundary(read.mesh, f)) << "cut facet " << f;
      if (k > 0) ASSERT_LT(read.cut_facets[k - 1], f);
      std::vector<int> v = facet_vertices(read.mesh, f);
      std::sort(v.begin(), v.end());
      read_inside.insert(v);
    }
    EXPECT_EQ(read_inside, inside);
    EXPECT_EQ(inside.empty(), cells.size() == static_cast<std::size_t>(num_cells_of(whole)));
    ASSERT_EQ(read.mesh.num_vertices(), whole.num_vertices());
    ASSERT_EQ(num_cells_of(read.mesh), num_cells_of(cut));
    for (int v = 0; v < whole.num_vertices(); ++v) ASSERT_EQ(read.mesh.vertex(v), whole.vertex(v));
    for (int c = 0; c < num_cells_of(cut); ++c) {
      ASSERT_EQ(cell_loops(read.mesh, c), cell_loops(whole, cells[static_cast<std::size_t>(c)])) << "cell " << c;
      EXPECT_EQ(measure(read.mesh, c), measure(cut, c)) << "cell " << c;
      EXPECT_EQ(read.mesh.centroid(c), cut.centroid(c)) << "cell " << c;
      EXPECT_EQ(read.mesh.region(c), cut.region(c)) << "cell " << c;
    }
    EXPECT_EQ(group_facets(read.mesh), group_facets(cut));
    some_smaller = some_smaller || static_cast<int>(cells.size()) < num_cells_of(whole);
    double corners = 0, squares = 0;
    int largest = 0;
    for (int c = 0; c < num_cells_of(whole); ++c) {
      const int m = cell_size(whole, c);
      corners += m, squares += static_cast<double>(m) * m, largest = std::max(largest, m);
    }
    EXPECT_EQ(read.cell_vertices, corners);
    EXPECT_EQ(read.cell_vertices_squared, squares);
    EXPECT_EQ(read.largest_cell, largest);
  }
  EXPECT_EQ(some_smaller, smaller);
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path path = fs::temp_directory_path() / ("hemivem-mesh-piece-read-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(path) << text;
  return path;
}

/// A solid Gmsh file of cubes n on the box [0, 1] x [0, 0.5] x [0, 1], the cells above z = 0.5
/// region 2, the bottom the face group "bottom".
fs::path cubes_msh(int n) {
  Mesh3D mesh = make_cubes(GridSize3(n, n / 2, n), Box{0, 1, 0, 0.5, 0, 1});
  std::vector<int> regions, bottom;
  for (int c = 0; c < mesh.num_cells(); ++c) regions.push_back(mesh.centroid(c).z() > 0.5 ? 2 : 1);
  mesh.set_regions(regions);
  for (int f : mesh.boundary_faces())
    if (mesh.face_centroid(f).z() == 0.0) bottom.push_back(f);
  mesh.set_face_group("bottom", bottom);
  const fs::path path = write_text("cubes.msh", "");
  write_gmsh3d(mesh, path);
  return path;
}

const auto read_plane = [](const fs::path& p) { return read_gmsh(p); };
const auto read_plane_piece = [](const fs::path& p, int r, int s) { return read_gmsh_piece(p, r, s); };
const auto read_poly = [](const fs::path& p) { return read_poly2d(p).mesh; };
const auto read_poly_piece = [](const fs::path& p, int r, int s) { return read_poly2d_piece(p, r, s); };
const auto read_solid = [](const fs::path& p) { return read_gmsh3d(p); };
const auto read_solid_piece = [](const fs::path& p, int r, int s) { return read_gmsh3d_piece(p, r, s); };

/// The pieces of `size` processes as each receives its own from the first, which reads the file
/// and makes them all (read(path, rows) on threads playing the processes), made once for each
/// file and size: a read_piece(path, rank, size) of expect_read_pieces_are_cut_pieces.
template <class M, class ReadSent>
auto sent_by_first(ReadSent read) {
  auto made = std::make_shared<std::map<std::pair<std::string, int>, std::vector<MeshPieceRead<M>>>>();
  return [read, made](const fs::path& path, int rank, int size) {
    auto& pieces = (*made)[{path.string(), size}];
    if (pieces.empty()) pieces = test::on_threads(size, [&](const test::ThreadRows& rows) { return read(path, rows); });
    return pieces[static_cast<std::size_t>(rank)];
  };
}
const auto sent_plane = sent_by_first<Mesh>([](const fs::path& p, const test::ThreadRows& rows) { return read_gmsh_piece(p, rows); });
const auto sent_poly = sent_by_first<Mesh>([](const fs::path& p, const test::ThreadRows& rows) { return read_poly2d_piece(p, rows); });
const auto sent_solid =
    sent_by_first<Mesh3D>([](const fs::path& p, const test::ThreadRows& rows) { return read_gmsh3d_piece(p, rows); });

/// The boundary facets of `mesh` whose every vertex lies on its lowest line or plane (least y in
/// the plane, least z in a solid), but for those of `cut` (a piece's, where it meets the rest).
template <class M>
std::vector<int> lowest_facets(const M& mesh, std::span<const int> cut = {}) {
  const auto height = [&](int v) { return mesh.vertex(v)(mesh.vertex(v).size() - 1); };
  double lowest = height(0);
  for (int v = 0; v < mesh.num_vertices(); ++v) lowest = std::min(lowest, height(v));
  std::vector<int> out;
  for (int f = 0; f < static_cast<int>(mesh.num_facets()); ++f) {
    if (!on_boundary(mesh, f) || std::binary_search(cut.begin(), cut.end(), f)) continue;
    const std::vector<int> vs = facet_vertices(mesh, f);
    if (std::all_of(vs.begin(), vs.end(), [&](int v) { return height(v) == lowest; })) out.push_back(f);
  }
  return out;
}

/// A BoundaryPick of the lowest facets (lowest_facets) that counts its calls into `calls` and
/// expects the piece it is given to hold every boundary facet of `whole` (by their vertices) and
/// no other of its own, and fewer cells than the whole when `fewer`.
template <class M>
BoundaryPick<M> lowest_pick(std::shared_ptr<const M> whole, std::shared_ptr<std::atomic<int>> calls, bool fewer) {
  return [whole, calls, fewer](MeshPieceRead<M>&& sides) {
    ++*calls;
    std::set<std::vector<int>> boundary, held;
    for (int f = 0; f < static_cast<int>(whole->num_facets()); ++f)
      if (on_boundary(*whole, f)) boundary.insert(facet_keys(*whole, std::vector<int>{f})[0]);
    for (int f = 0; f < static_cast<int>(sides.mesh.num_facets()); ++f)
      if (on_boundary(sides.mesh, f) && !std::binary_search(sides.cut_facets.begin(), sides.cut_facets.end(), f))
        held.insert(facet_keys(sides.mesh, std::vector<int>{f})[0]);
    EXPECT_EQ(held, boundary);
    EXPECT_EQ(static_cast<int>(sides.cells.size()) < num_cells_of(*whole), fewer);
    EXPECT_EQ(sides.mesh.num_vertices(), whole->num_vertices());
    return facet_keys(sides.mesh, lowest_facets(sides.mesh, sides.cut_facets));
  };
}

/// The pieces the first process makes of a generated mesh and sends (make(rows, pick) on threads
/// playing 1, 2 and 3 processes), `read_whole(name)` the whole mesh: without a pick, each the
/// piece cut from the whole; given a pick of the lowest facets (lowest_pick), called once, each
/// the piece cut with those facets in place of the boundary's, and together fewer cells from two
/// processes on.
template <class M, class ReadWhole, class Make>
void expect_generated_pieces_sent_picked(const fs::path& name, ReadWhole read_whole, Make make) {
  const auto whole = std::make_shared<const M>(read_whole(name));
  const std::vector<int> lowest = lowest_facets(*whole);
  ASSERT_FALSE(lowest.empty());
  for (int size : {1, 2, 3}) {
    const auto calls = std::make_shared<std::atomic<int>>(0);
    const BoundaryPick<M> pick = lowest_pick<M>(whole, calls, true);
    const auto plain = sent_by_first<M>([&](const fs::path&, const test::ThreadRows& rows) { return make(rows, BoundaryPick<M>{}); });
    const auto picked = sent_by_first<M>([&](const fs::path&, const test::ThreadRows& rows) { return make(rows, pick); });
    std::size_t without = 0, with = 0;
    expect_read_pieces_are_cut_pieces<M>(name, size, size > 1, read_whole, plain, nullptr, &without);
    expect_read_pieces_are_cut_pieces<M>(name, size, size > 1, read_whole, picked, &lowest, &with);
    EXPECT_EQ(calls->load(), 1) << size << " pieces";
    if (size > 1) EXPECT_LT(with, without) << size << " pieces";
  }
}

/// Every file of `folder` ending in `ext`, which `read_whole` refuses, is refused by one of two
/// processes' `read_piece` at least with the same message, and by both unless it is a defect of
/// the cells (a MeshError, which only the pieces holding it see). The number of such files.
template <class ReadWhole, class ReadPiece>
int expect_malformed_files_refused_by_pieces(const fs::path& folder, const std::string& ext, ReadWhole read_whole,
                                             ReadPiece read_piece) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ext) continue;
    SCOPED_TRACE(entry.path().filename().string());
    ++files;
    std::string whole;
    bool cells = false;
    try {
      read_whole(entry.path());
      ADD_FAILURE() << "read whole";
    } catch (const MeshError& e) {
      whole = e.what(), cells = true;
    } catch (const InputError& e) {
      whole = e.what();
    }
    int refused = 0;
    for (int rank = 0; rank < 2; ++rank) {
      try {
        read_piece(entry.path(), rank);
        EXPECT_TRUE(cells) << "rank " << rank << " read it";
      } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()), whole) << "rank " << rank;
        ++refused;
      }
    }
    EXPECT_GE(refused, 1);
  }
  return files;
}

}  // namespace

// each process's piece, read by itself or sent by the first process, which reads the file alone
TEST(MeshPieceRead, APlaneFilesPiecesAreThePiecesCutFromTheWholeMesh) {
  const fs::path squares = write_text("squares.msh", test::squares_msh(12, 9));
  for (const auto& read_piece : {std::function(read_plane_piece), std::function(sent_plane)}) {
    for (int size : {1, 2, 3})
      expect_read_pieces_are_cut_pieces<Mesh>(squares, size, size > 1, read_plane, read_piece);
    for (const char* file : {"two_regions.msh", "unit_square_triangles.msh", "unit_square_quads.msh"})
      expect_read_pieces_are_cut_pieces<Mesh>(test::data_dir() / "gmsh" / file, 2, false, read_plane, read_piece);
  }
  fs::remove(squares);
}

TEST(MeshPieceRead, APoly2dFilesPiecesAreThePiecesCutFromTheWholeMesh) {
  for (const auto& read_piece : {std::function(read_poly_piece), std::function(sent_poly)})
    for (const char* file : {"sutton-voronoi-merged.poly2d", "graded-block.poly2d"})
      for (int size : {1, 2, 3})
        expect_read_pieces_are_cut_pieces<Mesh>(test::scenes_dir() / "meshes" / file, size, size > 1, read_poly,
                                                read_piece);
}

// a .poly2d file the whole reader refuses, every process refuses with the same message, or a
// defect of its elements, the processes whose pieces hold it (one at least)
TEST(MeshPieceRead, APoly2dFileTheWholeReaderRefusesIsRefusedByThePieces) {
  EXPECT_GE(expect_malformed_files_refused_by_pieces(test::data_dir() / "malformed", ".poly2d",
                                                     [](const fs::path& p) { (void)read_poly2d(p); },
                                                     [](const fs::path& p, int r) { (void)read_poly2d_piece(p, r, 2); }),
            25);
}

// a Voronoi mesh's piece, made from its cells' vertex lists without the whole mesh by each
// process or by the first (the Lloyd iterations split among the processes) and sent, is the piece
// cut from make_voronoi's mesh, on a unit-scale rectangle and on one rescaled to unit scale;
// given a pick, the first's pieces hold of the boundary the picked facets' cells alone
TEST(MeshPieceRead, AVoronoiMeshsPiecesAreThePiecesCutFromTheWholeMesh) {
  for (const Rectangle& d : {Rectangle{0.0, 1.0, 0.0, 1.0}, Rectangle{-3e4, 5e4, 0.0, 2e4}}) {
    const auto whole = [&](const fs::path&) { return make_voronoi(GridSize(16, 12), d); };
    const auto piece = [&](const fs::path&, int r, int s) { return make_voronoi_piece(GridSize(16, 12), d, {}, r, s); };
    for (int size : {1, 2, 3}) expect_read_pieces_are_cut_pieces<Mesh>("voronoi", size, size > 1, whole, piece);
    expect_generated_pieces_sent_picked<Mesh>("voronoi", whole, [&](const test::ThreadRows& rows, const BoundaryPick<Mesh>& pick) {
      return make_voronoi_piece(GridSize(16, 12), d, rows, {}, {}, pick);
    });
  }
  for (const Box& b : {Box{0.0, 1.0, 0.0, 0.5, 0.0, 1.0}, Box{-3e4, 5e4, 0.0, 2e4, 1e4, 3e4}}) {
    const GridSize3 n(6, 4, 5);
    const auto whole = [&](const fs::path&) { return make_voronoi3d(n, b); };
    const auto piece = [&](const fs::path&, int r, int s) { return make_voronoi3d_piece(n, b, {}, r, s); };
    for (int size : {1, 2, 3}) expect_read_pieces_are_cut_pieces<Mesh3D>("voronoi3d", size, size > 1, whole, piece);
    expect_generated_pieces_sent_picked<Mesh3D>("voronoi3d", whole, [&](const test::ThreadRows& rows, const BoundaryPick<Mesh3D>& pick) {
      return make_voronoi3d_piece(n, b, rows, {}, {}, pick);
    });
  }
}

// a polygon's mesh's piece, made from its cells' lists without the whole mesh, is the piece cut
// from make_mesh's mesh, its edge groups the whole's; on an L-shaped polygon and on it shrunk
// below the range where CGAL meshes it as it is (made in coordinates scaled back exactly)
TEST(MeshPieceRead, APolygonsMeshsPiecesAreThePiecesCutFromTheWholeMesh) {
  const std::vector<Vec2> bracket{{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.4}, {0.4, 0.4}, {0.4, 1.0}, {0.0, 1.0}};
  for (const double scale : {1.0, 0x1p-120}) {
    PolygonDomain d;
    for (const Vec2& p : bracket) d.corners.push_back(scale * p);
    for (const char* generator : {"triangles", "voronoi"}) {
      SCOPED_TRACE(std::string(generator) + " at scale " + std::to_string(scale));
      const auto whole = [&](const fs::path&) { return make_mesh(generator, 10, d, 3); };
      const auto piece = [&](const fs::path&, int r, int s) { return make_mesh_piece(generator, 10, d, 3, r, s); };
      for (int size : {1, 2, 3}) expect_read_pieces_are_cut_pieces<Mesh>(generator, size, size > 1, whole, piece);
      expect_generated_pieces_sent_picked<Mesh>(generator, whole, [&](const test::ThreadRows& rows, const BoundaryPick<Mesh>& pick) {
        return make_mesh_piece(generator, 10, d, 3, rows, {}, pick);
      });
    }
  }
  PolygonDomain d;
  for (const Vec2& p : bracket) d.corners.push_back(p);
  for (const char* generator : {"squares", "hexagons"}) {  // the whole mesh's errors
    const std::string whole = test::input_error_of([&] { (void)make_mesh(generator, 10, d); });
    ASSERT_FALSE(whole.empty()) << generator;
    EXPECT_EQ(test::input_error_of([&] { (void)make_mesh_piece(generator, 10, d, 1, 0, 2); }), whole);
    // the first process meets it, and every other ends saying so
    const std::vector<std::string> sent = test::on_threads(3, [&](const test::ThreadRows& rows) {
      return test::input_error_of([&] { (void)make_mesh_piece(generator, 10, d, 1, rows); });
    });
    EXPECT_EQ(sent[0], whole);
    for (std::size_t rank = 1; rank < sent.size(); ++rank) EXPECT_EQ(sent[rank], "process 0 stopped: " + whole) << rank;
  }
}

TEST(MeshPieceRead, ASolidFilesPiecesAreThePiecesCutFromTheWholeMesh) {
  const fs::path cubes = cubes_msh(8);
  for (const auto& read_piece : {std::function(read_solid_piece), std::function(sent_solid)}) {
    for (int size : {1, 2, 3}) expect_read_pieces_are_cut_pieces<Mesh3D>(cubes, size, size > 1, read_solid, read_piece);
    // hexahedra, pyramids and tetrahedra; two bodies in one file (each body's kept cells joined)
    for (const char* file : {"hexahedra_pyramids_tetrahedra.msh", "two_boxes_tetrahedra.msh"})
      expect_read_pieces_are_cut_pieces<Mesh3D>(test::data_dir() / "gmsh3d" / file, 3, true, read_solid, read_piece);
    expect_read_pieces_are_cut_pieces<Mesh3D>(test::data_dir() / "gmsh3d" / "cube_prisms.msh", 3, false, read_solid,
                                              read_piece);
  }
  fs::remove(cubes);
}

/// What each of `size` processes meets when the first reads `path` and sends each its piece
/// (read(path, rows)): the InputError's message, empty where it receives its piece.
template <class Read>
std::vector<std::string> errors_sent_by_first(const fs::path& path, int size, Read read) {
  return test::on_threads(size, [&](const test::ThreadRows& rows) {
    return test::input_error_of([&] { (void)read(path, rows); });
  });
}

// given a pick of its boundary, a mesh of one body's pieces, read by each process or sent by the
// first, hold of the boundary and the groups the cells of the facets it picks alone, the piece
// of every boundary facet made once to pick them on; a mesh of two bodies' are made as without
// a pick, which is never called
TEST(MeshPieceRead, APieceOfOneBodyHoldsOfItsBoundaryThePickedFacetsAlone) {
  const fs::path squares = write_text("picked-squares.msh", test::squares_msh(12, 9));
  const fs::path cubes = cubes_msh(8);
  const fs::path two_bodies = write_text("picked-two-bodies.msh", "");  // two blocks of cubes apart
  {
    const Mesh3D a = make_cubes(GridSize3(4, 2, 3), Box{0, 1, 0, 0.5, 0, 1});
    const Mesh3D b = make_cubes(GridSize3(3, 2, 2), Box{2, 3, 0, 0.5, 0.5, 1});
    write_gmsh3d(join_meshes({&a, &b}, {"a", "b"}).mesh, two_bodies);
  }
  const fs::path poly = test::scenes_dir() / "meshes" / "graded-block.poly2d";
  // the pieces read by each process or sent by the first with `pick`, for each number of them
  const auto expect_picked = [&]<class M>(const fs::path& file, const auto& read_whole, const auto& read_own,
                                          const auto& read_sent, bool one_body) {
    const auto whole = std::make_shared<const M>(read_whole(file));
    const std::vector<int> lowest = lowest_facets(*whole);
    ASSERT_FALSE(lowest.empty());
    for (int size : {1, 2, 3}) {
      const auto calls = std::make_shared<std::atomic<int>>(0);
      const BoundaryPick<M> pick = lowest_pick<M>(whole, calls, true);
      const auto own = [&](const fs::path& p, int r, int s) { return read_own(p, r, s, pick); };
      const auto sent = sent_by_first<M>([&](const fs::path& p, const test::ThreadRows& rows) { return read_sent(p, rows, pick); });
      const std::vector<int>* picked = one_body ? &lowest : nullptr;
      std::size_t without = 0, with = 0;
      const bool smaller = one_body && size > 1;  // the two small blocks' pieces hold every cell
      expect_read_pieces_are_cut_pieces<M>(
          file, size, smaller, read_whole, [&](const fs::path& p, int r, int s) { return read_own(p, r, s, BoundaryPick<M>{}); },
          nullptr, &without);
      using Read = std::function<MeshPieceRead<M>(const fs::path&, int, int)>;
      for (const auto& [read, readings] : {std::pair{Read(own), size}, std::pair{Read(sent), 1}}) {
        calls->store(0);
        expect_read_pieces_are_cut_pieces<M>(file, size, smaller, read_whole, read, picked, &with);
        if (smaller) EXPECT_LT(with, without) << size << " pieces";
        else EXPECT_EQ(with, without) << size << " pieces";
        // once for each piece a process reads by itself, once for all that the first sends
        EXPECT_EQ(calls->load(), one_body ? readings : 0);
      }
    }
  };
  expect_picked.operator()<Mesh>(squares, read_plane, [](const fs::path& p, int r, int s, const BoundaryPick<Mesh>& pick) {
    return read_gmsh_piece(p, r, s, {}, pick);
  }, [](const fs::path& p, const test::ThreadRows& rows, const BoundaryPick<Mesh>& pick) {
    return read_gmsh_piece(p, rows, {}, pick);
  }, true);
  expect_picked.operator()<Mesh>(poly, read_poly, [](const fs::path& p, int r, int s, const BoundaryPick<Mesh>& pick) {
    return read_poly2d_piece(p, r, s, {}, pick);
  }, [](const fs::path& p, const test::ThreadRows& rows, const BoundaryPick<Mesh>& pick) {
    return read_poly2d_piece(p, rows, {}, pick);
  }, true);
  const auto solid_own = [](const fs::path& p, int r, int s, const BoundaryPick<Mesh3D>& pick) {
    return read_gmsh3d_piece(p, r, s, {}, pick);
  };
  const auto solid_sent = [](const fs::path& p, const test::ThreadRows& rows, const BoundaryPick<Mesh3D>& pick) {
    return read_gmsh3d_piece(p, rows, {}, pick);
  };
  expect_picked.operator()<Mesh3D>(cubes, read_solid, solid_own, solid_sent, true);
  expect_picked.operator()<Mesh3D>(two_bodies, read_solid, solid_own, solid_sent, false);
  fs::remove(squares);
  fs::remove(cubes);
  fs::remove(two_bodies);
}

// a pick that refuses ends every process with its error, the first with it, the others saying
// that process 0 stopped with it; a defect of the cells is named as without a pick
TEST(MeshPieceRead, APickThatRefusesEndsEveryProcess) {
  const fs::path squares = write_text("pick-refuses.msh", test::squares_msh(12, 9));
  const BoundaryPick<Mesh> refuses = [](MeshPieceRead<Mesh>&&) -> FacetKeys {
    throw InputError("contact.side: selects no boundary edge of the mesh");
  };
  const std::string message = test::input_error_of([&] { throw InputError("contact.side: selects no boundary edge of the mesh"); });
  EXPECT_EQ(test::input_error_of([&] { (void)read_gmsh_piece(squares, 1, 3, {}, refuses); }), message);
  const std::vector<std::string> met = errors_sent_by_first(
      squares, 3, [&](const fs::path& p, const test::ThreadRows& rows) { return read_gmsh_piece(p, rows, {}, refuses); });
  EXPECT_EQ(met[0], message);
  for (std::size_t rank = 1; rank < met.size(); ++rank) EXPECT_EQ(met[rank], "process 0 stopped: " + message) << "rank " << rank;
  // a defect inside the mesh, and one on its boundary (whose piece of every boundary facet
  // cannot be made: the pieces then meet it as without a pick)
  const BoundaryPick<Mesh> bottom = [](MeshPieceRead<Mesh>&& sides) {
    return facet_keys(sides.mesh, lowest_facets(sides.mesh, sides.cut_facets));
  };
  for (const auto& [name, text] : {std::pair{"inside", test::squares_msh_repeating_a_vertex(24)},
                                   std::pair{"boundary", test::squares_msh_crossing_on_the_bottom(24)}}) {
    SCOPED_TRACE(name);
    const fs::path defect = write_text(std::string("pick-defect-") + name + ".msh", text);
    const std::string whole = test::input_error_of([&] { (void)read_gmsh(defect); });
    ASSERT_FALSE(whole.empty());
    const std::vector<std::string> ends = errors_sent_by_first(
        defect, 3, [&](const fs::path& p, const test::ThreadRows& rows) { return read_gmsh_piece(p, rows, {}, bottom); });
    EXPECT_EQ(ends[0], whole);
    for (std::size_t rank = 1; rank < ends.size(); ++rank) EXPECT_EQ(ends[rank], "process 0 stopped: " + whole) << "rank " << rank;
    fs::remove(defect);
  }
  fs::remove(squares);
}

// a file the whole reader refuses, or with a defect in one cell, read by the first process alone:
// it refuses it as the whole reader does (a defect of the cells, which the process whose piece
// holds it meets making its mesh, the first names as the whole reader does), and every other
// process ends saying so; none waits
TEST(MeshPieceRead, AFileTheFirstProcessRefusesEndsEveryProcess) {
  const auto plane = [](const fs::path& p, const test::ThreadRows& rows) { return read_gmsh_piece(p, rows); };
  const auto poly = [](const fs::path& p, const test::ThreadRows& rows) { return read_poly2d_piece(p, rows); };
  const auto expect_every_process_ends = [](const std::vector<std::string>& met, const std::string& whole) {
    EXPECT_EQ(met[0], whole);
    for (std::size_t rank = 1; rank < met.size(); ++rank) EXPECT_EQ(met[rank], "process 0 stopped: " + whole) << "rank " << rank;
  };
  int files = 0;
  for (const auto& [folder, ext] : {std::pair{test::data_dir() / "gmsh" / "malformed", ".msh"},
                                    std::pair{test::data_dir() / "malformed", ".poly2d"}})
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() != ext) continue;
      SCOPED_TRACE(entry.path().filename().string());
      const bool gmsh = std::string(ext) == ".msh";
      const std::string whole = test::input_error_of([&] {
        if (gmsh) (void)read_gmsh(entry.path());
        else (void)read_poly2d(entry.path());
      });
      ASSERT_FALSE(whole.empty());
      expect_every_process_ends(gmsh ? errors_sent_by_first(entry.path(), 3, plane)
                                     : errors_sent_by_first(entry.path(), 3, poly),
                                whole);
      ++files;
    }
  EXPECT_GE(files, 35);
  // an element inside a larger mesh repeating a vertex, which only the pieces holding it meet
  // (one of three processes' at least, not all: MeshPieceRead.AFileTheWholeReaderRefuses...);
  // a file that is not there
  const fs::path defect = write_text("defect-first.msh", test::squares_msh_repeating_a_vertex(24));
  for (const fs::path& path : {defect, fs::path(defect.string() + ".missing")}) {
    SCOPED_TRACE(path.filename().string());
    const std::string whole = test::input_error_of([&] { (void)read_gmsh(path); });
    ASSERT_FALSE(whole.empty());
    expect_every_process_ends(errors_sent_by_first(path, 3, plane), whole);
  }
  fs::remove(defect);
}

// a file the whole reader refuses, every process refuses with the same message; a defect of
// the cells, the processes whose pieces hold it (one at least)
TEST(MeshPieceRead, AFileTheWholeReaderRefusesIsRefusedByThePieces) {
  EXPECT_GE(expect_malformed_files_refused_by_pieces(test::data_dir() / "gmsh" / "malformed", ".msh",
                                                     [](const fs::path& p) { (void)read_gmsh(p); },
                                                     [](const fs::path& p, int r) { (void)read_gmsh_piece(p, r, 2); }),
            10);
  // an element inside a larger mesh repeating a vertex: the processes whose pieces hold it
  // refuse it as the whole reader does, the others read theirs
  const fs::path defect = write_text("defect.msh", test::squares_msh_repeating_a_vertex(24));
  const std::string whole = test::input_error_of([&] { (void)read_gmsh(defect); });
  EXPECT_NE(whole.find("Gmsh element"), std::string::npos) << whole;
  int refused = 0;
  for (int rank = 0; rank < 3; ++rank) {
    const std::string error = test::input_error_of([&] { (void)read_gmsh_piece(defect, rank, 3); });
    if (!error.empty()) EXPECT_EQ(error, whole) << "rank " << rank;
    refused += error.empty() ? 0 : 1;
  }
  EXPECT_GE(refused, 1);
  EXPECT_LT(refused, 3);
  fs::remove(defect);
}

/// Expects of the piece `piece` (the cells `cells` of the mesh of `whole`, a scene of one body)
/// that it is one body whose every vertex lies on it (piece_bodies); that its contact
/// parts hold the whole's facets, its supports and loads those of the whole among its cells,
/// each support every vertex it holds of the whole. Whether it holds fewer facets of the
/// supports and loads than the whole.
template <int dim>
bool expect_one_body_piece(const BasicBuiltProblem<dim>& piece, const BasicBuiltProblem<dim>& whole,
                           const test::WholeParts<dim>& parts, const std::vector<int>& cells) {
  test::expect_whole_bodies(piece, whole);
  EXPECT_EQ(BasicRigidMotions<dim>(piece.mesh, make_dof_map(piece.mesh, {})).num_pieces(), 1);
  return parts.expect_held_by(piece, whole.mesh, std::set<int>(cells.begin(), cells.end()), true, true);
}

/// The problem of the scene on each of three processes' pieces (piece_of(rank, size, where):
/// read from its file, or made from its cells' lists) poses the share of the whole problem to
/// the bit; each piece holds every cell around each vertex a support at a point holds, and is a
/// piece of one body (expect_one_body_piece). Returns how many pieces hold fewer facets of the
/// supports and loads than the whole.
template <int dim, class PieceOf>
int expect_problem_pieces_pose_the_whole_share(const Scene& scene, PieceOf piece_of) {
  const auto whole = build_problem<dim>(scene);
  const std::vector<int> order = hilbert_vertex_order(whole->mesh);
  const test::WholeParts<dim> parts(*whole);
  int fewer = 0;
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    PieceOfMesh where;
    const auto piece = piece_of(rank, 3, where);
    const auto [first, end] = vertex_share(whole->mesh.num_vertices(), rank, 3);
    EXPECT_EQ(where.vertices.order, order);
    EXPECT_EQ(where.vertices.first, first);
    EXPECT_EQ(where.vertices.end, end);
    EXPECT_LT(static_cast<int>(where.cells.size()), where.whole_cells);
    const std::set<int> held(where.cells.begin(), where.cells.end());
    for (const auto& d : whole->problem.elasticity.dirichlet)
      for (const int v : d.vertices)
        for (int c = 0; c < num_cells_of(whole->mesh); ++c) {
          const auto loops = cell_loops(whole->mesh, c);
          bool around = false;
          for (const auto& loop : loops) around = around || std::find(loop.begin(), loop.end(), v) != loop.end();
          if (around) EXPECT_TRUE(held.count(c)) << "cell " << c << " around the supported vertex " << v;
        }
    fewer += expect_one_body_piece<dim>(*piece, *whole, parts, where.cells) ? 1 : 0;
    test::expect_same_share(pose_share(piece->problem, order, first, end), pose_share(whole->problem, order, first, end));
  }
  return fewer;
}

/// The problems that make(rows, where) poses on the pieces of processes played by threads, made
/// once: a piece_of of expect_problem_pieces_pose_the_whole_share.
template <int dim, class Make>
auto problem_pieces_on_threads(Make make) {
  using Made = std::pair<std::shared_ptr<BasicBuiltProblem<dim>>, PieceOfMesh>;
  auto made = std::make_shared<std::vector<Made>>();
  return [make, made](int rank, int size, PieceOfMesh& where) {
    if (made->empty())
      *made = test::on_threads(size, [&](const test::ThreadRows& rows) {
        Made piece;
        piece.first = make(rows, piece.second);
        return piece;
      });
    where = (*made)[static_cast<std::size_t>(rank)].second;
    return (*made)[static_cast<std::size_t>(rank)].first;
  };
}

/// What each of three processes played by threads meets posing the problem on its piece
/// (make(rows, where)): the first `whole`, each other "process 0 stopped: <whole>".
template <class Make>
void expect_the_first_stops_every_process(const std::string& whole, Make make) {
  const std::vector<std::string> met = test::on_threads(3, [&](const test::ThreadRows& rows) {
    PieceOfMesh where;
    return test::input_error_of([&] { (void)make(rows, where); });
  });
  EXPECT_EQ(met[0], whole);
  for (std::size_t rank = 1; rank < met.size(); ++rank) EXPECT_EQ(met[rank], "process 0 stopped: " + whole) << "rank " << rank;
}

/// The same of the pieces read from the scene's file, by each process, and sent by the first
/// (which reads the file alone) to three processes played by threads; the number of pieces of
/// either with fewer facets (the same).
template <int dim>
int expect_read_problem_pieces_pose_the_whole_share(const Scene& scene) {
  EXPECT_TRUE(reads_pieces(scene));
  const int fewer = expect_problem_pieces_pose_the_whole_share<dim>(
      scene, [&](int rank, int size, PieceOfMesh& where) { return read_problem_piece<dim>(scene, rank, size, where); });
  const int sent_fewer = expect_problem_pieces_pose_the_whole_share<dim>(
      scene, problem_pieces_on_threads<dim>([&](const test::ThreadRows& rows, PieceOfMesh& where) {
        return read_problem_piece<dim>(scene, rows, where);
      }));
  EXPECT_EQ(sent_fewer, fewer);
  return fewer;
}

TEST(MeshPieceRead, TheProblemOnAPieceReadFromTheFilePosesTheWholeShare) {
  // its supports and load on face groups, its contact on one: each piece holds those among its cells
  EXPECT_GT(expect_read_problem_pieces_pose_the_whole_share<3>(parse_scene(test::scenes_dir() / "gmsh-bracket-3d.toml")), 0);
  const fs::path squares = write_text("squares-scene.msh", test::squares_msh(24, 12));
  Scene plane = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  plane.mesh.file = squares;
  plane.contact->boundary = BoundarySelector{};
  plane.contact->boundary.groups = {"bottom"};
  EXPECT_EQ(expect_read_problem_pieces_pose_the_whole_share<2>(plane), 3);  // its sides clamped, its top pressed
  {
    SCOPED_TRACE("a region box, whose cells some pieces do not hold");
    Scene boxed = plane;
    boxed.material.regions.push_back(SceneRegionMaterial{3, 130.0, 0.3, std::array<double, 4>{0.1, 0.2, 0.6, 0.8}});
    expect_read_problem_pieces_pose_the_whole_share<2>(boxed);
    int without = 0;
    for (int rank = 0; rank < 3; ++rank) {
      PieceOfMesh where;
      const std::vector<int> regions = read_problem_piece<2>(boxed, rank, 3, where)->mesh.regions();
      without += std::count(regions.begin(), regions.end(), 3) == 0 ? 1 : 0;
    }
    EXPECT_GT(without, 0) << "every piece held the box's cells";
  }
  SceneDirichlet inside;  // a support at a vertex inside the body, away from the groups
  inside.boundary.points = {{0.75, 0.25, 0.0}};
  inside.ux = SceneScalar{0.0};
  plane.dirichlet.push_back(inside);
  expect_read_problem_pieces_pose_the_whole_share<2>(plane);
  fs::remove(squares);
  const fs::path cubes = cubes_msh(12);
  Scene solid = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  solid.mesh.file = cubes;
  inside.boundary.points = {{0.25, 0.25, 0.75}};
  solid.dirichlet.push_back(inside);
  EXPECT_EQ(expect_read_problem_pieces_pose_the_whole_share<3>(solid), 3);
  fs::remove(cubes);
}

// a segment picks on a piece the whole mesh's boundary facets the piece holds, never a facet
// where the pieces meet (on pieces sent by the first, it picks the contact before making them)
TEST(MeshPieceRead, ASegmentPicksOnAPieceTheWholeMeshsBoundaryFacetsAlone) {
  // .poly2d files: the top under a cylinder by a segment, along a loading path with friction;
  // sides of the mesh's bounding box
  expect_read_problem_pieces_pose_the_whole_share<2>(parse_scene(test::scenes_dir() / "cattaneo-mindlin.toml"));
  expect_read_problem_pieces_pose_the_whole_share<2>(parse_scene(test::scenes_dir() / "sutton-voronoi.toml"));
  const fs::path squares = write_text("segments.msh", test::squares_msh(24, 24));
  Scene plane = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  plane.mesh.file = squares;
  // a part of the bottom and a line through the body along edges inside it
  plane.contact->boundary = BoundarySelector{};
  plane.contact->boundary.segments = {{0.25, 0.0, 0.75, 0.0}, {0.5, 0.0, 0.5, 1.0}, {0.0, 0.5, 1.0, 0.5}};
  expect_read_problem_pieces_pose_the_whole_share<2>(plane);
  // the line through the body along an edge where the first piece meets the others picks no
  // boundary edge: the whole mesh's error on each piece
  const MeshPieceRead<Mesh> first = read_gmsh_piece(squares, 0, 3);
  ASSERT_FALSE(first.cut_facets.empty());
  const Vec2 a = first.mesh.vertex(first.mesh.edge(first.cut_facets[0]).v0);
  const Vec2 b = first.mesh.vertex(first.mesh.edge(first.cut_facets[0]).v1);
  plane.contact->boundary.segments = {a.x() == b.x() ? std::array<double, 4>{a.x(), 0.0, a.x(), 1.0}
                                                     : std::array<double, 4>{0.0, a.y(), 1.0, a.y()}};
  const std::string whole = test::input_error_of([&] { (void)build_problem<2>(plane); });
  EXPECT_NE(whole.find("selects no boundary edge"), std::string::npos) << whole;
  for (int rank = 0; rank < 3; ++rank) {
    PieceOfMesh where;
    EXPECT_EQ(test::input_error_of([&] { (void)read_problem_piece<2>(plane, rank, 3, where); }), whole) << "rank " << rank;
  }
  // pieces sent by the first: it picks the contact on the cells of the boundary before it makes
  // any piece, so it meets the error there and every other process ends saying so
  expect_the_first_stops_every_process(
      whole, [&](const test::ThreadRows& rows, PieceOfMesh& where) { return read_problem_piece<2>(plane, rows, where); });
  fs::remove(squares);
}

/// The problem of the scene on each of three processes' pieces of its Voronoi mesh (played by
/// threads, which split the Lloyd iterations) poses the share of the whole problem to the bit,
/// each a piece of one body (expect_one_body_piece). Returns how many pieces hold fewer facets
/// of the supports and loads than the whole.
template <int dim>
int expect_voronoi_pieces_pose_the_whole_share(const Scene& scene) {
  EXPECT_TRUE(makes_voronoi_pieces(scene));
  int fewer = 0;
  const auto whole = build_problem<dim>(scene);
  const test::WholeParts<dim> parts(*whole);
  const std::vector<int> order = hilbert_vertex_order(whole->mesh);
  auto made = test::on_threads(3, [&](const test::ThreadRows& rows) {
    auto where = std::make_shared<PieceOfMesh>();
    std::shared_ptr<BasicBuiltProblem<dim>> piece = voronoi_problem_piece<dim>(scene, rows, *where);
    return std::make_pair(piece, where);
  });
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    const auto& [piece, where] = made[static_cast<std::size_t>(rank)];
    const auto [first, end] = vertex_share(whole->mesh.num_vertices(), rank, 3);
    EXPECT_EQ(where->vertices.order, order);
    EXPECT_EQ(where->vertices.first, first);
    EXPECT_EQ(where->vertices.end, end);
    EXPECT_EQ(where->whole_cells, num_cells_of(whole->mesh));
    EXPECT_LT(static_cast<int>(where->cells.size()), where->whole_cells);
    EXPECT_EQ(piece->mesh.vertices(), whole->mesh.vertices());
    fewer += expect_one_body_piece<dim>(*piece, *whole, parts, where->cells) ? 1 : 0;
    test::expect_same_share(pose_share(piece->problem, order, first, end), pose_share(whole->problem, order, first, end));
  }
  return fewer;
}

// Example 4.1 in the plane and in a solid, and a contact part on a segment with supports on
// sides (rollers-pressure.toml)
TEST(MeshPieceRead, TheProblemOnAVoronoiMeshsPiecePosesTheWholeShare) {
  for (const char* name : {"paper-example-4.1-voronoi.toml", "rollers-pressure.toml"}) {
    SCOPED_TRACE(name);
    Scene scene = parse_scene(test::scenes_dir() / name);
    scene.mesh.n = 24;
    scene.mesh.ny.reset();
    EXPECT_EQ(expect_voronoi_pieces_pose_the_whole_share<2>(scene), 3);
  }
  {
    SCOPED_TRACE("a contact along a line through the body, which picks no boundary edge");
    Scene scene = parse_scene(test::scenes_dir() / "rollers-pressure.toml");
    scene.mesh.n = 24;
    scene.mesh.ny.reset();
    scene.contact->boundary = BoundarySelector{};
    scene.contact->boundary.segments = {{0.5, 0.0, 0.5, 1.0}};
    const std::string whole = test::input_error_of([&] { (void)build_problem<2>(scene); });
    EXPECT_NE(whole.find("selects no boundary edge"), std::string::npos) << whole;
    // the first picks the contact before it makes any piece, and every other process ends saying so
    expect_the_first_stops_every_process(
        whole, [&](const test::ThreadRows& rows, PieceOfMesh& where) { return voronoi_problem_piece<2>(scene, rows, where); });
  }
  {
    SCOPED_TRACE("example-4.1-3d.toml on Voronoi cells");
    Scene solid = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
    solid.mesh.generator = "voronoi";
    solid.mesh.n = 10;
    solid.mesh.ny = 5;
    solid.mesh.nz = 10;
    EXPECT_EQ(expect_voronoi_pieces_pose_the_whole_share<3>(solid), 3);
  }
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1-voronoi.toml");
  Scene adaptive = scene;
  adaptive.adapt = SceneAdapt{};
  EXPECT_FALSE(makes_voronoi_pieces(adaptive));
  scene.mesh.polygon = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
  EXPECT_FALSE(makes_voronoi_pieces(scene));  // clipped to a polygon: made whole
  EXPECT_FALSE(makes_voronoi_pieces(parse_scene(test::scenes_dir() / "example-4.1-3d.toml")));  // cubes
  EXPECT_FALSE(makes_voronoi_pieces(parse_scene(test::scenes_dir() / "two-blocks.toml")));
  EXPECT_FALSE(makes_voronoi_pieces(parse_scene(test::scenes_dir() / "paper-example-4.1.toml")));
}

// the L-shaped bracket, its supports, load and contact on the polygon's edge groups, meshed by
// triangles and by Voronoi cells, with a support at a point inside it too; a segment across the
// body along an edge where the first piece meets the others picks no edge, as on the whole mesh
TEST(MeshPieceRead, TheProblemOnAPolygonMeshsPiecePosesTheWholeShare) {
  Scene scene = parse_scene(test::scenes_dir() / "polygon-bracket.toml");
  scene.mesh.n = 14;
  const auto polygon_piece = [&](int rank, int size, PieceOfMesh& where) {
    return polygon_problem_piece(scene, rank, size, where);
  };
  const auto sent_piece = [&](const test::ThreadRows& rows, PieceOfMesh& where) {
    return polygon_problem_piece(scene, rows, where);
  };
  for (const char* generator : {"triangles", "voronoi"}) {
    SCOPED_TRACE(generator);
    scene.mesh.generator = generator;
    ASSERT_TRUE(makes_polygon_pieces(scene));
    const int fewer = expect_problem_pieces_pose_the_whole_share<2>(scene, polygon_piece);
    EXPECT_GT(fewer, 0);
    // made by the first and sent, holding of the boundary the contact's cells alone
    EXPECT_EQ(expect_problem_pieces_pose_the_whole_share<2>(scene, problem_pieces_on_threads<2>(sent_piece)), fewer);
  }
  const PolygonDomain bracket{{{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.4}, {0.4, 0.4}, {0.4, 1.0}, {0.0, 1.0}}};
  const auto seed = static_cast<std::uint64_t>(scene.mesh.seed);
  const Mesh cells = make_mesh(scene.mesh.generator, scene.mesh.n, bracket, seed);
  int nearest = 0;  // the vertex nearest (0.7, 0.2), inside the foot
  for (int v = 0; v < cells.num_vertices(); ++v)
    if ((cells.vertex(v) - Vec2(0.7, 0.2)).norm() < (cells.vertex(nearest) - Vec2(0.7, 0.2)).norm()) nearest = v;
  SceneDirichlet inside;
  inside.boundary.points = {{cells.vertex(nearest).x(), cells.vertex(nearest).y(), 0.0}};
  inside.uy = SceneScalar{0.0};
  scene.dirichlet.push_back(inside);
  expect_problem_pieces_pose_the_whole_share<2>(scene, polygon_piece);
  expect_problem_pieces_pose_the_whole_share<2>(scene, problem_pieces_on_threads<2>(sent_piece));
  scene.dirichlet.clear();
  const MeshPieceRead<Mesh> first = make_mesh_piece(scene.mesh.generator, scene.mesh.n, bracket, seed, 0, 3);
  ASSERT_FALSE(first.cut_facets.empty());
  const Vec2 a = first.mesh.vertex(first.mesh.edge(first.cut_facets[0]).v0);
  const Vec2 b = first.mesh.vertex(first.mesh.edge(first.cut_facets[0]).v1);
  scene.contact->boundary = BoundarySelector{};
  scene.contact->boundary.segments = {{a.x(), a.y(), b.x(), b.y()}};
  const std::string whole = test::input_error_of([&] { (void)build_problem<2>(scene); });
  EXPECT_NE(whole.find("selects no boundary edge"), std::string::npos) << whole;
  for (int rank = 0; rank < 3; ++rank) {
    PieceOfMesh where;
    EXPECT_EQ(test::input_error_of([&] { (void)polygon_problem_piece(scene, rank, 3, where); }), whole) << "rank " << rank;
  }
  expect_the_first_stops_every_process(whole, sent_piece);
  Scene adaptive = parse_scene(test::scenes_dir() / "polygon-bracket.toml");
  adaptive.adapt = SceneAdapt{};
  EXPECT_FALSE(makes_polygon_pieces(adaptive));
  EXPECT_FALSE(makes_polygon_pieces(parse_scene(test::scenes_dir() / "paper-example-4.1-voronoi.toml")));
}

TEST(MeshPieceRead, AGmshOrPoly2dFileOfOneBodyIsReadInPieces) {
  Scene scene = parse_scene(test::scenes_dir() / "gmsh-bracket-3d.toml");
  EXPECT_TRUE(reads_pieces(scene));
  Scene by_point = scene;
  by_point.clamped.points = {{0.0, 0.0, 0.0}};
  EXPECT_TRUE(reads_pieces(by_point));  // each piece holds the cells around the point's vertex
  Scene plane = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  plane.mesh.file = test::data_dir() / "gmsh" / "unit_square_quads.msh";
  EXPECT_TRUE(reads_pieces(plane));
  Scene boxed = plane;  // each piece puts its cells into the regions by their centroids
  boxed.material.regions.push_back(SceneRegionMaterial{3, 130.0, 0.3, std::array<double, 4>{0.0, 0.5, 0.0, 0.5}});
  EXPECT_TRUE(reads_pieces(boxed));
  plane.contact->boundary.segments = {{0.0, 0.0, 0.5, 0.0}};
  EXPECT_TRUE(reads_pieces(plane));  // a segment picks no edge where the pieces meet
  EXPECT_TRUE(reads_pieces(parse_scene(test::scenes_dir() / "sutton-voronoi.toml")));
  Scene adaptive = plane;
  adaptive.adapt = SceneAdapt{};
  EXPECT_FALSE(reads_pieces(adaptive));  // each step's mesh is refined whole
  Scene generated = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  EXPECT_FALSE(reads_pieces(generated));
}
