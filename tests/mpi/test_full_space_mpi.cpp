// The full-space route distributed by rows (hemivem/contact/full_space.hpp, FullSpaceShare) under
// mpiexec: every process poses the same problem, keeps its share of the rows (an uneven split),
// and the processes minimize together with PETSc's engines. The answer is the one-process
// answer of the same engine and the condensed route's; the certificate is the whole problem's,
// the same on every process, and rejects a point off balance on any one of them.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/full_space.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/pose_share.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/estimate/estimate_pieces.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/box_piece.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <utility>
#include <memory>
#include <string>
#include <vector>

#include "krylov_test_main.hpp"
#include "pressed_block3d.hpp"
#include "scrambled_mesh.hpp"
#include "stacked_bodies.hpp"

using namespace hemivem;

namespace {

MinimizerOptions tight() {
  MinimizerOptions o;
  o.tolerance = 1e-12;
  return o;
}

std::unique_ptr<SparseFactorization> factorization() {
  FactorizationOptions o;
  o.engine = "eigen";
  return make_factorization(o);
}

// A posed problem (Condensation::PoseOnly) and the condensed route's coordinates, kept with what
// they refer to.
struct Posed {
  LinearSystem system;
  std::unique_ptr<Condensation> posed;
  Eigen::VectorXd condensed_a;  ///< the condensed route's coordinates
  Eigen::MatrixXd near_null;    ///< the rigid motions in the rotated unknowns
};

template <int dim, class Problem, class Mesh>
Posed pose(const Problem& p, const Mesh& mesh) {
  Posed out;
  out.system = assemble(p.elasticity);
  BasicContactSolver<dim> solver(p, out.system, factorization(), tight());
  solver.prepare();
  out.posed = std::make_unique<Condensation>(out.system, solver.boundary(), part_conditions(solver.parts()),
                                             Condensation::PoseOnly{});
  const Condensation condensed(out.system, solver.boundary(), factorization(), part_conditions(solver.parts()));
  const auto ssn = make_minimizer("ssn");
  const MinimizerResult m = ssn->minimize(condensed.reduced(), Eigen::VectorXd(), tight());
  EXPECT_TRUE(m.converged()) << m.message;
  out.condensed_a = m.a;
  // translations and rotations about the origin, in the rotated free unknowns
  const auto& vertices = mesh.vertices();
  const int motions = dim == 2 ? 3 : 6;
  out.near_null.resize(out.posed->rotated_matrix().rows(), motions);
  for (int k = 0; k < motions; ++k) {
    Eigen::VectorXd u(static_cast<Eigen::Index>(dim * vertices.size()));
    for (std::size_t v = 0; v < vertices.size(); ++v) {
      Eigen::Matrix<double, dim, 1> m = Eigen::Matrix<double, dim, 1>::Zero();
      const auto& x = vertices[v];
      if (k < dim) {
        m(k) = 1.0;
      } else if constexpr (dim == 2) {
        m << -x(1), x(0);
      } else {
        m = Eigen::Vector3d::Unit(k - dim).cross(Eigen::Vector3d(x));
      }
      u.segment<dim>(static_cast<Eigen::Index>(dim * v)) = m;
    }
    out.near_null.col(k) = out.posed->rotated_free(u);
  }
  return out;
}

// Rank r of P owns a share of the rows that grows with r (rank 0 the fewest), so that the split is
// uneven and a share's boundary cuts through the contact surface's unknowns.
// With `idle`, rank 0 owns no row (and reads none) and the others share the rows.
RowLayout uneven_layout(const Condensation& posed, int rank, int size, bool idle = false) {
  const Eigen::Index n = posed.rotated_matrix().rows();
  if (idle && size > 1) {
    if (rank == 0) return layout_of(posed, 0, 0);
    RowLayout rest = uneven_layout(posed, rank - 1, size - 1);
    return rest;
  }
  const Eigen::Index weights = static_cast<Eigen::Index>(size) * (size + 1) / 2;
  Eigen::Index first = 0;
  for (int r = 0; r < rank; ++r) first += n * (r + 1) / weights;
  const Eigen::Index owned = rank == size - 1 ? n - first : n * (rank + 1) / weights;
  return layout_of(posed, first, owned);
}

struct Distributed {
  MinimizerResult result;
  Eigen::VectorXd x;         ///< the whole x, gathered
  Eigen::VectorXd a;         ///< the whole problem's coordinates, gathered in their numbering
  FullSpaceShare share;
  std::unique_ptr<RowDistribution> rows;
};

Distributed solve_distributed(const Posed& p, const std::string& engine, bool idle = false) {
  const ProcessWorld world = krylov_world();
  Distributed out;
  const RowLayout layout = uneven_layout(*p.posed, world.rank, world.size, idle);
  out.share = share_of(*p.posed, layout);
  out.rows = make_distributed_rows(layout);
  auto krylov = make_krylov_solver(engine);
  KrylovHints hints(p.near_null.middleRows(layout.first, layout.owned), 1);
  hints.rows = out.rows.get();
  Eigen::VectorXd x;
  out.result = minimize_full_space(out.share, *krylov, hints, tight(), &x);
  out.x = out.rows->all_gather(x);
  // the coordinates in the whole problem's numbering
  Eigen::VectorXd numbers(static_cast<Eigen::Index>(out.share.coordinate_numbers.size()));
  for (Eigen::Index i = 0; i < numbers.size(); ++i)
    numbers(i) = static_cast<double>(out.share.coordinate_numbers[static_cast<std::size_t>(i)]);
  const Eigen::VectorXd all_numbers = out.rows->all_gather(numbers), all_a = out.rows->all_gather(out.result.a);
  out.a.resize(all_a.size());
  for (Eigen::Index i = 0; i < all_a.size(); ++i) out.a(static_cast<Eigen::Index>(all_numbers(i))) = all_a(i);
  return out;
}

void expect_same_as_one_process(const Posed& p, const std::string& engine, bool idle = false) {
  SCOPED_TRACE(engine);
  auto krylov = make_krylov_solver(engine);
  Eigen::VectorXd x_one;
  const MinimizerResult one = minimize_full_space(*p.posed, *krylov, KrylovHints(p.near_null, 1), tight(), &x_one);
  ASSERT_TRUE(one.converged()) << one.message;
  const Distributed d = solve_distributed(p, engine, idle);
  ASSERT_TRUE(d.result.converged()) << d.result.message;
  EXPECT_LE(d.result.certificate.worst(), 1e-12);
  const double scale = x_one.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  ASSERT_EQ(d.x.size(), x_one.size());
  EXPECT_LE((d.x - x_one).cwiseAbs().maxCoeff(), 1e-8 * scale);
  ASSERT_EQ(d.a.size(), p.condensed_a.size());
  EXPECT_LE((d.a - p.condensed_a).cwiseAbs().maxCoeff(), 1e-8 * scale) << "the condensed route's coordinates";
  EXPECT_NEAR(d.result.objective, one.objective, 1e-9 * std::abs(one.objective));
  // the same verdict and numbers on every process
  EXPECT_EQ(d.rows->max(d.result.certificate.dual), d.rows->min(d.result.certificate.dual));
  EXPECT_EQ(d.rows->max(d.result.objective), d.rows->min(d.result.objective));
}

TEST(FullSpaceMpi, Example41InThePlaneIsTheOneProcessAnswer) {
  const Mesh mesh = make_squares(16);
  const Posed p = pose<2>(example_4_1(mesh), mesh);
  for (const std::string& engine : {"petsc-gamg", "petsc-hypre"}) expect_same_as_one_process(p, engine);
}

TEST(FullSpaceMpi, Example41InTheSolidIsTheOneProcessAnswer) {
  const Mesh3D mesh = make_cubes({5, 5, 5});
  const Posed p = pose<3>(test::example_4_1_3d(mesh), mesh);
  expect_same_as_one_process(p, "petsc-gamg");
}

// Each process poses only its share, from the cells that hold its vertices (pose_share: no
// process assembles, rotates or holds the whole system), and the processes solve together: the
// one-process answer of the whole posed problem.
template <int dim, class Problem>
void expect_posed_shares_solve_alike(const Problem& problem, int vertices) {
  const ProcessWorld world = krylov_world();
  const auto [first, end] = vertex_share(vertices, world.rank, world.size);
  const PosedShare mine = pose_share<dim>(problem, first, end);
  EXPECT_EQ(mine.share.matrix.rows(), mine.layout.owned);
  const auto rows = make_distributed_rows(mine.layout);
  EXPECT_EQ(mine.share.matrix.cols(), mine.layout.owned + static_cast<Eigen::Index>(mine.layout.ghosts.size()));
  if (world.size > 1) EXPECT_LT(mine.layout.owned, mine.layout.global) << "a share, not the whole";
  auto krylov = make_krylov_solver("petsc-gamg");
  KrylovHints hints(mine.near_null_space, mine.block_size);
  hints.rows = rows.get();
  Eigen::VectorXd x;
  const MinimizerResult distributed = minimize_full_space(mine.share, *krylov, hints, tight(), &x);
  ASSERT_TRUE(distributed.converged()) << distributed.message;
  const Eigen::VectorXd whole_x = rows->all_gather(x);
  // the whole problem posed and solved in this process
  const LinearSystem system = assemble(problem.elasticity);
  BasicContactSolver<dim> solver(problem, system, factorization(), tight());
  solver.prepare();
  const Condensation posed(system, solver.boundary(), part_conditions(solver.parts()), Condensation::PoseOnly{});
  auto one = make_krylov_solver("petsc-gamg");
  Eigen::VectorXd x_one;
  const MinimizerResult alone = minimize_full_space(posed, *one, Eigen::MatrixXd(), tight(), &x_one);
  ASSERT_TRUE(alone.converged()) << alone.message;
  ASSERT_EQ(whole_x.size(), x_one.size());
  EXPECT_LE((whole_x - x_one).cwiseAbs().maxCoeff(), 1e-8 * x_one.cwiseAbs().maxCoeff());
  EXPECT_NEAR(distributed.objective, alone.objective, 1e-9 * std::abs(alone.objective));
}

TEST(FullSpaceMpi, EachProcessPosesOnlyItsShareInThePlane) {
  const Mesh mesh = make_squares(16);
  expect_posed_shares_solve_alike<2>(example_4_1(mesh), static_cast<int>(mesh.vertices().size()));
}

TEST(FullSpaceMpi, EachProcessPosesOnlyItsShareInTheSolid) {
  const Mesh3D mesh = make_cubes({5, 5, 5});
  expect_posed_shares_solve_alike<3>(test::example_4_1_3d(mesh), static_cast<int>(mesh.vertices().size()));
}

// Rank 0 owns no row and reads none; it takes part in every collective call all the same.
TEST(FullSpaceMpi, AProcessOwningNoRowTakesPartInEverySolve) {
  const Mesh mesh = make_squares(10);
  const Posed p = pose<2>(example_4_1(mesh), mesh);
  expect_same_as_one_process(p, "petsc-gamg", true);
}

TEST(FullSpaceMpi, TheCertificateRejectsAPointOffBalanceOnAnyProcess) {
  const Mesh mesh = make_squares(12);
  const Posed p = pose<2>(example_4_1(mesh), mesh);
  Distributed d = solve_distributed(p, "petsc-gamg");
  ASSERT_TRUE(d.result.converged()) << d.result.message;
  const RowLayout& layout = d.rows->layout();
  Eigen::VectorXd x = d.x.segment(layout.first, layout.owned);
  EXPECT_TRUE(certify_full_space(d.share, *d.rows, x, 1e-12).certificate.converged());
  // the last process moves one of its unknowns that is not a coordinate
  if (d.rows->rank() == d.rows->size() - 1) {
    std::vector<char> coordinate(static_cast<std::size_t>(x.size()), 0);
    for (int row : d.share.coordinate_rows) coordinate[static_cast<std::size_t>(row)] = 1;
    Eigen::Index interior = 0;
    while (coordinate[static_cast<std::size_t>(interior)]) ++interior;
    x(interior) += 1e-6 * d.x.cwiseAbs().maxCoeff();
  }
  const Certificate c = certify_full_space(d.share, *d.rows, x, 1e-8).certificate;
  EXPECT_FALSE(c.converged()) << "on rank " << d.rows->rank();
  EXPECT_GT(c.dual, 1e-8);
}

// The share's matrix lent to the iteration: the same answer, and the matrix as it was, to the bit.
TEST(FullSpaceMpi, ALentMatrixGivesTheSameAnswerAndIsRestoredToTheBit) {
  const Mesh3D mesh = make_cubes({5, 5, 5});
  const ProcessWorld world = krylov_world();
  const auto [first, end] = vertex_share(static_cast<int>(mesh.vertices().size()), world.rank, world.size);
  PosedShare mine = pose_share<3>(test::example_4_1_3d(mesh), first, end);
  const SparseMatrix before = mine.share.matrix;
  const auto rows = make_distributed_rows(mine.layout);
  KrylovHints hints(mine.near_null_space, mine.block_size);
  hints.rows = rows.get();
  auto krylov = make_krylov_solver("petsc-gamg");
  Eigen::VectorXd x, y;
  const MinimizerResult kept = minimize_full_space(mine.share, *krylov, hints, tight(), &x);
  auto other = make_krylov_solver("petsc-gamg");
  const MinimizerResult lent = minimize_full_space_in_place(mine.share, *other, hints, tight(), &y);
  ASSERT_TRUE(kept.converged()) << kept.message;
  ASSERT_TRUE(lent.converged()) << lent.message;
  EXPECT_EQ(lent.iterations, kept.iterations);
  // the same Newton systems; PETSc's distributed set-up sums what processes send in the order
  // it receives them, so that two set-ups may differ in the last bits
  EXPECT_LE(rows->max((x - y).cwiseAbs().maxCoeff()), 1e-12 * rows->max(x.cwiseAbs().maxCoeff()));
  ASSERT_EQ(mine.share.matrix.nonZeros(), before.nonZeros());
  EXPECT_TRUE(std::equal(before.valuePtr(), before.valuePtr() + before.nonZeros(), mine.share.matrix.valuePtr()));
  EXPECT_TRUE(std::equal(before.innerIndexPtr(), before.innerIndexPtr() + before.nonZeros(),
                         mine.share.matrix.innerIndexPtr()));
}

// A Krylov engine that counts the releases after its last solve.
class ReleaseCounting final : public KrylovSolver {
 public:
  explicit ReleaseCounting(std::unique_ptr<KrylovSolver> engine) : engine_(std::move(engine)) {}
  std::string name() const override { return engine_->name(); }
  bool runs_across_processes() const noexcept override { return engine_->runs_across_processes(); }
  FactorizationResult compute(const SparseMatrix& A, const KrylovHints& hints) override {
    released_after_solves = 0;
    return engine_->compute(A, hints);
  }
  KrylovSolveResult solve(const Eigen::VectorXd& b, Eigen::VectorXd* x, double rtol, int max_iterations) const override {
    released_after_solves = 0;
    return engine_->solve(b, x, rtol, max_iterations);
  }
  void release() override {
    ++released_after_solves;
    engine_->release();
  }
  mutable int released_after_solves = -1;

 private:
  std::unique_ptr<KrylovSolver> engine_;
};

// The whole solve across processes as the command runs it (solve_full_space_shares): each
// process poses and solves its share, rank 0 gathers the whole solution. Against the condensed
// route (Eigen's factorization and ssn) in every displacement, the contact table, the energy and
// the balance of forces; the verdict and certificate the same on every process.
// `problem` is each process's problem (on its piece of the mesh, hemivem/mesh/box_piece.hpp, or
// the whole), `whole` the condensed route's (the same problem on the whole mesh; `problem` when
// null); the processes share the vertices along `vertex_order` (empty: the mesh's order).
template <int dim, class Problem>
void expect_shares_solve_as_the_condensed_route(
    const Problem& problem,
    const std::function<void(const BasicContactSolution<dim>& s, const BasicContactSolution<dim>& c)>& also = {},
    const Problem* whole = nullptr, const std::vector<int>& vertex_order = {}) {
  const ProcessWorld world = krylov_world();
  ReleaseCounting engine(make_krylov_solver("petsc-gamg"));
  const BasicContactSolution<dim> s =
      solve_full_space_shares<dim>(problem, engine, world, make_distributed_rows, tight(), {}, vertex_order);
  ASSERT_TRUE(s.converged()) << s.message;
  EXPECT_LE(s.certificate.worst(), 1e-12);
  EXPECT_EQ(s.stages, (std::vector<std::string>{"assembly", "posing", "full_space"}));
  for (const char* stage : {"setup", "post_process", "release"}) EXPECT_TRUE(s.timings.count(stage)) << stage;
  EXPECT_EQ(engine.released_after_solves, 1) << "the engine's matrix and preconditioner given back once, after its solves";
  const auto rows = process_rows();
  EXPECT_EQ(rows->max(s.certificate.dual), rows->min(s.certificate.dual)) << "one certificate on every process";
  EXPECT_EQ(rows->max(s.energy), rows->min(s.energy)) << "one energy on every process";
  const auto ssn = make_minimizer("ssn");
  const NonsmoothMinimizer* one[] = {ssn.get()};
  BasicContactSolver<dim> condensed(whole ? *whole : problem, factorization(), tight());
  const BasicContactSolution<dim> c = std::move(condensed.run(one).front());
  ASSERT_TRUE(c.converged()) << c.message;
  if (also) also(s, c);
  EXPECT_EQ(s.unknowns, c.unknowns);
  EXPECT_NEAR(s.energy, c.energy, 1e-9 * std::abs(c.energy));
  // every process holds the whole solution, the same on each
  ASSERT_EQ(rows->max(static_cast<double>(s.u.size())), rows->min(static_cast<double>(s.u.size())));
  EXPECT_EQ(rows->max(s.u.sum()), rows->min(s.u.sum()));
  EXPECT_EQ(rows->max(static_cast<double>(s.contact.size())), rows->min(static_cast<double>(s.contact.size())));
  const double scale = c.u.cwiseAbs().maxCoeff();
  ASSERT_EQ(s.u.size(), c.u.size());
  EXPECT_LE((s.u - c.u).cwiseAbs().maxCoeff(), 1e-8 * scale);
  ASSERT_EQ(s.contact.size(), c.contact.size());
  double force = 0.0;
  for (const auto& node : c.contact) force = std::max(force, std::abs(node.force()));
  ASSERT_GT(force, 0.0);
  for (std::size_t i = 0; i < c.contact.size(); ++i) {
    SCOPED_TRACE("contact node " + std::to_string(i));
    EXPECT_EQ(s.contact[i].vertex, c.contact[i].vertex);
    EXPECT_NEAR(s.contact[i].u_nu, c.contact[i].u_nu, 1e-8 * scale);
    EXPECT_NEAR(s.contact[i].force(), c.contact[i].force(), 1e-8 * force);
    EXPECT_NEAR(s.contact[i].reaction, c.contact[i].reaction, 1e-8 * force);
    EXPECT_EQ(s.contact[i].friction_state, c.contact[i].friction_state);
    EXPECT_LE((s.contact[i].friction_vector - c.contact[i].friction_vector).norm(), 1e-8 * force);
  }
  EXPECT_LE((s.forces.contact - c.forces.contact).norm(), 1e-8 * force * static_cast<double>(c.contact.size()));
  EXPECT_LE((s.forces.applied - c.forces.applied).norm(), 1e-12 * std::max(1.0, c.forces.applied.norm()));
  ASSERT_EQ(s.forces.reactions.size(), c.forces.reactions.size());
  for (std::size_t k = 0; k < c.forces.reactions.size(); ++k)
    EXPECT_LE((s.forces.reactions[k].force - c.forces.reactions[k].force).norm(),
              1e-8 * std::max(1.0, c.forces.reactions[k].force.norm()));
}

TEST(FullSpaceMpi, TheCommandsSolveAcrossProcessesIsTheCondensedAnswerInThePlane) {
  const Mesh mesh = make_squares(16);
  expect_shares_solve_as_the_condensed_route<2>(example_4_1(mesh));
}

TEST(FullSpaceMpi, TheCommandsSolveAcrossProcessesIsTheCondensedAnswerInTheSolid) {
  const Mesh3D mesh = make_cubes({5, 5, 5});
  expect_shares_solve_as_the_condensed_route<3>(test::example_4_1_3d(mesh));
}

// A mesh whose vertices are numbered at random (`scrambled`, as a Gmsh file's or a refined
// mesh's may be; `slabs` the same problem on the mesh numbered as generated, in slabs), shared
// along its Hilbert order: the condensed answer, and each process's share reads about as few of
// the other processes' unknowns (its ghosts) as a slab does, where a share of the scrambled
// mesh's own order reads nearly all of them.
template <int dim, class Problem>
void expect_scrambled_mesh_shared_along_its_order(const Problem& scrambled, const Problem& slabs) {
  const MeshOf<dim>& mesh = *scrambled.elasticity.mesh;
  const std::vector<int> order = hilbert_vertex_order(mesh);
  expect_shares_solve_as_the_condensed_route<dim, Problem>(scrambled, {}, nullptr, order);
  const ProcessWorld world = krylov_world();
  const auto [first, end] = vertex_share(mesh.num_vertices(), world.rank, world.size);
  const PosedShare compact = pose_share(scrambled, order, first, end);
  const PosedShare scattered = pose_share(scrambled, first, end);
  const PosedShare slab = pose_share(slabs, first, end);
  const auto ghosts = [](const PosedShare& s) { return static_cast<double>(s.layout.ghosts.size()); };
  // 10^3 cubes on 2 to 4 processes: 381 to 567 ghosts along the order, 327 to 654 of a slab,
  // 2 121 to 2 484 along the scrambled numbering
  if (world.size > 1) {
    EXPECT_GT(ghosts(compact), 0.0);
    EXPECT_LE(ghosts(compact), 2.0 * ghosts(slab)) << "the slab's " << ghosts(slab);
    EXPECT_GT(ghosts(scattered), 0.8 * static_cast<double>(scattered.layout.global - scattered.layout.owned));
  }
}

TEST(FullSpaceMpi, AScrambledSolidSharedAlongItsHilbertOrderIsTheCondensedAnswer) {
  const Mesh3D slabs = make_cubes({10, 10, 10});
  const Mesh3D scrambled = test::scrambled(slabs);
  expect_scrambled_mesh_shared_along_its_order<3>(test::example_4_1_3d(scrambled), test::example_4_1_3d(slabs));
}

TEST(FullSpaceMpi, AScrambledPlaneMeshSharedAlongItsHilbertOrderIsTheCondensedAnswer) {
  const Mesh slabs = make_squares(32);
  const Mesh scrambled = test::scrambled(slabs);
  expect_scrambled_mesh_shared_along_its_order<2>(example_4_1(scrambled), example_4_1(slabs));
}

// The estimate of the processes' pieces (`mine` on each process's piece `where`) is the whole
// mesh's (`all`) to the bit, on every process.
template <int dim, class Problem>
void expect_estimate_of_pieces(const Problem& mine, const Problem& all, const BasicContactSolution<dim>& s,
                               const PieceOfMesh& where) {
  const auto rows = process_rows();
  const ErrorEstimate pieces = estimate_error_of_pieces<dim>(mine, s, where, *rows);
  const ErrorEstimate whole = estimate_error(all, s);
  EXPECT_EQ(pieces.energy, whole.energy);
  EXPECT_EQ(pieces.norm, whole.norm);
  EXPECT_EQ(pieces.parts, whole.parts);
  EXPECT_EQ(pieces.indicators, whole.indicators);
  EXPECT_GT(pieces.energy, 0.0);
}

// Each process makes only its piece of the mesh (its vertices' cells, the named sides' and the
// first column, hemivem/mesh/box_piece.hpp) and solves its share from it: the condensed route's
// answer on the whole mesh, the balance of forces added up over the processes' vertices.
/// The unit square on 16 x 16 squares, whole, and this process's piece of it (its vertices,
/// every side), which leaves cells out on more than one process.
struct PlanePiece {
  GridSize n{16, 16};
  BoxPiece box;
  Mesh whole, piece;
};

PlanePiece plane_piece() {
  const ProcessWorld world = krylov_world();
  PlanePiece p;
  p.whole = make_squares(p.n);
  const auto [first, end] = vertex_share(p.whole.num_vertices(), world.rank, world.size);
  p.box = BoxPiece{first, end, {"left", "right", "top", "bottom"}};
  p.piece = make_mesh_piece("squares", p.n, Rectangle{}, p.box);
  if (world.size > 1) EXPECT_LT(p.piece.num_elements(), p.whole.num_elements());
  return p;
}

TEST(FullSpaceMpi, EachProcessMakesOnlyItsPieceOfTheMeshInThePlane) {
  const PlanePiece p = plane_piece();
  const ContactProblem mine = example_4_1(p.piece), all = example_4_1(p.whole);
  const PieceOfMesh where{piece_cells("squares", p.n, p.box), p.whole.num_elements(), p.box.first_vertex,
                          p.box.end_vertex};
  expect_shares_solve_as_the_condensed_route<2>(
      mine, [&](const ContactSolution& s, const ContactSolution&) { expect_estimate_of_pieces<2>(mine, all, s, where); },
      &all);
}

// in the solid, with a body force: the applied load of the processes' vertices added up
TEST(FullSpaceMpi, EachProcessMakesOnlyItsPieceOfTheMeshInTheSolid) {
  const ProcessWorld world = krylov_world();
  const GridSize3 n(4, 3, 9);
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  for (const std::string generator : {"cubes", "tetrahedra"}) {
    SCOPED_TRACE(generator);
    const Mesh3D whole = make_mesh3d(generator, n, domain);
    const auto [first, end] = vertex_share(whole.num_vertices(), world.rank, world.size);
    const Mesh3D piece = make_mesh3d_piece(generator, n, domain, BoxPiece{first, end, {"x0", "x1", "top", "bottom"}});
    ContactProblem3D mine = test::example_4_1_3d(piece), all = test::example_4_1_3d(whole);
    for (ContactProblem3D* p : {&mine, &all}) p->elasticity.body_force = [](const Vec3&) { return Vec3(0.5, 0.0, -2.0); };
    const PieceOfMesh where{piece_cells(generator, n, BoxPiece{first, end, {"x0", "x1", "top", "bottom"}}),
                            whole.num_cells(), first, end};
    expect_shares_solve_as_the_condensed_route<3>(
        mine,
        [&](const ContactSolution3D& s, const ContactSolution3D&) { expect_estimate_of_pieces<3>(mine, all, s, where); },
        &all);
  }
}

// a start (an adaptive step's, prolongated from the mesh before): from the answer itself the
// iteration has nothing to do, on every process
TEST(FullSpaceMpi, TheCommandsSolveAcrossProcessesStartsFromADisplacement) {
  const Mesh mesh = make_squares(16);
  const ContactProblem problem = example_4_1(mesh);
  const ProcessWorld world = krylov_world();
  auto krylov = make_krylov_solver("petsc-gamg");
  const ContactSolution s = solve_full_space_shares<2>(problem, *krylov, world, make_distributed_rows, tight());
  ASSERT_TRUE(s.converged()) << s.message;
  ASSERT_GT(s.iterations(), 2);
  const ContactSolution again =
      solve_full_space_shares<2>(problem, *krylov, world, make_distributed_rows, tight(), s.u);
  ASSERT_TRUE(again.converged()) << again.message;
  EXPECT_EQ(again.iterations(), 0) << "the start is the answer";
  EXPECT_LE((again.u - s.u).cwiseAbs().maxCoeff(), 1e-12 * s.u.cwiseAbs().maxCoeff());
}

// a posing one process refuses (its problem, as its piece of a mesh may be, its own: here held by
// nothing) ends every process before the rows are distributed: that process with its error, the
// others with an InputError naming it and its message, none waiting for it
TEST(FullSpaceMpi, APosingOneProcessRefusesEndsEveryProcess) {
  const Mesh mesh = make_squares(12);
  const ProcessWorld world = krylov_world();
  const int refusing = world.size > 1 ? 1 : 0;
  ContactProblem p = example_4_1(mesh);
  if (world.rank == refusing) p.elasticity.dirichlet.clear();
  auto krylov = make_krylov_solver("petsc-gamg");
  std::string message;
  try {
    FullSpaceShares<2> shares(p, *krylov, world, make_distributed_rows);
    ADD_FAILURE() << "posed";
  } catch (const InputError& e) {
    message = e.what();
  }
  const auto prefix = [&](int rank) {
    return rank == refusing ? std::string() : "process " + std::to_string(refusing) + " stopped: ";
  };
  EXPECT_EQ(message.rfind(prefix(world.rank), 0), 0u) << message;
  EXPECT_NE(message.find("free"), std::string::npos) << message;
  // the same refusal on every process
  const Eigen::VectorXd lengths = process_rows()->all_gather(Eigen::VectorXd::Constant(1, static_cast<double>(message.size())));
  for (int rank = 0; rank < world.size; ++rank)
    EXPECT_EQ(lengths(rank) - static_cast<double>(prefix(rank).size()), lengths(refusing)) << "process " << rank;
  // and the processes go on together
  EXPECT_FALSE(FullSpaceShares<2>(example_4_1(mesh), *krylov, world, make_distributed_rows).load_is_zero());
}

// a bilateral part: the reactions of its tied rows come from the gathered residual
TEST(FullSpaceMpi, TheCommandsSolveAcrossProcessesGathersTheTiedReactions) {
  const Mesh mesh = make_squares(12);
  ContactProblem p = example_4_1(mesh);
  p.parts.front().constraint = ConstraintKind::bilateral;
  const ProcessWorld world = krylov_world();
  auto krylov = make_krylov_solver("petsc-gamg");
  // only a bilateral node's normal force reads the residual, which is then gathered
  EXPECT_TRUE(FullSpaceShares<2>(p, *krylov, world, make_distributed_rows).contact_reads_residual());
  EXPECT_FALSE(FullSpaceShares<2>(example_4_1(mesh), *krylov, world, make_distributed_rows).contact_reads_residual());
  expect_shares_solve_as_the_condensed_route<2>(p);
}

// a solid's Tresca friction, groups of two tangential coordinates: a block whose top is moved
// sideways and down (its x-sides carrying the shear traction) onto a one-sided foundation that
// lets go of part of the bottom, so that nodes slip and nodes stick. Its two layers of cells
// make the processes' slabs of vertices split the contact surface: a process reads the unknowns
// of another's groups, whose frames it rotates its columns into.
const Box kBlock{0.0, 1.0, 0.0, 1.0, 0.0, 0.5};

/// The friction tests' block on `mesh` (kBlock's cubes): its top held at `top`, its bottom on a
/// foundation of stiffness 2000 with friction (the part named "foundation", facets set here).
ContactProblem3D block_on_foundation(const Mesh3D& mesh, VectorField3 top, ContactPart3D foundation) {
  ContactProblem3D problem;
  problem.elasticity.mesh = &mesh;
  problem.elasticity.materials = MaterialTable(Material{100.0, 0.3}, PlaneModel::strain);
  problem.elasticity.dirichlet.push_back({select_box_side(mesh, kBlock, "top"), std::move(top), {true, true, true}, "top"});
  foundation.name = "foundation";
  foundation.facets = select_box_side(mesh, kBlock, "bottom");
  foundation.law = linear_law(2000.0);
  problem.parts.push_back(std::move(foundation));
  return problem;
}

TEST(FullSpaceMpi, TheCommandsSolveAcrossProcessesIsTheCondensedAnswerWithASolidsFriction) {
  const Mesh3D mesh = make_cubes({6, 6, 2}, kBlock);
  ContactPart3D foundation;
  foundation.constraint = ConstraintKind::one_sided;
  foundation.gap = [](const Vec3& x) { return 0.0005 * x.x(); };
  foundation.friction = tresca_law(0.8);
  ContactProblem3D problem =
      block_on_foundation(mesh, [](const Vec3&) { return Vec3(0.01, 0.003, -0.004); }, std::move(foundation));
  for (const auto& [side, sign] : {std::pair{"x0", -1.0}, std::pair{"x1", 1.0}}) {
    TractionLoad3D t;
    t.facets = select_box_side(mesh, kBlock, side);
    t.traction = [s = sign](const Vec3&) { return Vec3(0, 0, s * 0.1); };
    problem.elasticity.tractions.push_back(t);
  }
  expect_shares_solve_as_the_condensed_route<3>(problem, [](const BasicContactSolution<3>& s,
                                                             const BasicContactSolution<3>& c) {
    int slip = 0, stick = 0;
    for (const auto& node : c.contact) {
      slip += node.friction_state == FrictionState::slip ? 1 : 0;
      stick += node.friction_state == FrictionState::stick ? 1 : 0;
    }
    EXPECT_GT(slip, 0);
    EXPECT_GT(stick, 0);
    // the Newton systems are those of the whole problem: about as many iterations as the
    // condensed route's (11); with the ghost columns left out of the groups' frames, 19
    EXPECT_LE(s.iterations(), c.iterations() + 4) << c.iterations() << " iterations of the condensed route";
  });
}

// Two bodies joined at their contact: the upper pressed down and sideways by its top, the lower
// clamped at its bottom, the interface one-sided (and with Tresca friction). Each process joins its
// own rows with the rows of the pairs' nodes across from its vertices; the slabs of vertices split
// the bodies (the upper's are numbered first, its contact layer at their start), so that a process
// owns the vertices across from nodes another owns.
std::string stacked(int dim, const std::string& contact, const std::string& supports = "") {
  test::StackedBodies b;
  b.dim = dim;
  b.n = dim == 2 ? "[8, 4]" : "[4, 4, 3]";
  b.top = dim == 2 ? "[0.004, -0.01]" : "[0.004, 0.002, -0.01]";
  b.supports = supports;
  b.contact = contact;
  return test::stacked_bodies(b);
}

/// The lower body clamped on its side x0 too, which reaches the interface.
const std::string kSideClamped = ", {side = \"x0\", value = [0.0, 0.001, 0.0]}";

TEST(FullSpaceMpi, TwoJoinedPlaneBodiesAcrossProcessesAreTheCondensedAnswer) {
  const auto two = build_problem<2>(parse_scene_string(stacked(2, ""), "two-blocks.toml"));
  expect_shares_solve_as_the_condensed_route<2>(two->problem);
}

// the lower body clamped on a side reaching the interface: pairs' nodes free where the vertex
// across is prescribed, whose joined load takes the system's columns there
TEST(FullSpaceMpi, TwoJoinedSolidsWithAShiftedLoadAcrossProcessesAreTheCondensedAnswer) {
  const auto two = build_problem<3>(parse_scene_string(stacked(3, "", kSideClamped), "two-solids.toml"));
  expect_shares_solve_as_the_condensed_route<3>(two->problem);
  // shared along the mesh's Hilbert order: each process joins the pairs' nodes of its own order
  expect_shares_solve_as_the_condensed_route<3, ContactProblem3D>(two->problem, {}, nullptr,
                                                                  hilbert_vertex_order(two->mesh));
}

// the same along a proportional path: each step's load and prescribed values (the shift with
// them) set on the posed shares; every step's energy and contact, and the last displacement
TEST(FullSpaceMpi, APathOfTwoJoinedSolidsWithAShiftedLoadAcrossProcessesIsTheCondensedRoutes) {
  const auto two = build_problem<3>(
      parse_scene_string(stacked(3, "friction = {law = \"tresca\", bound = 0.004}\n", kSideClamped), "two-solids.toml"));
  BasicPathOptions<3> across;
  across.minimizer = tight();
  across.distribute = make_distributed_rows;
  across.world = krylov_world();
  across.frame = [](int) { return true; };
  BasicPathOptions<3> alone = across;
  alone.distribute = nullptr;
  alone.world = ProcessWorld{};
  const auto ssn = make_minimizer("ssn");
  const BasicPathLoading<3> loading{{0.5, 1.0, 1.5}, {}};
  BasicContactProblem<3> a = two->problem, b = two->problem;
  const BasicPathSolution<3> s = solve_path(a, make_krylov_solver("petsc-gamg"), *ssn, loading, across);
  const BasicPathSolution<3> c = solve_path(b, factorization(), *ssn, loading, alone);
  ASSERT_TRUE(c.converged());
  ASSERT_TRUE(s.converged()) << s.last.message;
  ASSERT_EQ(s.steps.size(), c.steps.size());
  for (std::size_t k = 0; k < c.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    EXPECT_NEAR(s.steps[k].energy, c.steps[k].energy, 1e-8 * std::abs(c.steps[k].energy));
    ASSERT_EQ(s.steps[k].u.size(), c.steps[k].u.size());
    EXPECT_LE((s.steps[k].u - c.steps[k].u).cwiseAbs().maxCoeff(), 1e-8 * c.steps[k].u.cwiseAbs().maxCoeff());
  }
}

// A proportional path's step across processes (FullSpaceShares::scale_load): t times the load the
// shares were posed with, scaled on each process's own rows, is that load set whole (set_load of
// t b and t times the prescribed values): the posed prescribed values to the bit, the point
// found, its residual and energy to round-off. Of one body no rotated load of the whole problem
// is kept.
template <int dim>
void expect_scaled_load_as_the_whole_load_set(const BasicContactProblem<dim>& problem) {
  const ProcessWorld world = krylov_world();
  const LinearSystem whole = assemble(problem.elasticity);
  auto first = make_krylov_solver("petsc-gamg"), second = make_krylov_solver("petsc-gamg");
  FullSpaceShares<dim> scaled(problem, *first, world, make_distributed_rows);
  FullSpaceShares<dim> set(problem, *second, world, make_distributed_rows);
  const bool joined = scaled.posed().joins_bodies();
  ASSERT_GT(whole.dofs.prescribed_values().cwiseAbs().maxCoeff(), 0.0) << "prescribed values to scale";
  for (const double t : {0.5, 1.5}) {
    SCOPED_TRACE("t = " + std::to_string(t));
    scaled.scale_load(t);
    set.set_load(t * whole.b, t * whole.dofs.prescribed());
    EXPECT_TRUE(scaled.posed().dof_map().prescribed_values().cwiseEqual(set.posed().dof_map().prescribed_values()).all());
    if (!joined) {
      EXPECT_EQ(scaled.posed().rotated_load().size(), 0);
      EXPECT_EQ(set.posed().rotated_load().size(), 0);
    }
    EXPECT_FALSE(scaled.load_is_zero());
    const auto a = scaled.minimize(scaled.posed().reduced(), scaled.posed().origin(), tight());
    const auto b = set.minimize(set.posed().reduced(), set.posed().origin(), tight());
    ASSERT_TRUE(a.result.converged()) << a.result.message;
    // each process holds its own rows of the point, nothing of the whole problem
    const RowDistribution& rows = scaled.distribution();
    ASSERT_EQ(a.x.size(), rows.layout().owned);
    ASSERT_EQ(a.residual.size(), rows.layout().owned);
    ASSERT_EQ(b.x.size(), set.distribution().layout().owned);
    ASSERT_EQ(rows.layout().first, set.distribution().layout().first);
    // two solves of the same load by two engines' preconditioners: the same point to round-off
    const double scale = rows.max(b.x.cwiseAbs().maxCoeff());
    ASSERT_GT(scale, 0.0);
    EXPECT_LE((a.x - b.x).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_LE((a.residual - b.residual).cwiseAbs().maxCoeff(), 1e-12 * rows.max(b.residual.cwiseAbs().maxCoeff()) + 1e-300);
    EXPECT_NEAR(a.quadratic, b.quadratic, 1e-12 * std::abs(b.quadratic));
    // and the displacement holds the scaled prescribed values
    const Eigen::VectorXd u = scaled.posed().displacement_of(rows.all_gather(a.x));
    for (int k = 0; k < whole.dofs.num_dofs(); ++k)
      if (whole.dofs.free_index(k) < 0) ASSERT_EQ(u(k), t * whole.dofs.prescribed_value(k));
  }
  scaled.scale_load(0.0);
  EXPECT_TRUE(scaled.load_is_zero());
  EXPECT_FALSE(set.load_is_zero());
}

// a block between rollers, one of them pushing, pressed on its top onto a linear foundation
TEST(FullSpaceMpi, AScaledLoadIsTheWholeLoadSetInThePlane) {
  const auto block = build_problem<2>(parse_scene_string(R"(schema_version = 1
[mesh]
generator = "squares"
n = [12, 6]
domain = [0.0, 2.0, 0.0, 1.0]
[material]
E = 100.0
nu = 0.3
[[dirichlet]]
side = "left"
ux = 0.002
[[dirichlet]]
side = "right"
ux = 0.0
[[loads.traction]]
side = "top"
value = [0.0, -2.0]
[contact]
side = "bottom"
law = "linear"
constraint = "none"
[contact.parameters]
stiffness = 50.0
)", "pushed-block.toml"));
  expect_scaled_load_as_the_whole_load_set<2>(block->problem);
}

TEST(FullSpaceMpi, AScaledLoadIsTheWholeLoadSetInTheSolid) {
  const Mesh3D mesh = make_cubes({6, 6, 6});
  expect_scaled_load_as_the_whole_load_set<3>(test::pressed_block(mesh, Box{}));
}

TEST(FullSpaceMpi, AScaledLoadIsTheWholeLoadSetOfTwoJoinedSolids) {
  const auto two = build_problem<3>(parse_scene_string(stacked(3, "", kSideClamped), "two-solids.toml"));
  expect_scaled_load_as_the_whole_load_set<3>(two->problem);
}

TEST(FullSpaceMpi, TwoJoinedSolidsWithFrictionAcrossProcessesAreTheCondensedAnswer) {
  const auto two = build_problem<3>(
      parse_scene_string(stacked(3, "friction = {law = \"tresca\", bound = 0.004}\n"), "two-solids.toml"));
  expect_shares_solve_as_the_condensed_route<3>(two->problem, [](const BasicContactSolution<3>&,
                                                                  const BasicContactSolution<3>& c) {
    int slip = 0, stick = 0;
    for (const auto& node : c.contact) {
      slip += node.friction_state == FrictionState::slip ? 1 : 0;
      stick += node.friction_state == FrictionState::stick ? 1 : 0;
    }
    EXPECT_GT(slip + stick, 0) << "the bodies touch";
  });
}

/// The path of `mine` across the processes (PathOptions::distribute, petsc-gamg) and of `all` in
/// one process on the condensed route (Eigen's factorization), both with ssn to a tight
/// tolerance and `both` applied to their options.
template <int dim, class Problem>
std::pair<BasicPathSolution<dim>, BasicPathSolution<dim>> paths_across_and_alone(
    Problem& mine, Problem& all, BasicPathLoading<dim> loading,
    const std::function<void(BasicPathOptions<dim>&)>& both = {}, const std::vector<int>& vertex_order = {}) {
  const auto ssn = make_minimizer("ssn");
  BasicPathOptions<dim> across, alone;
  for (BasicPathOptions<dim>* o : {&across, &alone}) {
    o->minimizer = tight();
    if (both) both(*o);
  }
  across.distribute = make_distributed_rows;
  across.world = krylov_world();
  across.vertex_order = vertex_order;
  return {solve_path(mine, make_krylov_solver("petsc-gamg"), *ssn, loading, across),
          solve_path(all, factorization(), *ssn, std::move(loading), alone)};
}

// A loading path across processes (PathOptions::distribute): each process poses its share once
// and solves it at every step, the path's own work (the fixed point on a Coulomb bound, the
// steps' contact tables) done alike on every process. Against the condensed route's path
// (Eigen's factorization and ssn) at every step: the contact unknowns, forces and friction states,
// the energy, the fixed point's convergence, and the last displacement, on every process.
template <int dim, class Problem>
void expect_path_across_processes_as_the_condensed_route(Problem& problem, BasicPathLoading<dim> loading,
                                                         const std::vector<int>& vertex_order = {}) {
  const auto [s, c] = paths_across_and_alone<dim>(problem, problem, std::move(loading), {}, vertex_order);
  ASSERT_TRUE(c.converged());
  ASSERT_TRUE(s.converged()) << s.last.message;
  ASSERT_EQ(s.steps.size(), c.steps.size());
  EXPECT_EQ(s.last.stages, (std::vector<std::string>{"assembly", "posing", "path"}));
  bool slip = false, stick = false;
  for (std::size_t k = 0; k < c.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    const auto &a = s.steps[k], &b = c.steps[k];
    EXPECT_TRUE(a.fixed_point.used && a.fixed_point.converged);
    EXPECT_LE(a.certificate.worst(), 1e-10);
    EXPECT_NEAR(a.energy, b.energy, 1e-8 * std::abs(b.energy));
    ASSERT_EQ(a.contact.size(), b.contact.size());
    double scale = 0.0, force = 0.0;
    for (const auto& node : b.contact) {
      scale = std::max({scale, std::abs(node.u_nu), node.u_tangential.norm()});
      force = std::max(force, std::abs(node.force()));
    }
    ASSERT_GT(force, 0.0);
    for (std::size_t i = 0; i < b.contact.size(); ++i) {
      SCOPED_TRACE("contact node " + std::to_string(i));
      EXPECT_NEAR(a.contact[i].u_nu, b.contact[i].u_nu, 1e-8 * scale);
      EXPECT_LE((a.contact[i].u_tangential - b.contact[i].u_tangential).norm(), 1e-8 * scale);
      EXPECT_NEAR(a.contact[i].force(), b.contact[i].force(), 1e-8 * force);
      EXPECT_EQ(a.contact[i].friction_state, b.contact[i].friction_state);
      EXPECT_LE((a.contact[i].friction_vector - b.contact[i].friction_vector).norm(), 1e-8 * force);
      slip = slip || (b.contact[i].friction_state == FrictionState::slip && b.contact[i].force() > 0.0);
      stick = stick || (b.contact[i].friction_state == FrictionState::stick && b.contact[i].force() > 0.0);
    }
  }
  EXPECT_TRUE(slip && stick) << "the path lets nodes stick and slip";
  ASSERT_EQ(s.last.u.size(), c.last.u.size());
  EXPECT_LE((s.last.u - c.last.u).cwiseAbs().maxCoeff(), 1e-8 * c.last.u.cwiseAbs().maxCoeff());
}

// A proportional path across processes whose contact part is bilateral: each step's tied nodes
// take their normal forces from the residual, which the processes gather for it (the steps
// before the last are no frames, and their displacement is not gathered). Against the
// condensed route's path at every step.
template <int dim, class Problem>
void expect_tied_reactions_of_each_step_as_the_condensed_route(Problem& problem) {
  BasicPathLoading<dim> loading;
  loading.t = {0.5, 1.0, 1.5};
  const auto [s, c] = paths_across_and_alone<dim>(problem, problem, loading);
  ASSERT_TRUE(c.converged());
  ASSERT_TRUE(s.converged()) << s.last.message;
  ASSERT_EQ(s.steps.size(), c.steps.size());
  for (std::size_t k = 0; k < c.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    const auto &a = s.steps[k], &b = c.steps[k];
    EXPECT_EQ(a.u.size() > 0, k + 1 == c.steps.size()) << "the last step alone is a frame";
    EXPECT_NEAR(a.energy, b.energy, 1e-8 * std::abs(b.energy));
    ASSERT_EQ(a.contact.size(), b.contact.size());
    double force = 0.0;
    for (const auto& node : b.contact) force = std::max(force, std::abs(node.reaction));
    ASSERT_GT(force, 0.0) << "the tied nodes carry forces";
    for (std::size_t i = 0; i < b.contact.size(); ++i) {
      SCOPED_TRACE("contact node " + std::to_string(i));
      ASSERT_EQ(b.contact[i].state, ContactState::tied);
      EXPECT_NEAR(a.contact[i].reaction, b.contact[i].reaction, 1e-8 * force);
    }
  }
  EXPECT_LE((s.last.u - c.last.u).cwiseAbs().maxCoeff(), 1e-8 * c.last.u.cwiseAbs().maxCoeff());
}

TEST(FullSpaceMpi, APathAcrossProcessesGathersEachStepsTiedReactionsInThePlane) {
  const Mesh mesh = make_squares(12);
  ContactProblem problem = example_4_1(mesh);
  problem.parts.front().constraint = ConstraintKind::bilateral;
  expect_tied_reactions_of_each_step_as_the_condensed_route<2>(problem);
}

TEST(FullSpaceMpi, APathAcrossProcessesGathersEachStepsTiedReactionsInTheSolid) {
  const Mesh3D mesh = make_mesh3d("cubes", GridSize3(4, 3, 6), Box{0.0, 1.0, 0.0, 0.5, 0.0, 1.0});
  ContactProblem3D problem = test::example_4_1_3d(mesh);
  problem.parts.front().constraint = ConstraintKind::bilateral;
  expect_tied_reactions_of_each_step_as_the_condensed_route<3>(problem);
}

// Example 4.1 pressed, then sheared along the top, on a Coulomb foundation (friction-coulomb.toml)
TEST(FullSpaceMpi, ACoulombPathAcrossProcessesIsTheCondensedRoutesInThePlane) {
  const Mesh mesh = make_squares(12);
  ContactProblem problem = example_4_1(mesh);
  problem.parts.front().friction = tresca_law(1.0);
  problem.parts.front().friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
  PathLoading loading;
  loading.t = {0.5, 1.0, 1.5, 2.0};
  const auto top = problem.elasticity.tractions;
  loading.update = [top](double t, ContactProblem& p) {
    p.elasticity.tractions = top;
    for (auto& traction : p.elasticity.tractions)
      traction.traction = [t](const Vec2&) { return Vec2(4.0 * std::max(t - 1.0, 0.0), -8.0 * std::min(t, 1.0)); };
  };
  loading.updates_prescribed = false;
  loading.updates_gaps = false;
  expect_path_across_processes_as_the_condensed_route<2>(problem, loading);
}

// a block on `mesh` (kBlock's cubes) pressed onto a Coulomb foundation, then dragged by its top
// (groups of two tangential coordinates, split between the processes), the processes sharing
// the vertices along `vertex_order` (empty: the mesh's own)
void expect_coulomb_block_path_as_the_condensed_routes(const Mesh3D& mesh, const std::vector<int>& vertex_order) {
  const auto top_at = [](double t) {
    return [t](const Vec3&) {
      return Vec3(0.01 * std::max(t - 1.0, 0.0), 0.003 * std::max(t - 1.0, 0.0), -0.004 * std::min(t, 1.0));
    };
  };
  ContactPart3D foundation;
  foundation.constraint = ConstraintKind::none;
  foundation.friction = tresca_law(1.0);
  foundation.friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
  ContactProblem3D problem = block_on_foundation(mesh, top_at(0.5), std::move(foundation));
  BasicPathLoading<3> loading;
  loading.t = {0.5, 1.0, 1.5, 2.0};
  loading.update = [top_at](double t, ContactProblem3D& p) { p.elasticity.dirichlet.front().value = top_at(t); };
  loading.updates_gaps = false;
  expect_path_across_processes_as_the_condensed_route<3>(problem, loading, vertex_order);
}

TEST(FullSpaceMpi, ACoulombPathAcrossProcessesIsTheCondensedRoutesInTheSolid) {
  expect_coulomb_block_path_as_the_condensed_routes(make_cubes({6, 6, 2}, kBlock), {});
}

// the same on the block's cubes numbered at random, shared along the mesh's Hilbert order
TEST(FullSpaceMpi, ACoulombPathOnAScrambledSolidAlongItsHilbertOrderIsTheCondensedRoutes) {
  const Mesh3D mesh = test::scrambled(make_cubes({6, 6, 2}, kBlock));
  expect_coulomb_block_path_as_the_condensed_routes(mesh, hilbert_vertex_order(mesh));
}

// A loading path on the processes' pieces of the mesh (a body force: the cells a piece lacks
// carry load), every step a frame: against the condensed route's path on the whole mesh, each
// step's applied resultant and its frame's balance of forces (each process summing its own
// vertices, FullSpaceShares::applied and balance), the contact and the last displacement.
template <int dim, class Problem>
void expect_path_on_pieces_as_the_condensed_route(Problem& mine, Problem& all, BasicPathLoading<dim> loading) {
  const auto [s, c] = paths_across_and_alone<dim>(mine, all, std::move(loading),
                                                  [](BasicPathOptions<dim>& o) { o.frame = [](int) { return true; }; });
  ASSERT_TRUE(c.converged());
  ASSERT_TRUE(s.converged()) << s.last.message;
  ASSERT_EQ(s.steps.size(), c.steps.size());
  for (std::size_t k = 0; k < c.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    const auto &a = s.steps[k], &b = c.steps[k];
    const double load = b.applied.norm();
    ASSERT_GT(load, 0.0);
    EXPECT_LE((a.applied - b.applied).norm(), 1e-12 * load);
    ASSERT_TRUE(a.forces && b.forces);
    EXPECT_LE((a.forces->applied - b.forces->applied).norm(), 1e-12 * load);
    ASSERT_EQ(a.forces->reactions.size(), b.forces->reactions.size());
    for (std::size_t r = 0; r < b.forces->reactions.size(); ++r)
      EXPECT_LE((a.forces->reactions[r].force - b.forces->reactions[r].force).norm(), 1e-8 * load);
    EXPECT_LE((a.forces->contact - b.forces->contact).norm(), 1e-8 * load);
    EXPECT_LE(a.forces->residual(), 1e-8);
    ASSERT_EQ(a.contact.size(), b.contact.size());
    double scale = 0.0;
    for (const auto& node : b.contact) scale = std::max(scale, std::abs(node.u_nu));
    for (std::size_t i = 0; i < b.contact.size(); ++i) EXPECT_NEAR(a.contact[i].u_nu, b.contact[i].u_nu, 1e-8 * scale);
    ASSERT_EQ(a.u.size(), b.u.size());
    EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), 1e-8 * b.u.cwiseAbs().maxCoeff());
  }
}

// a path its caller stops after the second of three steps: that step's displacement is made
// then, and its balance of forces summed over the processes' vertices of their pieces, as the
// condensed route's path on the whole mesh stopped there
TEST(FullSpaceMpi, APathOnPiecesStoppedByItsCallerBalancesTheStepItStoppedAt) {
  const PlanePiece p = plane_piece();
  ContactProblem mine = example_4_1(p.piece), all = example_4_1(p.whole);
  for (ContactProblem* q : {&mine, &all}) q->elasticity.body_force = [](const Vec2&) { return Vec2(0.5, -2.0); };
  PathLoading loading;
  loading.t = {0.5, 1.0, 1.25};
  const auto [s, c] = paths_across_and_alone<2>(mine, all, loading, [](PathOptions& o) {
    o.on_step = [](const PathStep& step) { return step.index < 2; };
  });
  ASSERT_EQ(c.steps.size(), 2u);
  ASSERT_EQ(s.steps.size(), 2u);
  const PathStep &a = s.steps.back(), &b = c.steps.back();
  ASSERT_TRUE(a.converged() && b.converged());
  ASSERT_EQ(a.u.size(), b.u.size());
  EXPECT_LE((a.u - b.u).cwiseAbs().maxCoeff(), 1e-8 * b.u.cwiseAbs().maxCoeff());
  ASSERT_TRUE(a.forces && b.forces);
  const double load = b.forces->applied.norm();
  ASSERT_GT(load, 0.0);
  EXPECT_LE((a.forces->applied - b.forces->applied).norm(), 1e-12 * load);
  EXPECT_LE((a.forces->contact - b.forces->contact).norm(), 1e-8 * load);
  EXPECT_LE(a.forces->residual(), 1e-8);
}

// proportional: the load at t = 1 gathered from the processes' rows, its resultant summed over them
TEST(FullSpaceMpi, APathOnThePiecesOfTheMeshIsTheCondensedRoutesInThePlane) {
  const PlanePiece p = plane_piece();
  ContactProblem mine = example_4_1(p.piece), all = example_4_1(p.whole);
  for (ContactProblem* q : {&mine, &all}) q->elasticity.body_force = [](const Vec2&) { return Vec2(0.5, -2.0); };
  PathLoading loading;
  loading.t = {0.5, 1.0, 1.25};
  expect_path_on_pieces_as_the_condensed_route<2>(mine, all, loading);
}

// a body force that grows with t (each step's load assembled on the piece and its resultant
// summed over the processes' vertices)
TEST(FullSpaceMpi, APathOnThePiecesOfTheMeshIsTheCondensedRoutesInTheSolid) {
  const ProcessWorld world = krylov_world();
  const GridSize3 n(4, 3, 9);
  const Box domain{0.0, 1.0, 0.0, 0.5, 0.0, 1.0};
  const Mesh3D whole = make_mesh3d("cubes", n, domain);
  const auto [first, end] = vertex_share(whole.num_vertices(), world.rank, world.size);
  const Mesh3D piece = make_mesh3d_piece("cubes", n, domain, BoxPiece{first, end, {"x0", "x1", "top", "bottom"}});
  // the first slab's piece leaves boxes out (a middle one of three may hold them all)
  if (world.size > 1 && world.rank == 0) EXPECT_LT(piece.num_cells(), whole.num_cells());
  ContactProblem3D mine = test::example_4_1_3d(piece), all = test::example_4_1_3d(whole);
  BasicPathLoading<3> loading;
  loading.t = {0.5, 1.0, 2.0};
  loading.update = [](double t, ContactProblem3D& p) {
    p.elasticity.body_force = [t](const Vec3&) { return Vec3(0.5 * t, 0.0, -4.0 * t); };
  };
  loading.updates_prescribed = false;
  loading.updates_gaps = false;
  expect_path_on_pieces_as_the_condensed_route<3>(mine, all, loading);
}

}  // namespace

int main(int argc, char** argv) {
  return hemivem::test::run_tests_on_every_process(argc, argv, "the distributed full-space route");
}
