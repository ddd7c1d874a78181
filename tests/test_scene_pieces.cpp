// Which scenes the processes of the full-space route across processes make in pieces
// (scene_piece, hemivem/scene/scene_pieces.hpp): a generated box of one body whose supports,
// loads and contact select sides, in a static solve or along a loading path; where a process's
// piece lies in the whole mesh (scene_piece_of_mesh), against the meshes built; and which
// scenes' meshes, made whole, each process cuts its piece from (cuts_pieces); which scenes of
// several bodies each process makes its piece of each body of (makes_body_pieces).
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/scene_pieces.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "posed_share_checks.hpp"
#include "test_support.hpp"
#include "thread_rows.hpp"

using namespace hemivem;

namespace {

Scene shipped(const std::string& name) { return parse_scene(test::scenes_dir() / name); }

int cells_of(const Mesh& mesh) { return mesh.num_elements(); }
int cells_of(const Mesh3D& mesh) { return mesh.num_cells(); }

/// The pieces of `scene` on two processes: their vertices split the whole mesh's in order,
/// both name the scene's sides, and each piece built holds the cells scene_piece_of_mesh
/// names, of the whole mesh's count. Returns the first piece's cells.
template <int dim>
int expect_two_pieces(const Scene& scene) {
  const std::optional<BoxPiece> first = scene_piece(scene, 0, 2), second = scene_piece(scene, 1, 2);
  EXPECT_TRUE(first && second);
  if (!first || !second) return 0;
  const auto whole = build_problem<dim>(scene);
  EXPECT_EQ(first->first_vertex, 0);
  EXPECT_EQ(first->end_vertex, second->first_vertex);
  EXPECT_EQ(second->end_vertex, whole->mesh.num_vertices());
  EXPECT_FALSE(first->sides.empty());
  EXPECT_EQ(first->sides, second->sides);
  const auto pieces = test::on_threads(2, [&](const test::ThreadRows& rows) {
    return build_problem_piece<dim>(scene, rows.rank() == 0 ? *first : *second, rows);
  });
  for (const int rank : {0, 1}) {
    const BoxPiece& piece = rank == 0 ? *first : *second;
    const PieceOfMesh where = scene_piece_of_mesh(scene, piece);
    const auto& built = pieces[static_cast<std::size_t>(rank)];
    EXPECT_EQ(where.whole_cells, cells_of(whole->mesh));
    EXPECT_EQ(static_cast<int>(where.cells.size()), cells_of(built->mesh));
    EXPECT_EQ(built->mesh.num_vertices(), whole->mesh.num_vertices());
    EXPECT_EQ(where.vertices.first, piece.first_vertex);
    EXPECT_EQ(where.vertices.end, piece.end_vertex);
    EXPECT_TRUE(where.vertices.order.empty());  // a slab of the mesh's own order
  }
  return static_cast<int>(scene_piece_of_mesh(scene, *first).cells.size());
}

TEST(ScenePieces, AStaticSolveOfAGeneratedBoxIsMadeInPieces) {
  const Scene plane = shipped("paper-example-4.1.toml");
  EXPECT_LT(expect_two_pieces<2>(plane), 64 * 64) << "the first half leaves cells out";
  expect_two_pieces<2>(shipped("paper-example-4.1-triangles.toml"));
  expect_two_pieces<2>(shipped("paper-example-4.1-distorted.toml"));  // squares, their inner vertices moved
  expect_two_pieces<2>(shipped("paper-example-4.1-nonconvex.toml"));  // a grid twice as fine
  Scene solid = shipped("example-4.1-3d.toml");
  expect_two_pieces<3>(solid);
  solid.mesh.generator = "tetrahedra";  // six cells a box
  expect_two_pieces<3>(solid);
}

// a loading path changes its loads, prescribed values and obstacles on the sides alone
TEST(ScenePieces, ALoadingPathOfAGeneratedBoxIsMadeInPieces) {
  const Scene coulomb = shipped("friction-coulomb.toml");
  ASSERT_TRUE(coulomb.path);
  expect_two_pieces<2>(coulomb);
  const Scene block = shipped("coulomb-block-3d.toml");
  ASSERT_TRUE(block.path);
  expect_two_pieces<3>(block);
}

// a support or a load that picks a facet on no process's piece is refused on every process with
// the whole mesh's message; the pieces gather before any of them refuses
TEST(ScenePieces, ASupportOrLoadThatPicksNoFacetOfAnyPieceIsRefusedOnEvery) {
  Scene scene = shipped("paper-example-4.1.toml");
  scene.mesh.n = 12;
  BoundarySelector inside;  // a line across the body, along no boundary edge of the whole mesh
  inside.segments = {{0.0, 0.5, 1.0, 0.5}};
  for (const bool support : {true, false}) {
    SCOPED_TRACE(support ? "a support" : "a load");
    Scene across = scene;
    if (support) {
      SceneDirichlet d;
      d.boundary = inside;
      d.ux = SceneScalar{0.0};
      across.dirichlet.push_back(d);
    } else {
      SceneTraction t;
      t.boundary = inside;
      t.value = {SceneScalar{1.0}, SceneScalar{0.0}, SceneScalar{0.0}};
      across.tractions.push_back(t);
    }
    const std::string expected = test::input_error_of([&] { (void)build_problem<2>(across); });
    EXPECT_NE(expected.find(support ? "dirichlet[0]: selects no boundary edge" : "loads.traction[1]: selects no boundary edge"),
              std::string::npos)
        << expected;
    ASSERT_TRUE(scene_piece(across, 0, 3));
    const auto refused = test::on_threads(3, [&](const test::ThreadRows& rows) {
      return test::input_error_of(
          [&] { (void)build_problem_piece<2>(across, *scene_piece(across, rows.rank(), 3), rows); });
    });
    for (const std::string& message : refused) EXPECT_EQ(message, expected);
  }
}

// a mesh of one body that is no generated box is read or made in pieces from its cells' lists;
// every shipped scene takes one route across processes, and those made whole and cut are these
TEST(ScenePieces, EveryShippedSceneTakesOneRouteAcrossProcesses) {
  for (const char* name : {"paper-example-4.1-voronoi.toml",  // not a grid of boxes
                           "polygon-bracket.toml",            // a polygon
                           "gmsh-bracket-3d.toml"}) {         // a file
    SCOPED_TRACE(name);
    EXPECT_FALSE(scene_piece(shipped(name), 0, 2));
    EXPECT_FALSE(cuts_pieces(shipped(name)));
  }
  EXPECT_TRUE(makes_voronoi_pieces(shipped("paper-example-4.1-voronoi.toml")));
  EXPECT_TRUE(makes_polygon_pieces(shipped("polygon-bracket.toml")));
  EXPECT_TRUE(reads_pieces(shipped("gmsh-bracket-3d.toml")));
  EXPECT_FALSE(cuts_pieces(shipped("paper-example-4.1.toml")));  // made in pieces
  std::vector<std::string> cut;
  int scenes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::scenes_dir())) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    const Scene scene = parse_scene(entry.path());
    const int routes = static_cast<int>(scene_piece(scene, 0, 2).has_value()) + reads_pieces(scene) +
                       makes_voronoi_pieces(scene) + makes_polygon_pieces(scene) + makes_body_pieces(scene) +
                       cuts_pieces(scene) + scene.adapt.has_value();
    EXPECT_EQ(routes, 1);
    if (cuts_pieces(scene)) cut.push_back(name);
    ++scenes;
  }
  EXPECT_GT(scenes, 30);
  EXPECT_EQ(cut, std::vector<std::string>{});
}

// several bodies of generated boxes selected by sides, segments and points, or made as lists
// (Voronoi cells, a polygon's mesh, a mesh file), are made in pieces, in a static solve and on a loading
// path; any other bodies are made whole and cut; an adaptive solve's meshes are held whole
TEST(ScenePieces, SeveralBodiesAreMadeInPiecesOrCutAndAdaptiveStepsHeldWholeOnEveryProcess) {
  const Scene blocks = shipped("two-blocks.toml");  // a Voronoi body on a body of squares
  EXPECT_FALSE(scene_piece(blocks, 0, 2));
  EXPECT_TRUE(makes_body_pieces(blocks));
  EXPECT_FALSE(cuts_pieces(blocks));
  Scene file = blocks;  // a body read from a file: each process reads its piece of it
  file.bodies[1].mesh.file = test::scenes_dir() / "meshes" / "graded-block.poly2d";
  EXPECT_TRUE(makes_body_pieces(file));
  EXPECT_FALSE(cuts_pieces(file));
  file.bodies[1].material.regions.push_back(SceneRegionMaterial{1, 20.0, 0.3, std::array<double, 4>{0.0, 0.5, -1.0, 0.0}});
  EXPECT_TRUE(makes_body_pieces(file));  // with region boxes too
  EXPECT_FALSE(cuts_pieces(file));
  Scene boxed = blocks;  // region boxes in the Voronoi body and the squares: made in pieces
  boxed.bodies[0].material.regions.push_back(SceneRegionMaterial{1, 20.0, 0.3, std::array<double, 4>{0.0, 0.5, 0.5, 1.0}});
  boxed.bodies[1].material.regions.push_back(SceneRegionMaterial{1, 20.0, 0.3, std::array<double, 4>{0.0, 0.5, 0.0, 0.5}});
  EXPECT_TRUE(makes_body_pieces(boxed));
  EXPECT_FALSE(cuts_pieces(boxed));
  Scene triangles = blocks;
  triangles.bodies[0].mesh.generator = "triangles";
  EXPECT_TRUE(makes_body_pieces(triangles));
  EXPECT_FALSE(cuts_pieces(triangles));
  const Scene boxes = shipped("two-boxes-3d.toml");
  EXPECT_FALSE(scene_piece(boxes, 0, 2));  // a scene of one body's piece
  EXPECT_TRUE(makes_body_pieces(boxes));
  EXPECT_FALSE(cuts_pieces(boxes));
  Scene path = boxes;  // a loading path of two bodies
  path.path = shipped("cattaneo-mindlin.toml").path;
  ASSERT_TRUE(path.path);
  EXPECT_TRUE(makes_body_pieces(path));
  Scene grouped = boxes;  // the lower's top named as a group: no side, made whole and cut
  ASSERT_TRUE(grouped.contact && grouped.contact->against);
  grouped.contact->against->sides.clear();
  grouped.contact->against->groups = {"top"};
  EXPECT_FALSE(makes_body_pieces(grouped));
  EXPECT_TRUE(cuts_pieces(grouped));
  Scene adaptive_bodies = boxes;
  adaptive_bodies.adapt = SceneAdapt{};
  EXPECT_FALSE(makes_body_pieces(adaptive_bodies));
  EXPECT_FALSE(cuts_pieces(adaptive_bodies));
  Scene adaptive = shipped("paper-example-4.1.toml");  // its meshes after the first are not boxes
  ASSERT_TRUE(scene_piece(adaptive, 0, 2));
  EXPECT_FALSE(makes_body_pieces(adaptive));  // one body
  adaptive.adapt = SceneAdapt{};
  EXPECT_FALSE(scene_piece(adaptive, 0, 2));
  EXPECT_FALSE(cuts_pieces(adaptive));
  EXPECT_NE(test::input_error_of([&] {
              PieceOfMesh where;
              (void)build_bodies_piece<3>(grouped, 0, 2, where);
            }).find("not made in pieces"),
            std::string::npos);
}

// a support at a point holds the grid vertex nearest it, whose cells every piece holds; a
// segment along a side is made as the side, a segment across the body with every side (the
// piece's edges where it meets the others picked by no selector); of several bodies, a segment
// across one is cut from the whole mesh (cut_problem_piece renumbers the whole's facets)
TEST(ScenePieces, PointsAndSegmentsAreMadeInPiecesAcrossSeveralBodiesCut) {
  const Scene plate = shipped("plate-friction-benchmark.toml");  // squares [32, 32], held at (0.04, 0)
  ASSERT_TRUE(plate.path);
  expect_two_pieces<2>(plate);
  EXPECT_FALSE(cuts_pieces(plate));
  for (int rank : {0, 1}) EXPECT_EQ(scene_piece(plate, rank, 2)->held, std::vector<int>{32}) << "the corner (32, 0) of the grid";
  Scene solid = shipped("example-4.1-3d.toml");  // cubes [8, 4, 8] on [0, 1] x [0, 0.5] x [0, 1]
  SceneDirichlet point;
  point.boundary.points = {{1.0, 0.5, 0.5}, {0.25, 0.0, 1.0}};  // the grid points (8, 4, 4) and (2, 0, 8)
  point.uz = SceneScalar{0.0};
  solid.dirichlet.push_back(point);
  expect_two_pieces<3>(solid);
  EXPECT_EQ(scene_piece(solid, 0, 2)->held, (std::vector<int>{8 + 4 * 9 + 4 * 45, 2 + 8 * 45}));

  Scene along = shipped("paper-example-4.1.toml");
  along.contact->boundary = BoundarySelector{};
  along.contact->boundary.segments = {{0.2, 0.0, 0.7, 0.0}, {1.0, 0.3, 1.0, 0.4}};  // on the bottom and the right
  const std::optional<BoxPiece> piece = scene_piece(along, 0, 2);
  ASSERT_TRUE(piece);
  for (const char* side : {"bottom", "right"})
    EXPECT_NE(std::find(piece->sides.begin(), piece->sides.end(), side), piece->sides.end()) << side;
  expect_two_pieces<2>(along);
  Scene across = along;
  across.contact->boundary.segments.push_back({0.0, 0.5, 1.0, 0.5});  // across the body: every side held
  const std::optional<BoxPiece> every = scene_piece(across, 0, 2);
  ASSERT_TRUE(every);
  EXPECT_EQ(every->sides, (std::vector<std::string>{"bottom", "left", "right", "top"}));
  EXPECT_FALSE(cuts_pieces(across));
  expect_two_pieces<2>(across);
  Scene bodies = shipped("two-blocks.toml");  // several bodies: a segment across one holds every side of it
  bodies.bodies[0].mesh.generator = "triangles";
  ASSERT_TRUE(makes_body_pieces(bodies));
  bodies.bodies[1].tractions.push_back(SceneTraction{});
  bodies.bodies[1].tractions.back().boundary.segments = {{0.0, 0.1, 1.0, 0.1}};
  EXPECT_TRUE(makes_body_pieces(bodies));
  EXPECT_FALSE(cuts_pieces(bodies));
  const Scene rollers = shipped("rollers-pressure.toml");  // a contact part on a segment of a Voronoi mesh's bottom
  EXPECT_FALSE(scene_piece(rollers, 0, 2));
  EXPECT_FALSE(cuts_pieces(rollers));  // made from its cells' lists, where a segment picks no cut edge
  EXPECT_TRUE(makes_voronoi_pieces(rollers));
}

// region boxes put each piece's cells into the regions of the whole mesh's cells, a piece that
// holds no cell of a region included; whether each region holds a cell is the whole mesh's to
// say, from every piece's regions
TEST(ScenePieces, RegionBoxesPutEachPiecesCellsInTheWholeMeshsRegions) {
  Scene scene = shipped("extreme/bimaterial-1e6.toml");  // region 1: the upper half's box
  scene.mesh.n = 12;
  scene.material.regions.push_back(SceneRegionMaterial{2, 130.0, 0.3, std::array<double, 4>{0.4, 0.6, 0.1, 0.2}});
  const auto whole = build_problem<2>(scene);
  std::vector<int> regions;
  ASSERT_TRUE(scene_piece(scene, 0, 3));
  const auto pieces = test::on_threads(3, [&](const test::ThreadRows& rows) {
    return build_problem_piece<2>(scene, *scene_piece(scene, rows.rank(), 3), rows);
  });
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    const std::optional<BoxPiece> piece = scene_piece(scene, rank, 3);
    ASSERT_TRUE(piece);
    const PieceOfMesh where = scene_piece_of_mesh(scene, *piece);
    const auto& built = pieces[static_cast<std::size_t>(rank)];
    ASSERT_EQ(static_cast<int>(where.cells.size()), built->mesh.num_elements());
    for (std::size_t k = 0; k < where.cells.size(); ++k)
      EXPECT_EQ(built->mesh.region(static_cast<int>(k)), whole->mesh.region(where.cells[k])) << "cell " << where.cells[k];
    test::expect_same_share(pose_share(built->problem, piece->first_vertex, piece->end_vertex),
                            pose_share(whole->problem, piece->first_vertex, piece->end_vertex));
    const std::vector<int>& mine = built->mesh.regions();
    EXPECT_EQ(std::count(mine.begin(), mine.end(), 2) > 0, rank == 0) << "the box's cells lie in the first piece alone";
    regions.insert(regions.end(), mine.begin(), mine.end());
  }
  EXPECT_NO_THROW(check_regions_of_pieces(scene, regions));
  regions.erase(std::remove(regions.begin(), regions.end(), 2), regions.end());
  EXPECT_NE(test::input_error_of([&] { check_regions_of_pieces(scene, regions); })
                .find("material.region[1].id: region 2 matches no element of the mesh (its box holds no element centroid"),
            std::string::npos);
}

}  // namespace
