// What the results need of a whole mesh that the processes hold in pieces, gathered from the
// pieces (whole_of_pieces of hemivem/app/outputs.hpp), the processes played by threads: the whole
// mesh's own size, stress peak, cells' stresses, facets and a plane's elements, to the bit, and a
// plane's figures drawn from them the whole mesh's.
#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/stress.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/scene_pieces.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"
#include "thread_rows.hpp"

namespace {

using namespace hemivem;
using app::WholeOfPieces;
using test::ThreadRows;

/// A smooth displacement of every vertex that is not linear, so that the cells' projected
/// stresses differ from cell to cell.
template <class MeshType>
Eigen::VectorXd bent(const MeshType& mesh) {
  constexpr int dim = std::is_same_v<MeshType, Mesh3D> ? 3 : 2;
  Eigen::VectorXd u(dim * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const auto x = mesh.vertex(v);
    for (int c = 0; c < dim; ++c)
      u(dim * v + c) = 1e-3 * (std::sin(3.0 * x(0) + c) * std::cos(2.0 * x(1)) + x(dim - 1) * x(dim - 1) * (c + 1));
  }
  return u;
}

/// Every file a plane or a solid writes from what is gathered for it.
const std::vector<std::string> every_file{"result.json", "stress.csv", "contact-surface.vtu", "pressure.png",
                                          "deformed.png", "u_nu.png",  "error.png"};

template <int dim>
using MakePiece = std::function<std::unique_ptr<BasicBuiltProblem<dim>>(int, int, PieceOfMesh&)>;

/// Each process's pieces made by `make(rank, size, where)` (outside the threads: the gathering is
/// what they play), then whole_of_pieces for `files` on `size` threads: each process's record
/// (and the first process's piece in `first`, when given).
template <int dim>
std::vector<WholeOfPieces> gathered(int size, const MakePiece<dim>& make, const Eigen::VectorXd& u,
                                    const std::vector<std::string>& files = every_file,
                                    std::unique_ptr<BasicBuiltProblem<dim>>* first = nullptr) {
  std::vector<std::unique_ptr<BasicBuiltProblem<dim>>> pieces;
  std::vector<PieceOfMesh> where(static_cast<std::size_t>(size));
  for (int rank = 0; rank < size; ++rank) pieces.push_back(make(rank, size, where[static_cast<std::size_t>(rank)]));
  std::vector<WholeOfPieces> records = test::on_threads(size, [&](const ThreadRows& rows) {
    const auto k = static_cast<std::size_t>(rows.rank());
    return app::whole_of_pieces<dim>(pieces[k]->problem, u, where[k], rows, files);
  });
  if (first) *first = std::move(pieces.front());
  return records;
}

std::vector<std::vector<int>> loops_of(const Mesh3D& mesh, const std::vector<int>& faces) {
  std::vector<std::vector<int>> loops;
  for (const int f : faces) loops.push_back(mesh.face(f).vertices);
  return loops;
}
std::vector<std::vector<int>> loops_of(const Mesh& mesh, const std::vector<int>& edges) {
  std::vector<std::vector<int>> loops;
  for (const int e : edges) loops.push_back({mesh.edge(e).v0, mesh.edge(e).v1});
  return loops;
}

/// The records of 2 and 3 processes' pieces (`make`) of the scene's whole problem are its own:
/// on every process the mesh's size and stress peak, on the first its cells' centroids and
/// stresses, its boundary facets, a solid's contact faces and a plane's edges and elements,
/// each in the whole mesh's order.
template <int dim>
void expect_the_whole_meshs(const Scene& scene, const MakePiece<dim>& make) {
  const auto whole = build_problem<dim>(scene);
  const auto& mesh = whole->mesh;
  const Eigen::VectorXd u = bent(mesh);
  const auto stresses = app::cell_stresses(mesh, whole->problem.elasticity.materials, u);
  const std::optional<app::StressPeak> peak = app::stress_peak(mesh, stresses);
  ASSERT_TRUE(peak.has_value());
  const app::MeshSize size = app::mesh_size(mesh);
  for (const int processes : {2, 3}) {
    SCOPED_TRACE(std::to_string(processes) + " processes");
    const std::vector<WholeOfPieces> records = gathered<dim>(processes, make, u);
    for (std::size_t rank = 0; rank < records.size(); ++rank) {
      SCOPED_TRACE("rank " + std::to_string(rank));
      const WholeOfPieces& r = records[rank];
      EXPECT_EQ(r.size.vertices, size.vertices);
      EXPECT_EQ(r.size.cells, size.cells);
      EXPECT_EQ(r.size.facets, size.facets);
      EXPECT_EQ(r.size.h, size.h);
      ASSERT_TRUE(r.stress.has_value());
      EXPECT_EQ(r.stress->cell, peak->cell);
      EXPECT_EQ(r.stress->von_mises, peak->von_mises);
      EXPECT_EQ(r.stress->centroid, peak->centroid);
      EXPECT_TRUE(r.serves("stress.csv"));
      if (rank > 0) {  // what only the first writes
        EXPECT_TRUE(r.stress_rows.empty());
        EXPECT_TRUE(r.contact_surface.empty());
        EXPECT_TRUE(r.boundary.empty());
        EXPECT_TRUE(r.edges.empty());
        EXPECT_EQ(r.cells.size(), 0u);
        continue;
      }
      ASSERT_EQ(r.stress_rows.size(), stresses.size() * (dim + 6));
      for (std::size_t c = 0; c < stresses.size(); ++c) {
        const double* row = r.stress_rows.data() + c * (dim + 6);
        const auto x = mesh.centroid(static_cast<int>(c));
        for (int i = 0; i < dim; ++i) EXPECT_EQ(row[i], x(i)) << "cell " << c;
        const auto& s = stresses[c];
        const double expected[] = {s.xx, s.yy, s.zz, s.yz, s.xz, s.xy};
        for (int i = 0; i < 6; ++i) EXPECT_EQ(row[dim + i], expected[i]) << "cell " << c << " component " << i;
      }
      EXPECT_EQ(r.boundary, loops_of(mesh, mesh.boundary_facets()));
      if constexpr (dim == 3) {
        EXPECT_FALSE(r.contact_surface.empty());
        EXPECT_EQ(r.contact_surface, loops_of(mesh, contact_faces(whole->problem)));
      } else {
        ASSERT_EQ(r.edges.size(), mesh.edges().size());
        for (std::size_t e = 0; e < r.edges.size(); ++e) {
          EXPECT_EQ(r.edges[e][0], mesh.edges()[e].v0) << "edge " << e;
          EXPECT_EQ(r.edges[e][1], mesh.edges()[e].v1) << "edge " << e;
        }
        ASSERT_EQ(r.cells.size(), static_cast<std::size_t>(mesh.num_elements()));
        for (int c = 0; c < mesh.num_elements(); ++c) {
          const auto loop = mesh.element(c);
          const auto got = r.cells[static_cast<std::size_t>(c)];
          EXPECT_EQ(std::vector<int>(got.begin(), got.end()), std::vector<int>(loop.begin(), loop.end())) << "element " << c;
        }
      }
    }
  }
}

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> box_piece(const Scene& scene, int rank, int size, PieceOfMesh& where) {
  const std::optional<BoxPiece> piece = scene_piece(scene, rank, size);
  if (!piece) throw std::logic_error("the scene is not cut into a box's pieces");
  where = scene_piece_of_mesh(scene, *piece);
  // the processes complete the supports together: every process's piece made, this one kept
  auto pieces = test::on_threads(size, [&](const ThreadRows& rows) {
    return build_problem_piece<dim>(scene, *scene_piece(scene, rows.rank(), size), rows);
  });
  return std::move(pieces[static_cast<std::size_t>(rank)]);
}

TEST(WholeOfPieces, AGeneratedSolidsPiecesGiveTheWholeMeshs) {
  Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  scene.mesh.n = 5, scene.mesh.ny = 4, scene.mesh.nz = 3;
  expect_the_whole_meshs<3>(scene, [&](int rank, int size, PieceOfMesh& where) { return box_piece<3>(scene, rank, size, where); });
}

TEST(WholeOfPieces, AGeneratedPlanesPiecesGiveTheWholeMeshs) {
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  scene.mesh.n = 12;
  expect_the_whole_meshs<2>(scene, [&](int rank, int size, PieceOfMesh& where) { return box_piece<2>(scene, rank, size, where); });
}

TEST(WholeOfPieces, TheSolidsPiecesReadFromAFileAndCutFromTheWholeGiveTheWholeMeshs) {
  const Scene scene = parse_scene(test::scenes_dir() / "gmsh-bracket-3d.toml");
  ASSERT_TRUE(reads_pieces(scene));
  {
    SCOPED_TRACE("read");
    expect_the_whole_meshs<3>(scene, [&](int rank, int size, PieceOfMesh& where) {
      return read_problem_piece<3>(scene, rank, size, where);
    });
  }
  {
    SCOPED_TRACE("cut");
    expect_the_whole_meshs<3>(scene, [&](int rank, int size, PieceOfMesh& where) {
      return cut_problem_piece<3>(build_problem<3>(scene), rank, size, where);
    });
  }
}

/// What a figure leaves for gnuplot: its script and each data file's name and text.
std::string drawn(const app::Figure& f) {
  std::ostringstream text;
  text << f.png << ' ' << f.width << 'x' << f.height << '\n' << f.script << '\n';
  for (const app::PlotData& d : f.data) {
    text << "== " << d.name << '\n';
    d.write(text);
  }
  return text.str();
}

TEST(WholeOfPieces, APlanesFiguresDrawnFromItsPiecesAreTheWholeMeshs) {
  Scene scene = parse_scene(test::scenes_dir() / "paper-example-4.1.toml");
  scene.mesh.n = 12;
  const app::SceneSolve solved = app::solve_scene(scene);
  ASSERT_FALSE(solved.solution.contact.empty());
  const app::RunInfo info = app::run_info(scene, solved);
  const Mesh& mesh = solved.built->mesh;
  const std::vector<double>& eta = estimate_error(solved.built->problem, solved.solution).indicators;
  const std::vector<std::string> figures{"deformed.png", "u_nu.png", "error.png"};
  for (const int processes : {2, 3}) {
    SCOPED_TRACE(std::to_string(processes) + " processes");
    std::unique_ptr<BasicBuiltProblem<2>> first;
    const std::vector<WholeOfPieces> records = gathered<2>(
        processes, [&](int rank, int size, PieceOfMesh& where) { return box_piece<2>(scene, rank, size, where); },
        solved.solution.u, figures, &first);
    const WholeOfPieces& whole = records.front();
    const Mesh& piece = first->mesh;
    ASSERT_LT(piece.num_elements(), mesh.num_elements());  // the first process holds a piece, not the whole
    EXPECT_TRUE(whole.stress_rows.empty());  // stress.csv not asked for
    EXPECT_FALSE(whole.serves("stress.csv"));
    EXPECT_TRUE(whole.serves("error.png"));
    EXPECT_EQ(drawn(app::u_nu_figure(piece, whole, solved.solution, info)), drawn(app::u_nu_figure(mesh, solved.solution, info)));
    EXPECT_EQ(drawn(app::deformed_figure(piece, whole, solved.solution, info)),
              drawn(app::deformed_figure(mesh, solved.solution, info)));
    EXPECT_EQ(drawn(app::indicator_figure(piece, whole, eta, info)), drawn(app::indicator_figure(mesh, eta, info)));
  }
}

TEST(WholeOfPieces, WhatIsNotAskedForIsNotGathered) {
  Scene scene = parse_scene(test::scenes_dir() / "example-4.1-3d.toml");
  scene.mesh.n = 4, scene.mesh.ny = 4, scene.mesh.nz = 3;
  const auto whole = build_problem<3>(scene);
  const std::vector<WholeOfPieces> records = gathered<3>(
      2, [&](int rank, int size, PieceOfMesh& where) { return box_piece<3>(scene, rank, size, where); },
      bent(whole->mesh), {"result.json", "pressure.png"});
  const WholeOfPieces& r = records.front();
  EXPECT_EQ(r.size.cells, whole->mesh.num_cells());
  EXPECT_TRUE(r.stress.has_value());
  EXPECT_TRUE(r.stress_rows.empty());
  EXPECT_TRUE(r.boundary.empty());
  EXPECT_EQ(r.contact_surface, loops_of(whole->mesh, contact_faces(whole->problem)));
  for (const char* file : {"result.json", "contact.csv", "pressure.png"}) EXPECT_TRUE(r.serves(file)) << file;
  for (const char* file : {"stress.csv", "deformed.png", "contact-surface.vtu"}) EXPECT_FALSE(r.serves(file)) << file;
}

}  // namespace
