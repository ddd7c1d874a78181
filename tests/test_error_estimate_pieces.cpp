// The error estimate of a mesh in pieces (hemivem/estimate/estimate_pieces.hpp): the cells each
// piece owns (a third of the vertices each) are every cell of the whole mesh once, with the whole
// mesh's terms to the bit; and the estimate they sum to is estimate_error's.
#include <hemivem/contact/solver.hpp>
#include <hemivem/estimate/estimate_pieces.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/box_piece.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/scene/scene_pieces.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pressed_block3d.hpp"
#include "test_support.hpp"

using namespace hemivem;

namespace {

template <int dim>
BasicContactSolution<dim> solved(const BasicContactProblem<dim>& problem) {
  FactorizationOptions eigen;
  eigen.engine = "eigen";
  MinimizerOptions options;
  options.tolerance = 1e-12;
  BasicContactSolver<dim> solver(problem, make_factorization(eigen), options);
  const auto ssn = make_minimizer("ssn");
  const NonsmoothMinimizer* one[] = {ssn.get()};
  BasicContactSolution<dim> s = std::move(solver.run(one).front());
  EXPECT_TRUE(s.converged()) << s.message;
  return s;
}

/// Every cell's terms of `problem` solved by `s` (a piece of every vertex in one process), whose
/// estimate (estimate_error_of_pieces) is estimate_error's.
template <int dim>
std::map<int, std::vector<double>> terms_of_the_whole(const BasicContactProblem<dim>& problem,
                                                      const BasicContactSolution<dim>& s, int whole_cells) {
  const ErrorEstimate expected = estimate_error(problem, s);
  std::vector<int> all(static_cast<std::size_t>(whole_cells));
  for (int c = 0; c < whole_cells; ++c) all[static_cast<std::size_t>(c)] = c;
  const PieceOfMesh everything{all, whole_cells, {0, problem.elasticity.mesh->num_vertices(), {}}};
  std::map<int, std::vector<double>> terms;
  for (auto& [c, t] : owned_estimate_terms<dim>(problem, s, everything)) terms[c] = t;
  EXPECT_EQ(terms.size(), static_cast<std::size_t>(whole_cells));
  const OneProcessRows one(0);
  const ErrorEstimate from_one = estimate_error_of_pieces<dim>(problem, s, everything, one);
  EXPECT_EQ(from_one.energy, expected.energy);
  EXPECT_EQ(from_one.norm, expected.norm);
  EXPECT_EQ(from_one.parts, expected.parts);
  EXPECT_EQ(from_one.indicators, expected.indicators);
  return terms;
}

/// The cells each piece owns, counted in `owners`, are every cell of the whole once.
void expect_each_cell_once(const std::map<int, int>& owners, int whole_cells) {
  EXPECT_EQ(owners.size(), static_cast<std::size_t>(whole_cells));
  for (const auto& [c, count] : owners) EXPECT_EQ(count, 1) << "cell " << c;
}

/// The pieces of the thirds of the vertices (make_piece(piece) and its problem make_problem(mesh))
/// own every cell of `whole` once, with its terms; the estimate of a piece of every vertex in one
/// process is estimate_error's.
template <int dim, class MakePiece, class MakeProblem>
void expect_pieces_estimate_the_whole(const MeshOf<dim>& whole, int whole_cells, const MakePiece& make_piece,
                                      const MakeProblem& make_problem) {
  const BasicContactProblem<dim> problem = make_problem(whole);
  const BasicContactSolution<dim> s = solved<dim>(problem);
  std::map<int, std::vector<double>> terms = terms_of_the_whole<dim>(problem, s, whole_cells);
  std::map<int, int> owners;
  const int n = whole.num_vertices();
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}}) {
    SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
    const BoxPiece box{v0, v1, {}};
    const auto [mesh, cells] = make_piece(box);
    const BasicContactProblem<dim> on_piece = make_problem(mesh);
    for (const auto& [c, t] : owned_estimate_terms<dim>(on_piece, s, PieceOfMesh{cells, whole_cells, {v0, v1, {}}})) {
      ++owners[c];
      EXPECT_EQ(t, terms[c]) << "cell " << c;
    }
  }
  expect_each_cell_once(owners, whole_cells);
}

/// The pieces three processes keep of the scene's mesh made whole (cut_problem_piece, their
/// vertices shares of its Hilbert order) own every cell of the whole mesh once, with its terms to
/// the bit: a solid's piece holds some faces from the other cell than the whole mesh stored them
/// from, and a face's geometry and a cell's volume and centroid do not depend on that.
template <int dim>
void expect_cut_pieces_estimate_the_whole(const std::string& scene_file) {
  SCOPED_TRACE(scene_file);
  const Scene scene = parse_scene(test::scenes_dir() / scene_file);
  const auto whole = build_problem<dim>(scene);
  const int whole_cells = whole->mesh.num_cells();
  const BasicContactSolution<dim> s = solved<dim>(whole->problem);
  std::map<int, std::vector<double>> terms = terms_of_the_whole<dim>(whole->problem, s, whole_cells);
  std::map<int, int> owners;
  for (int rank = 0; rank < 3; ++rank) {
    SCOPED_TRACE("rank " + std::to_string(rank));
    PieceOfMesh where;
    const auto piece = cut_problem_piece<dim>(build_problem<dim>(scene), rank, 3, where);
    ASSERT_FALSE(where.vertices.order.empty());
    for (const auto& [c, t] : owned_estimate_terms<dim>(piece->problem, s, where)) {
      ++owners[c];
      ASSERT_EQ(t.size(), terms[c].size());
      EXPECT_EQ(t, terms[c]) << "cell " << c;
    }
  }
  expect_each_cell_once(owners, whole_cells);
}

TEST(ErrorEstimatePieces, ThePiecesKeptOfMeshesMadeWholeEstimateEachCellOnceAsTheWholeMesh) {
  expect_cut_pieces_estimate_the_whole<2>("polygon-bracket.toml");
  expect_cut_pieces_estimate_the_whole<3>("gmsh-bracket-3d.toml");
}

TEST(ErrorEstimatePieces, ThePlanesPiecesEstimateEachCellOnceAsTheWholeMesh) {
  for (const std::string generator : {"squares", "triangles"}) {
    SCOPED_TRACE(generator);
    const GridSize n(12, 12);
    const Mesh whole = make_mesh(generator, n);
    expect_pieces_estimate_the_whole<2>(
        whole, whole.num_elements(),
        [&](BoxPiece box) {
          box.sides = {"left", "right", "top", "bottom"};
          return std::make_pair(make_mesh_piece(generator, n, Rectangle{}, box), piece_cells(generator, n, box));
        },
        [](const Mesh& mesh) { return example_4_1(mesh); });
  }
}

TEST(ErrorEstimatePieces, TheSolidsPiecesEstimateEachCellOnceAsTheWholeMesh) {
  const GridSize3 n(4, 3, 9);
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  for (const std::string generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    const Mesh3D whole = make_mesh3d(generator, n, domain);
    const auto with_body_force = [](const Mesh3D& mesh) {
      ContactProblem3D p = test::example_4_1_3d(mesh);
      p.elasticity.body_force = [](const Vec3&) { return Vec3(0.5, 0.0, -2.0); };
      return p;
    };
    expect_pieces_estimate_the_whole<3>(
        whole, whole.num_cells(),
        [&](BoxPiece box) {
          box.sides = {"x0", "x1", "top", "bottom"};
          return std::make_pair(make_mesh3d_piece(generator, n, domain, box), piece_cells(generator, n, box));
        },
        with_body_force);
  }
}

}  // namespace
