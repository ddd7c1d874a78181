// A process's share of the full-space route's posed problem, posed from its own rows
// (pose_share, hemivem/contact/pose_share.hpp), against the share cut out of the whole posed
// problem (share_of(posed, layout_of(posed, first, owned))): the same layout, rows of the rotated
// matrix and load, coordinates, tied rows and near-null space, for ranges of vertices at the
// start, in the middle, at the end and over the whole mesh, in the plane and in the solid. And the
// rows of the assembly it starts from (assemble_rows) against the whole assembly's.
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/mesh/boundary.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "pressed_block3d.hpp"
#include "scrambled_mesh.hpp"
#include "stacked_bodies.hpp"
#include "test_support.hpp"

using namespace hemivem;

namespace {

/// The dof of each free index of `dofs`.
std::vector<int> free_dofs(const DofMap& dofs) {
  std::vector<int> free;
  for (int f = 0; f < dofs.num_free(); ++f) free.push_back(dofs.free_dof(f));
  return free;
}

constexpr double rel = 1e-14;

/// The largest |a - b| over the largest |b| (0 for two empty or zero arrays).
double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.size() == 0 && b.size() == 0) return 0.0;
  const double scale = b.cwiseAbs().maxCoeff();
  const double diff = (a - b).cwiseAbs().maxCoeff();
  return scale > 0.0 ? diff / scale : diff;
}

/// The rigid motions of `mesh` (translations, rotations about the mean of its vertices) in the
/// rotated free unknowns of `posed`, written out here from their definition.
template <int dim>
Eigen::MatrixXd rigid_motions(const MeshOf<dim>& mesh, const Condensation& posed) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& x : mesh.vertices()) centre.head<dim>() += x;
  centre /= mesh.num_vertices();
  const int count = dim == 2 ? 3 : 6;
  Eigen::MatrixXd N(posed.rotated_matrix().rows(), count);
  for (int k = 0; k < count; ++k) {
    Eigen::VectorXd u(dim * mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      Eigen::Vector3d x = Eigen::Vector3d::Zero();
      x.head<dim>() = mesh.vertices()[static_cast<std::size_t>(v)];
      x -= centre;
      const Eigen::Vector3d m = k < dim   ? Eigen::Vector3d(Eigen::Vector3d::Unit(k))
                                : dim == 2 ? Eigen::Vector3d(-x(1), x(0), 0.0)
                                           : Eigen::Vector3d(Eigen::Vector3d::Unit(k - 3).cross(x));
      u.segment<dim>(dim * v) = m.head<dim>();
    }
    N.col(k) = posed.rotated_free(u);
  }
  return N;
}

/// The coordinates of two shares are the same: numbers, rows, laws (the same law, or two zero
/// laws of two posings), weights, bounds, groups, origins.
void expect_same_coordinates(const FullSpaceShare& mine, const FullSpaceShare& whole) {
  EXPECT_EQ(mine.coordinate_numbers, whole.coordinate_numbers);
  EXPECT_EQ(mine.coordinate_rows, whole.coordinate_rows);
  EXPECT_EQ(mine.tied_rows, whole.tied_rows);
  const ReducedProblem& p = mine.coordinates;
  const ReducedProblem& q = whole.coordinates;
  ASSERT_EQ(p.laws.size(), q.laws.size());
  for (std::size_t l = 0; l < p.laws.size(); ++l)
    EXPECT_TRUE(p.laws[l] == q.laws[l] || p.laws[l]->name() == q.laws[l]->name()) << "law " << l;
  EXPECT_EQ(p.law_index, q.law_index);
  EXPECT_EQ(p.w, q.w);
  EXPECT_EQ(p.lo, q.lo);
  EXPECT_EQ(p.hi, q.hi);
  EXPECT_EQ(p.c.size(), p.size());
  EXPECT_EQ(p.S.size(), 0);
  ASSERT_EQ(p.groups.size(), q.groups.size());
  for (std::size_t g = 0; g < p.groups.size(); ++g) {
    EXPECT_EQ(p.groups[g].first, q.groups[g].first);
    EXPECT_EQ(p.groups[g].second, q.groups[g].second);
  }
  EXPECT_EQ(mine.origin, whole.origin);
}

/// pose_share of the vertices [v0, v1) of `p` is the share of the whole posed problem `posed`
/// (`dofs` its dof map) of their free dofs.
template <int dim>
void expect_share_of_whole(const BasicContactProblem<dim>& p, const Condensation& posed, const DofMap& dofs, int v0,
                           int v1) {
  SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
  const PosedShare mine = pose_share(p, v0, v1);
  const std::vector<int> free = free_dofs(dofs);
  const auto first = std::lower_bound(free.begin(), free.end(), dim * v0) - free.begin();
  const auto end = std::lower_bound(free.begin(), free.end(), dim * v1) - free.begin();
  const RowLayout layout = layout_of(posed, first, end - first);
  EXPECT_EQ(mine.layout.first, layout.first);
  EXPECT_EQ(mine.layout.owned, layout.owned);
  EXPECT_EQ(mine.layout.global, layout.global);
  EXPECT_EQ(mine.layout.ghosts, layout.ghosts);
  const FullSpaceShare whole = share_of(posed, layout);
  const SparseMatrix& A = mine.share.matrix;
  ASSERT_EQ(A.rows(), layout.owned) << "a share's matrix holds its owned rows only";
  ASSERT_EQ(A.cols(), whole.matrix.cols());
  EXPECT_EQ(A.nonZeros(), whole.matrix.nonZeros()) << "the same pattern, exact zeros kept alike";
  EXPECT_LE(relative_difference(Eigen::MatrixXd(A), Eigen::MatrixXd(whole.matrix)), rel);
  EXPECT_LE(relative_difference(mine.share.load, whole.load), rel);
  expect_same_coordinates(mine.share, whole);
  const Eigen::MatrixXd N = rigid_motions<dim>(*p.elasticity.mesh, posed);
  EXPECT_LE(relative_difference(mine.near_null_space, N.middleRows(layout.first, layout.owned)), rel);
  EXPECT_EQ(mine.block_size, node_block_size(dofs, dim));
  // the rows of a start a process rotates alone are the whole start's rotated rows, to the bit
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(dofs.num_dofs(), -1.0, 2.0).array().sin();
  const Eigen::VectorXd rotated = posed.rotated_free(u);
  const Eigen::VectorXd own = posed.rotated_free(u, layout.first, layout.owned);
  ASSERT_EQ(own.size(), layout.owned);
  EXPECT_TRUE((own.array() == rotated.segment(layout.first, layout.owned).array()).all());
}

/// expect_share_of_whole for the first third of the vertices, the middle third, the last third,
/// all of them and none: against the problem posed whole as the full-space route poses it.
template <int dim>
void expect_shares_of_whole(const BasicContactProblem<dim>& p) {
  BasicContactSolver<dim> solver(p, make_krylov_solver("eigen-cg"), MinimizerOptions{});
  solver.prepare();
  ASSERT_NE(solver.condensation(), nullptr);
  const Condensation& posed = *solver.condensation();
  const int n = p.elasticity.mesh->num_vertices();
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {0, n}})
    expect_share_of_whole(p, posed, solver.system().dofs, v0, v1);
  // the thirds hold every coordinate once, and read each other's unknowns
  Eigen::Index coordinates = 0;
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}}) {
    const PosedShare third = pose_share(p, v0, v1);
    coordinates += third.share.coordinates.size();
    EXPECT_FALSE(third.layout.ghosts.empty());
  }
  EXPECT_EQ(coordinates, posed.reduced().size());
  const PosedShare none = pose_share(p, n / 2, n / 2);
  EXPECT_EQ(none.layout.owned, 0);
  EXPECT_EQ(none.share.matrix.rows(), 0);
  EXPECT_EQ(none.share.coordinates.size(), 0);
}

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> scene(const std::string& name, const std::vector<std::string>& overrides) {
  Scene s = parse_scene(test::scenes_dir() / name);
  apply_overrides(s, overrides);
  return build_problem<dim>(s);
}

TEST(PoseShare, Example41InThePlaneIsTheWholePosingsShare) {
  const Mesh mesh = make_squares(16);
  expect_shares_of_whole<2>(example_4_1(mesh));
}

TEST(PoseShare, Example41InTheSolidIsTheWholePosingsShare) {
  const Mesh3D mesh = make_cubes({5, 5, 5});
  expect_shares_of_whole<3>(test::example_4_1_3d(mesh));
}

// a start's rotated unknowns turn back into its free dofs (the frames are orthogonal), and a
// range of them that holds some of a contact node's unknowns but not all is refused
TEST(PoseShare, AStartsRotatedRowsTurnBackIntoItsFreeDofs) {
  const Mesh3D mesh = make_cubes({4, 4, 4});
  const BasicContactProblem<3> p = test::example_4_1_3d(mesh);
  BasicContactSolver<3> solver(p, make_krylov_solver("eigen-cg"), MinimizerOptions{});
  solver.prepare();
  const Condensation& posed = *solver.condensation();
  const DofMap& dofs = solver.system().dofs;
  Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(dofs.num_dofs(), -1.0, 2.0).array().cos();
  for (int k = 0; k < dofs.num_dofs(); ++k)
    if (dofs.free_index(k) < 0) u(k) = dofs.prescribed_value(k);
  const Eigen::VectorXd back = posed.displacement_of(posed.rotated_free(u));
  EXPECT_LE((back - u).cwiseAbs().maxCoeff(), 1e-14 * u.cwiseAbs().maxCoeff());
  const int node = solver.boundary().nodes.front();
  const int first = dofs.free_index(3 * node);
  ASSERT_GE(first, 0);
  ASSERT_GE(dofs.free_index(3 * node + 1), 0) << "a node with two free components";
  EXPECT_THROW((void)posed.rotated_free(u, first + 1, dofs.num_free() - first - 1), InternalError);
  EXPECT_THROW((void)posed.rotated_free(u, 0, dofs.num_free() + 1), InternalError);
  EXPECT_THROW((void)posed.rotated_free(Eigen::VectorXd(u.head(3)), 0, 3), InputError);
}

// a share moves without a copy of its rows: the moved share holds the same arrays, the other none
TEST(PoseShare, AShareMovesWithoutACopyOfItsRows) {
  const Mesh3D mesh = make_cubes({4, 4, 4});
  PosedShare posed = pose_share<3>(test::example_4_1_3d(mesh), 0, mesh.num_vertices() / 2);
  const SparseMatrix copy = posed.share.matrix;
  const double* values = posed.share.matrix.valuePtr();
  ASSERT_GT(copy.nonZeros(), 0);
  PosedShare moved(std::move(posed));
  EXPECT_EQ(moved.share.matrix.valuePtr(), values);
  EXPECT_EQ(posed.share.matrix.nonZeros(), 0);  // NOLINT(bugprone-use-after-move): what a move leaves
  PosedShare assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.share.matrix.valuePtr(), values);
  EXPECT_EQ(moved.share.matrix.nonZeros(), 0);  // NOLINT(bugprone-use-after-move)
  ASSERT_EQ(assigned.share.matrix.nonZeros(), copy.nonZeros());
  EXPECT_TRUE(std::equal(copy.valuePtr(), copy.valuePtr() + copy.nonZeros(), assigned.share.matrix.valuePtr()));
}

// a solid's isotropic friction: each node's two tangential coordinates, a group, in its owner's rows
TEST(PoseShare, ASolidsFrictionKeepsEachGroupWithItsNode) {
  const auto built = scene<3>("friction-block-3d.toml", {"mesh.n=[6, 6, 3]"});
  expect_shares_of_whole<3>(built->problem);
  const PosedShare all = pose_share(built->problem, 0, built->mesh.num_vertices());
  EXPECT_FALSE(all.share.coordinates.groups.empty());
}

// two parts, a gap and an obstacle in the plane; the normal law of the indenter's part acting
// from its surface (origins)
TEST(PoseShare, TwoPartsAGapAndAnObstacleInThePlane) {
  const auto built = scene<2>("bracket-two-contacts.toml", {"mesh.n=[16, 8]"});
  built->problem.parts[1].law_from_surface = true;
  expect_shares_of_whole<2>(built->problem);
}

// an obstacle on a solid whose contact nodes on the symmetry planes have a prescribed component
TEST(PoseShare, AnObstacleAndPrescribedComponentsAtContactNodesOnASolid) {
  const auto built = scene<3>("hertz-sphere-3d.toml", {"mesh.n=6"});
  expect_shares_of_whole<3>(built->problem);
}

// a bilateral part: its normals are tied rows, its tangentials coordinates of the zero law
TEST(PoseShare, ABilateralPartsTiedRowsStayWithTheirOwners) {
  const Mesh mesh = make_squares(12);
  ContactProblem p = example_4_1(mesh);
  p.parts.front().constraint = ConstraintKind::bilateral;
  expect_shares_of_whole<2>(p);
  const PosedShare all = pose_share(p, 0, mesh.num_vertices());
  EXPECT_FALSE(all.share.tied_rows.empty());
}

TEST(PoseShare, WhatItCannotPoseIsRefusedByName) {
  const Mesh mesh = make_squares(4);
  ContactProblem p = example_4_1(mesh);
  EXPECT_NE(test::input_error_of([&] { (void)pose_share(p, 0, mesh.num_vertices() + 1); }).find("vertices"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([&] { (void)pose_share(p, 3, 2); }).find("vertices"), std::string::npos);
  ContactProblem none = p;
  none.parts.clear();
  EXPECT_NE(test::input_error_of([&] { (void)pose_share(none, 0, 5); }).find("no contact node"), std::string::npos);
}

// ---- two bodies joined at their contact ----

/// The stacked bodies of these tests: 6 x 3 squares or 3 x 3 x 3 cubes each, the upper's top
/// moved sideways and down, with a Tresca bound when `friction`, and further supports of the lower.
std::string stacked(int dim, bool friction, const std::string& supports = "") {
  test::StackedBodies b;
  b.dim = dim;
  b.n = dim == 2 ? "[6, 3]" : "[3, 3, 3]";
  b.top = dim == 2 ? "[0.004, -0.01]" : "[0.004, 0.002, -0.01]";
  b.supports = supports;
  b.contact = friction ? "friction = {law = \"tresca\", bound = 0.002}\n" : "";
  return test::stacked_bodies(b);
}

// the thirds of two joined bodies: each process's rows joined with the rows of the pairs' nodes
// across from its vertices, wherever the split falls
TEST(PoseShare, TwoJoinedSolidsAreTheWholePosingsShares) {
  for (const bool friction : {false, true}) {
    SCOPED_TRACE(friction ? "with friction" : "frictionless");
    const auto two = build_problem<3>(parse_scene_string(stacked(3, friction), "two-solids.toml"));
    expect_shares_of_whole<3>(two->problem);
  }
}

TEST(PoseShare, TwoJoinedPlaneBodiesAreTheWholePosingsShares) {
  const auto two = build_problem<2>(parse_scene_string(stacked(2, true), "two-blocks.toml"));
  expect_shares_of_whole<2>(two->problem);
  // a split between the pairs' nodes and the vertices across from them: every node's row read
  // by the other side
  const int n = two->mesh.num_vertices();
  for (int cut : {n / 4, n / 2, 3 * n / 4}) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    BasicContactSolver<2> solver(two->problem, make_krylov_solver("eigen-cg"), MinimizerOptions{});
    solver.prepare();
    expect_share_of_whole<2>(two->problem, *solver.condensation(), solver.system().dofs, 0, cut);
    expect_share_of_whole<2>(two->problem, *solver.condensation(), solver.system().dofs, cut, n);
  }
}

// a pair's node free where the vertex across from it is prescribed (the lower body clamped on a
// side that reaches the interface): the joined load takes the system's columns at those nodes
TEST(PoseShare, TwoJoinedSolidsWithAShiftedLoadAreTheWholePosingsShares) {
  const auto two = build_problem<3>(parse_scene_string(
      stacked(3, false, ", {side = \"x0\", value = [0.0, 0.001, 0.0]}"), "two-solids.toml"));
  BasicContactSolver<3> solver(two->problem, make_krylov_solver("eigen-cg"), MinimizerOptions{});
  solver.prepare();
  LinearSystem whole = assemble(two->problem.elasticity);
  Joining joining(whole.dofs, [&] {
    std::vector<std::pair<int, Across>> pairs;
    const ContactBoundary& boundary = solver.boundary();
    for (int i = 0; i < boundary.size(); ++i)
      if (boundary.across[static_cast<std::size_t>(i)].size() > 0)
        pairs.emplace_back(boundary.nodes[static_cast<std::size_t>(i)], boundary.across[static_cast<std::size_t>(i)]);
    return pairs;
  }(), 3);
  ASSERT_TRUE(joining.shifts_load()) << "some pair's node is free where the vertex across is prescribed";
  expect_shares_of_whole<3>(two->problem);
  // posed without the system's columns, it names the node
  const std::string refused = test::input_error_of([&] {
    (void)Condensation(whole.dofs, solver.boundary(), part_conditions(solver.parts()), Condensation::CoordinatesOnly{});
  });
  EXPECT_NE(refused.find("displacement free where a vertex of the other body"), std::string::npos) << refused;
}

// ---- shares along a vertex order ----

/// Each free unknown of `ordered` numbered as in `whole`, and back.
struct Renumbering {
  std::vector<int> to_whole, from_whole;
  Renumbering(const DofMap& ordered, const DofMap& whole) {
    for (const int d : free_dofs(ordered)) to_whole.push_back(whole.free_index(d));
    for (const int d : free_dofs(whole)) from_whole.push_back(ordered.free_index(d));
  }
  int to(Eigen::Index i) const { return to_whole[static_cast<std::size_t>(i)]; }
};

/// The matrix `A` (global columns) with its rows and columns numbered as `number` says.
Eigen::MatrixXd renumbered(const SparseMatrix& A, const Renumbering& number) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(A.rows(), A.cols());
  for (Eigen::Index c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator e(A, c); e; ++e) out(number.to(e.row()), number.to(c)) = e.value();
  return out;
}

/// The rows of a share with global columns (its local columns: owned rows, then ghosts).
Eigen::MatrixXd with_global_columns(const PosedShare& share) {
  const RowLayout& l = share.layout;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(l.owned, l.global);
  for (Eigen::Index c = 0; c < share.share.matrix.outerSize(); ++c) {
    const Eigen::Index g = c < l.owned ? l.first + c : l.ghosts[static_cast<std::size_t>(c - l.owned)];
    for (SparseMatrix::InnerIterator e(share.share.matrix, c); e; ++e) out(e.row(), g) = e.value();
  }
  return out;
}

/// pose_share of every vertex along `order` is the whole posed problem (the full-space route's,
/// in dof order) with its free unknowns numbered along the order: its matrix, load, coordinates'
/// rows and near-null space. Its shares of thirds of the order hold its rows, each a contiguous
/// range of that numbering, and every coordinate once.
template <int dim>
void expect_ordered_shares_of_whole(const BasicContactProblem<dim>& p, const std::vector<int>& order) {
  BasicContactSolver<dim> solver(p, make_krylov_solver("eigen-cg"), MinimizerOptions{});
  solver.prepare();
  const Condensation& posed = *solver.condensation();
  const DofMap& dofs = solver.system().dofs;
  const Renumbering number(make_dof_map(*p.elasticity.mesh, p.elasticity.dirichlet, order), dofs);
  const auto n = static_cast<int>(order.size());
  const PosedShare all = pose_share(p, order, 0, n);
  const FullSpaceShare whole = share_of(posed, layout_of(posed, 0, dofs.num_free()));
  EXPECT_TRUE(all.layout.ghosts.empty());
  ASSERT_EQ(all.share.matrix.rows(), whole.matrix.rows());
  EXPECT_EQ(all.share.matrix.nonZeros(), whole.matrix.nonZeros());
  const Eigen::MatrixXd A = Eigen::MatrixXd(whole.matrix);
  EXPECT_LE(relative_difference(renumbered(all.share.matrix, number), A), rel);
  Eigen::VectorXd load(whole.load.size());
  Eigen::MatrixXd N(all.near_null_space.rows(), all.near_null_space.cols());
  for (Eigen::Index i = 0; i < load.size(); ++i) {
    load(number.to(i)) = all.share.load(i);
    N.row(number.to(i)) = all.near_null_space.row(i);
  }
  EXPECT_LE(relative_difference(load, whole.load), rel);
  EXPECT_LE(relative_difference(N, rigid_motions<dim>(*p.elasticity.mesh, posed)), rel);
  EXPECT_EQ(all.share.coordinate_numbers, whole.coordinate_numbers);
  ASSERT_EQ(all.share.coordinate_rows.size(), whole.coordinate_rows.size());
  for (std::size_t k = 0; k < whole.coordinate_rows.size(); ++k)
    EXPECT_EQ(number.to(all.share.coordinate_rows[k]), whole.coordinate_rows[k]) << "coordinate " << k;
  std::vector<int> tied;
  for (const int r : all.share.tied_rows) tied.push_back(number.to(r));
  std::sort(tied.begin(), tied.end());
  EXPECT_EQ(tied, whole.tied_rows);
  EXPECT_EQ(all.share.coordinates.w, whole.coordinates.w);
  EXPECT_EQ(all.share.coordinates.lo, whole.coordinates.lo);
  EXPECT_EQ(all.share.coordinates.hi, whole.coordinates.hi);
  EXPECT_EQ(all.share.origin, whole.origin);
  const Eigen::MatrixXd rows = with_global_columns(all);
  Eigen::Index first = 0, coordinates = 0;
  for (const auto& [p0, p1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}}) {
    SCOPED_TRACE("positions " + std::to_string(p0) + " to " + std::to_string(p1));
    const PosedShare third = pose_share(p, order, p0, p1);
    EXPECT_EQ(third.layout.first, first) << "the thirds' rows follow each other";
    first += third.layout.owned;
    EXPECT_LE(relative_difference(with_global_columns(third), rows.middleRows(third.layout.first, third.layout.owned)),
              rel);
    EXPECT_LE(relative_difference(third.share.load, all.share.load.segment(third.layout.first, third.layout.owned)),
              rel);
    coordinates += third.share.coordinates.size();
  }
  EXPECT_EQ(first, dofs.num_free());
  EXPECT_EQ(coordinates, posed.reduced().size());
}

TEST(PoseShare, ASolidsSharesAlongAVertexOrderAreTheWholePosingRenumbered) {
  const Mesh3D mesh = make_cubes({5, 4, 4});
  expect_ordered_shares_of_whole<3>(test::example_4_1_3d(mesh), test::random_order(mesh.num_vertices(), 11));
}

TEST(PoseShare, APlaneBodysSharesAlongAVertexOrderAreTheWholePosingRenumbered) {
  const auto built = scene<2>("bracket-two-contacts.toml", {"mesh.n=[12, 6]"});
  expect_ordered_shares_of_whole<2>(built->problem, test::random_order(built->mesh.num_vertices(), 12));
}

// the joining reads the rows of the nodes across from a share's vertices, assembled in runs
// consecutive in the order, some of them neighbours of others: each entry once
TEST(PoseShare, TwoJoinedSolidsWithAShiftedLoadAlongAVertexOrderAreTheWholePosingRenumbered) {
  const auto two = build_problem<3>(parse_scene_string(
      stacked(3, false, ", {side = \"x0\", value = [0.0, 0.001, 0.0]}"), "two-solids.toml"));
  expect_ordered_shares_of_whole<3>(two->problem, test::random_order(two->mesh.num_vertices(), 13));
  expect_ordered_shares_of_whole<3>(two->problem, hilbert_vertex_order(two->mesh));
}

TEST(PoseShare, AShareAlongAnOrderThatIsNotAPermutationIsRefused) {
  const Mesh mesh = make_squares(4);
  const ContactProblem p = example_4_1(mesh);
  std::vector<int> order = test::random_order(mesh.num_vertices(), 1);
  order.back() = order.front();
  EXPECT_NE(test::input_error_of([&] { (void)pose_share(p, order, 0, 3); }).find("not a permutation"),
            std::string::npos);
}

// ---- the rows of the assembly ----

/// assemble_rows of [v0, v1) (of the positions [v0, v1) of `order` when it is not empty, the
/// free unknowns numbered along it) holds assemble()'s entries in its owned rows and columns,
/// none between two unknowns it does not own, and b's owned rows.
template <int dim>
void expect_rows_of_whole(const BasicElasticityProblem<dim>& p, int v0, int v1, const std::vector<int>& order = {}) {
  SCOPED_TRACE("vertices " + std::to_string(v0) + " to " + std::to_string(v1));
  const LinearSystem whole = assemble(p);
  const SystemRows rows = order.empty() ? assemble_rows(p, v0, v1) : assemble_rows(p, order, v0, v1);
  const DofMap dofs = order.empty() ? whole.dofs : make_dof_map(*p.mesh, p.dirichlet, order);
  EXPECT_EQ(free_dofs(rows.dofs), free_dofs(dofs));
  const Renumbering number(dofs, whole.dofs);
  const Eigen::MatrixXd A(whole.A), L(rows.A);
  const auto owns = [&](Eigen::Index i) { return i >= rows.at && i < rows.at + rows.owned; };
  double largest = 0.0;
  for (std::size_t i = 0; i < rows.unknowns.size(); ++i)
    for (std::size_t j = 0; j < rows.unknowns.size(); ++j) {
      const auto a = static_cast<Eigen::Index>(i), b = static_cast<Eigen::Index>(j);
      if (owns(a) || owns(b))
        largest = std::max(largest, std::abs(L(a, b) - A(number.to(rows.unknowns[i]), number.to(rows.unknowns[j]))));
      else
        EXPECT_EQ(rows.A.coeff(a, b), 0.0);
    }
  EXPECT_LE(largest, rel * A.cwiseAbs().maxCoeff());
  // every entry of an owned row is among its unknowns
  for (Eigen::Index i = rows.first; i < rows.first + rows.owned; ++i) {
    EXPECT_EQ(rows.unknowns[static_cast<std::size_t>(rows.at + i - rows.first)], i);
    for (SparseMatrix::InnerIterator e(whole.A, number.to(i)); e; ++e)  // A's pattern is symmetric
      EXPECT_TRUE(std::binary_search(rows.unknowns.begin(), rows.unknowns.end(),
                                     number.from_whole[static_cast<std::size_t>(e.row())]));
  }
  for (Eigen::Index k = 0; k < rows.owned; ++k)
    EXPECT_NEAR(rows.b(k), whole.b(number.to(rows.first + k)), rel * whole.b.cwiseAbs().maxCoeff());
}

TEST(PoseShare, TheRowsOfTheAssemblyAreTheWholeAssemblysWithLoadsAndPrescribedValues) {
  const Mesh mesh = make_mesh("voronoi", GridSize{7, 5});
  const auto side = [&](const std::string& name) {
    return select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(Rectangle{}, name)});
  };
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{10.0, 0.3}, PlaneModel::strain);
  p.dirichlet.push_back({side("left"), [](const Vec2& x) { return Vec2(0.01 * x.y(), -0.02); },
                         {true, true}, "left"});
  p.dirichlet.push_back({side("bottom"), [](const Vec2& x) { return Vec2(0.0, 0.03 * x.x()); },
                         {false, true}, "roller"});
  p.body_force = [](const Vec2& x) { return Vec2(1.0 + x.x(), x.y() * x.x()); };
  TractionLoad top;
  top.facets = side("top");
  top.traction = [](const Vec2& x) { return Vec2(x.x(), -2.0); };
  top.pressure = [](const Vec2& x) { return 1.0 + x.x(); };
  p.tractions.push_back(top);
  const int n = mesh.num_vertices();
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {0, n}})
    expect_rows_of_whole<2>(p, v0, v1);
  const std::vector<int> order = test::random_order(n, 2);
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {0, n}})
    expect_rows_of_whole<2>(p, v0, v1, order);
}

TEST(PoseShare, TheRowsOfASolidsAssemblyAreTheWholeAssemblys) {
  const Mesh3D mesh = make_tetrahedra({3, 4, 3});
  const Box box = mesh.bounding_box();
  ElasticityProblem3D p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{10.0, 0.3}, PlaneModel::strain);
  p.dirichlet.push_back({select_box_side(mesh, box, "x0"), [](const Vec3& x) { return Vec3(0.01 * x.y(), -0.02, x.z()); },
                         {true, true, true}, "x0"});
  p.dirichlet.push_back({select_box_side(mesh, box, "bottom"), [](const Vec3& x) { return Vec3(0.0, 0.0, 0.01 * x.x()); },
                         {false, false, true}, "roller"});
  p.body_force = [](const Vec3& x) { return Vec3(1.0 + x.x(), x.y() * x.x(), x.z()); };
  TractionLoad3D top;
  top.facets = select_box_side(mesh, box, "top");
  top.traction = [](const Vec3& x) { return Vec3(x.x(), -2.0, x.y()); };
  top.pressure = [](const Vec3& x) { return 1.0 + x.x(); };
  p.tractions.push_back(top);
  const int n = mesh.num_vertices();
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {0, n}})
    expect_rows_of_whole<3>(p, v0, v1);
  // along a vertex order: ranges of its positions, in its numbering
  const std::vector<int> order = test::random_order(n, 3);
  for (const auto& [v0, v1] : std::vector<std::pair<int, int>>{{0, n / 3}, {n / 3, 2 * n / 3}, {2 * n / 3, n}, {0, n}})
    expect_rows_of_whole<3>(p, v0, v1, order);
  const std::vector<int> short_order(order.begin() + 1, order.end());
  EXPECT_NE(test::input_error_of([&] { (void)assemble_rows(p, short_order, 0, 1); }).find("not a permutation"),
            std::string::npos);
}

}  // namespace
