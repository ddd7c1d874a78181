// The Krylov engines of the full-space route (hemivem/krylov_solver.hpp), every one built: a
// three-dimensional elasticity matrix assembled by hemivem's VEM on a cube clamped on one face,
// solved to rtol 1e-10 against Eigen's SimplicialLDLT, with the residual each engine reports
// checked against one computed here; the rigid motions as GAMG's near-null space; an indefinite
// matrix; a start that is already the solution; and the factory's names.
#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>

#include "linear_support.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace hemivem {
namespace {

/// The elastic cube of n^3 boxes clamped on its face x = 0 and pulled on its face x = 1, its
/// free dofs' system, and the six rigid motions at the free dofs (translations along x, y, z,
/// rotations about the axes through the cube's center).
struct ClampedCube {
  LinearSystem system;
  Eigen::MatrixXd rigid_motions;
  Eigen::VectorXd reference;  ///< SimplicialLDLT's solution of A u = b
};

const ClampedCube& clamped_cube(int n) {
  static std::map<int, ClampedCube> cache;
  const auto found = cache.find(n);
  if (found != cache.end()) return found->second;
  const Mesh3D mesh = make_cubes(n);
  const Box box;
  ElasticityProblem3D p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{65.0, 0.29});
  p.dirichlet.push_back({select_box_side(mesh, box, "x0"), {}, {true, true, true}, "x0"});
  p.tractions.push_back({select_box_side(mesh, box, "x1"), [](const Vec3& x) { return Vec3(1.0, x[2], -2.0); }, {}});
  ClampedCube c;
  c.system = assemble(p);
  const int nf = c.system.dofs.num_free();
  c.rigid_motions = Eigen::MatrixXd::Zero(nf, 6);
  for (int k = 0; k < nf; ++k) {
    const int dof = c.system.dofs.free_dof(k);
    const int component = dof % 3;
    const Vec3 x = mesh.vertex(dof / 3) - Vec3(0.5, 0.5, 0.5);
    c.rigid_motions(k, component) = 1.0;
    // e_a x x for the axes a = 0, 1, 2: (0, -z, y), (z, 0, -x), (-y, x, 0).
    const double rotations[3][3] = {{0.0, -x[2], x[1]}, {x[2], 0.0, -x[0]}, {-x[1], x[0], 0.0}};
    for (int a = 0; a < 3; ++a) c.rigid_motions(k, 3 + a) = rotations[a][component];
  }
  const Eigen::SimplicialLDLT<SparseMatrix> ldlt(c.system.A);
  c.reference = ldlt.solve(c.system.b);
  return cache.emplace(n, std::move(c)).first->second;
}

double true_residual(const SparseMatrix& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  return (b - A * x).norm() / b.norm();
}

class KrylovEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(KrylovEngine, SolvesElasticityAsLdlt) {
  const ClampedCube& cube = clamped_cube(6);
  const auto solver = make_krylov_solver(GetParam());
  ASSERT_EQ(solver->name(), GetParam());
  const FactorizationResult setup = solver->compute(cube.system.A, cube.rigid_motions);
  ASSERT_TRUE(setup.ok()) << setup.message;
  Eigen::VectorXd x;  // resized to zeros by solve()
  const KrylovSolveResult r = solver->solve(cube.system.b, &x, 1e-10, 5000);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(x.size(), cube.system.b.size());
  EXPECT_GT(r.iterations, 0);
  EXPECT_LE(r.relative_residual, 1e-10);
  EXPECT_NEAR(r.relative_residual, true_residual(cube.system.A, cube.system.b, x), 1e-12);
  EXPECT_LE(test::relative_error(x, cube.reference), 1e-8);
  RecordProperty("iterations", r.iterations);
}

TEST_P(KrylovEngine, StartAtTheSolutionReturnsAtOnce) {
  const ClampedCube& cube = clamped_cube(6);
  const auto solver = make_krylov_solver(GetParam());
  ASSERT_TRUE(solver->compute(cube.system.A, cube.rigid_motions).ok());
  Eigen::VectorXd x = cube.reference;
  const KrylovSolveResult r = solver->solve(cube.system.b, &x, 1e-10, 5000);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LE(r.iterations, 1);
  EXPECT_LE(r.relative_residual, 1e-10);
  EXPECT_LE(test::relative_error(x, cube.reference), 1e-12);
}

// An engine released solves no more until it computes again, then as it did.
TEST_P(KrylovEngine, AReleasedEngineSolvesAgainOnceItComputes) {
  const ClampedCube& cube = clamped_cube(4);
  const auto solver = make_krylov_solver(GetParam());
  Eigen::VectorXd first, x;
  KrylovSolveResult runs[2];
  for (int run = 0; run < 2; ++run) {
    ASSERT_TRUE(solver->compute(cube.system.A, cube.rigid_motions).ok());
    runs[run] = solver->solve(cube.system.b, run == 0 ? &first : &x, 1e-10, 5000);
    ASSERT_TRUE(runs[run].ok()) << runs[run].message;
    solver->release();
    EXPECT_THROW(solver->solve(cube.system.b, &x, 1e-10, 5000), InternalError);
  }
  solver->release();  // twice: nothing more to give back
  EXPECT_EQ(runs[1].iterations, runs[0].iterations);
  EXPECT_LE(test::relative_error(x, first), 1e-12);
}

TEST_P(KrylovEngine, ZeroRightHandSideGivesZero) {
  const ClampedCube& cube = clamped_cube(2);
  const auto solver = make_krylov_solver(GetParam());
  ASSERT_TRUE(solver->compute(cube.system.A, Eigen::MatrixXd()).ok());
  Eigen::VectorXd x = Eigen::VectorXd::Ones(cube.system.b.size());
  const KrylovSolveResult r = solver->solve(Eigen::VectorXd::Zero(cube.system.b.size()), &x, 1e-10, 100);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.relative_residual, 0.0);
  EXPECT_EQ(x.norm(), 0.0);
}

TEST_P(KrylovEngine, TooFewIterationsIsANumericalFailure) {
  const ClampedCube& cube = clamped_cube(6);
  const auto solver = make_krylov_solver(GetParam());
  ASSERT_TRUE(solver->compute(cube.system.A, cube.rigid_motions).ok());
  Eigen::VectorXd x;
  const KrylovSolveResult r = solver->solve(cube.system.b, &x, 1e-10, 2);
  EXPECT_EQ(r.status, FactorizationStatus::numerical_failure);
  EXPECT_LE(r.iterations, 2);
  EXPECT_GT(r.relative_residual, 1e-10);
  EXPECT_NE(r.message.find(GetParam()), std::string::npos) << r.message;
}

/// *H = the cube's A (compressed), `solver` computed on it and one solve run: the first system
/// of a Newton iteration, whose values the caller then changes in place.
void first_system(const ClampedCube& cube, KrylovSolver& solver, const KrylovHints& hints, SparseMatrix* H) {
  *H = cube.system.A;
  H->makeCompressed();
  ASSERT_TRUE(solver.compute(*H, hints).ok());
  Eigen::VectorXd x;
  ASSERT_TRUE(solver.solve(cube.system.b, &x, 1e-10, 5000).ok());
}

/// compute(H, hints) again and a solve from zero, its answer against LDL^T's to `tolerance`
/// and its reported residual against the one computed here, within what round-off lets two
/// evaluations of b - H x differ (100 eps (|H| |x| + |b|) relative to ||b||).
KrylovSolveResult solve_again(KrylovSolver& solver, const SparseMatrix& H, const KrylovHints& hints,
                              const Eigen::VectorXd& b, double tolerance) {
  const FactorizationResult setup = solver.compute(H, hints);
  EXPECT_TRUE(setup.ok()) << setup.message;
  const Eigen::SimplicialLDLT<SparseMatrix> ldlt(H);
  Eigen::VectorXd x;
  const KrylovSolveResult r = solver.solve(b, &x, 1e-10, 5000);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_LE(test::relative_error(x, ldlt.solve(b)), tolerance);
  const double roundoff =
      100.0 * std::numeric_limits<double>::epsilon() * (H.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs()).norm() / b.norm();
  EXPECT_NEAR(r.relative_residual, true_residual(H, b, x), 1e-12 + roundoff);
  return r;
}

// The systems of a Newton iteration: one matrix object whose values change in place (half of
// the unknowns become identity rows, the others' diagonal grows). compute() again on it solves
// the new system as LDL^T does, in as many iterations as an engine set up afresh on a copy
// (GAMG, which keeps its aggregates and interpolation, within a few).
TEST_P(KrylovEngine, ValuesChangedInPlaceAreTheNewSystem) {
  const ClampedCube& cube = clamped_cube(6);
  SparseMatrix H;
  const auto solver = make_krylov_solver(GetParam());
  ASSERT_NO_FATAL_FAILURE(first_system(cube, *solver, KrylovHints(cube.rigid_motions, 3), &H));
  const double* values = H.valuePtr();
  for (int j = 0; j < H.outerSize(); ++j)
    for (SparseMatrix::InnerIterator e(H, j); e; ++e) {
      const bool held = (j % 2 == 0) || (e.row() % 2 == 0);
      if (held)
        e.valueRef() = e.row() == j ? 1.0 : 0.0;
      else if (e.row() == j)
        e.valueRef() *= 3.0;
    }
  ASSERT_EQ(H.valuePtr(), values);
  Eigen::MatrixXd null_space = cube.rigid_motions;
  for (Eigen::Index i = 0; i < null_space.rows(); i += 2) null_space.row(i).setZero();
  const KrylovHints changed(null_space, 3);
  const KrylovSolveResult r = solve_again(*solver, H, changed, cube.system.b, 1e-8);
  ASSERT_TRUE(r.ok()) << r.message;

  const SparseMatrix copy = H;
  const auto fresh = make_krylov_solver(GetParam());
  ASSERT_TRUE(fresh->compute(copy, changed).ok());
  Eigen::VectorXd y;
  const KrylovSolveResult f = fresh->solve(cube.system.b, &y, 1e-10, 5000);
  ASSERT_TRUE(f.ok()) << f.message;
  RecordProperty("iterations_in_place", r.iterations);
  RecordProperty("iterations_fresh", f.iterations);
  if (GetParam() == "petsc-gamg")
    EXPECT_LE(r.iterations, f.iterations + 5);
  else
    EXPECT_EQ(r.iterations, f.iterations);
}

/// The 1D Laplacian shifted by -I: tridiag(-1, 1, -1), a positive diagonal, eigenvalues
/// 1 - 2 cos(k pi / (n + 1)) in (-1, 3), about a third of them negative.
SparseMatrix shifted_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 1.0);
    if (i + 1 < n) {
      entries.emplace_back(i, i + 1, -1.0);
      entries.emplace_back(i + 1, i, -1.0);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  return A;
}

/// The status of compute() when it fails, of solve() otherwise.
FactorizationStatus indefinite_status(KrylovSolver& solver, const SparseMatrix& A, std::string* message) {
  const FactorizationResult setup = solver.compute(A, Eigen::MatrixXd());
  if (!setup.ok()) {
    *message = setup.message;
    return setup.status;
  }
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), 1.0, 2.0);
  Eigen::VectorXd x;
  const KrylovSolveResult r = solver.solve(b, &x, 1e-10, 1000);
  *message = r.message;
  return r.status;
}

// PETSc's CG stops on negative curvature (KSP_DIVERGED_INDEFINITE_MAT or _PC). Eigen's CG does
// not stop on it, and eigen-cg's checks (a diagonal entry <= 0, x^T A x <= 0 for its x) need
// not see it: for eigen-cg only a failure is asserted.
TEST_P(KrylovEngine, IndefiniteMatrixIsNotPositiveDefinite) {
  const auto solver = make_krylov_solver(GetParam());
  for (const SparseMatrix& A : {shifted_laplacian(200), test::one_negative_eigenvalue(300, 7)}) {
    std::string message;
    const FactorizationStatus status = indefinite_status(*solver, A, &message);
    if (GetParam() == "eigen-cg")
      EXPECT_NE(status, FactorizationStatus::success) << message;
    else
      EXPECT_EQ(status, FactorizationStatus::not_positive_definite) << message;
  }
}

TEST_P(KrylovEngine, NegativeDiagonalIsNotPositiveDefinite) {
  SparseMatrix A = shifted_laplacian(50);
  A.coeffRef(17, 17) = -1.0;
  const auto solver = make_krylov_solver(GetParam());
  const FactorizationResult setup = solver->compute(A, Eigen::MatrixXd());
  EXPECT_EQ(setup.status, FactorizationStatus::not_positive_definite) << setup.message;
}

TEST_P(KrylovEngine, ContractViolationsThrow) {
  const auto solver = make_krylov_solver(GetParam());
  Eigen::VectorXd x;
  EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(3), &x, 1e-10, 10), InternalError);
  const SparseMatrix A = shifted_laplacian(4) + 2.0 * test::random_spd(4, 1).cwiseAbs();
  EXPECT_THROW(solver->compute(A, KrylovHints(Eigen::MatrixXd::Ones(3, 2))), InternalError);
  EXPECT_THROW(solver->compute(A, KrylovHints(Eigen::MatrixXd(), 3)), InternalError);  // 3 does not divide 4
  EXPECT_THROW(solver->compute(A, KrylovHints(Eigen::MatrixXd(), 0)), InternalError);
  ASSERT_TRUE(solver->compute(A, Eigen::MatrixXd()).ok());
  EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(3), &x, 1e-10, 10), InternalError);
  EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(4), nullptr, 1e-10, 10), InternalError);
  EXPECT_THROW(solver->solve(Eigen::VectorXd::Ones(4), &x, 0.0, 10), InternalError);
}

INSTANTIATE_TEST_SUITE_P(Built, KrylovEngine, ::testing::ValuesIn(available_krylov_solvers()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

bool gamg_built() {
  const auto built = available_krylov_solvers();
  return std::find(built.begin(), built.end(), "petsc-gamg") != built.end();
}

/// petsc-gamg's CG iterations to rtol 1e-10 on the cube with `hints`, its answer checked against
/// LDL^T's (-1 when it fails).
int gamg_iterations(const ClampedCube& cube, const KrylovHints& hints) {
  const auto solver = make_krylov_solver("petsc-gamg");
  const FactorizationResult setup = solver->compute(cube.system.A, hints);
  EXPECT_TRUE(setup.ok()) << setup.message;
  if (!setup.ok()) return -1;
  Eigen::VectorXd x;
  const KrylovSolveResult r = solver->solve(cube.system.b, &x, 1e-10, 5000);
  EXPECT_TRUE(r.ok()) << r.message;
  EXPECT_LE(test::relative_error(x, cube.reference), 1e-8);
  return r.ok() ? r.iterations : -1;
}

// GAMG given the rigid motions builds the coarse spaces of elasticity: on 10^3 cubes it needs
// fewer CG iterations than GAMG left to its default (the constant vector per dof).
TEST(Krylov, NearNullSpaceSavesGamgIterations) {
  if (!gamg_built()) GTEST_SKIP() << "petsc-gamg not built";
  const ClampedCube& cube = clamped_cube(10);
  const int without = gamg_iterations(cube, Eigen::MatrixXd());
  const int with = gamg_iterations(cube, cube.rigid_motions);
  RecordProperty("iterations_without", without);
  RecordProperty("iterations_with", with);
  EXPECT_GT(with, 0);
  EXPECT_LT(with, without);
}

// The unknowns in node blocks of three: GAMG aggregates the graph of nodes and solves as LDL^T
// does, and a block size that does not fit the matrix is a contract violation.
TEST(Krylov, GamgOnNodeBlocks) {
  if (!gamg_built()) GTEST_SKIP() << "petsc-gamg not built";
  const ClampedCube& cube = clamped_cube(10);
  RecordProperty("iterations_scalar", gamg_iterations(cube, KrylovHints(cube.rigid_motions, 1)));
  const int blocks = gamg_iterations(cube, KrylovHints(cube.rigid_motions, 3));
  RecordProperty("iterations_blocks", blocks);
  EXPECT_GT(blocks, 0);
  const auto solver = make_krylov_solver("petsc-gamg");
  EXPECT_THROW(solver->compute(cube.system.A, KrylovHints(cube.rigid_motions, 7)), InternalError);  // 7 does not divide 3630
}

// A system changed in place so that the smoothers' eigenvalue bounds of the first no longer
// hold (a stiff coupling of the 24 unknowns of one box: the Jacobi-scaled matrix's largest
// eigenvalue grows about tenfold): GAMG's preconditioner set up again with the first's bounds
// is indefinite, and the engine sets one up afresh: the answer is LDL^T's.
TEST(Krylov, GamgSetUpAfreshWhenTheReusedOneIsIndefinite) {
  if (!gamg_built()) GTEST_SKIP() << "petsc-gamg not built";
  const ClampedCube& cube = clamped_cube(6);
  SparseMatrix H;
  const KrylovHints hints(cube.rigid_motions, 3);
  const auto solver = make_krylov_solver("petsc-gamg");
  ASSERT_NO_FATAL_FAILURE(first_system(cube, *solver, hints, &H));
  // the free unknowns of the box at the cube's far corner, all coupled in A's pattern
  std::vector<int> box;
  for (int k = 0; k < static_cast<int>(cube.system.dofs.num_free()); ++k) {
    const int v = cube.system.dofs.free_dof(k) / 3;
    if (v % 7 >= 5 && (v / 7) % 7 >= 5 && v / 49 >= 5) box.push_back(k);
  }
  ASSERT_EQ(box.size(), 24u);
  const double big = 1e3 * H.diagonal().maxCoeff();
  for (int i : box)
    for (int j : box) H.coeffRef(i, j) += big;
  const KrylovSolveResult r = solve_again(*solver, H, hints, cube.system.b, 1e-7);
  ASSERT_TRUE(r.ok()) << r.message;
  RecordProperty("iterations", r.iterations);
}

// The PETSc engines' module holds PETSc and the MPI build of MUMPS; this program links the
// sequential MUMPS engine. Both run in one process, on the same system.
TEST(Krylov, PetscBesideSequentialMumps) {
  const auto built = available_krylov_solvers();
  const auto linear = available_factorizations();
  if (std::find(built.begin(), built.end(), "petsc-gamg") == built.end() ||
      std::find(linear.begin(), linear.end(), "mumps") == linear.end())
    GTEST_SKIP() << "needs petsc-gamg and mumps";
  const ClampedCube& cube = clamped_cube(6);
  FactorizationOptions options;
  options.engine = "mumps";
  const auto mumps = make_factorization(options);
  ASSERT_TRUE(mumps->factorize(cube.system.A).ok());
  Eigen::MatrixXd direct;
  ASSERT_TRUE(mumps->solve(cube.system.b, &direct).ok());
  const auto gamg = make_krylov_solver("petsc-gamg");
  ASSERT_TRUE(gamg->compute(cube.system.A, cube.rigid_motions).ok());
  Eigen::VectorXd x;
  const KrylovSolveResult r = gamg->solve(cube.system.b, &x, 1e-10, 1000);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_LE(test::relative_error(x, direct), 1e-8);
  EXPECT_LE(test::relative_error(direct, cube.reference), 1e-12);
}

TEST(Krylov, Names) {
  const std::vector<std::string>& known = known_krylov_solvers();
  EXPECT_EQ(known, (std::vector<std::string>{"petsc-gamg", "petsc-hypre", "eigen-cg"}));
  EXPECT_TRUE(is_krylov_solver("Petsc_GAMG"));
  EXPECT_TRUE(is_krylov_solver("EIGEN-CG"));
  EXPECT_FALSE(is_krylov_solver("nope"));
  EXPECT_FALSE(is_krylov_solver("auto"));

  const std::vector<std::string> built = available_krylov_solvers();
  ASSERT_FALSE(built.empty());
  EXPECT_NE(std::find(built.begin(), built.end(), "eigen-cg"), built.end());
  auto position = known.begin();
  for (const std::string& name : built) {  // in the order of preference
    position = std::find(position, known.end(), name);
    EXPECT_NE(position, known.end()) << name;
  }
  EXPECT_EQ(make_krylov_solver("auto")->name(), built.front());
  EXPECT_EQ(make_krylov_solver("Eigen_CG")->name(), "eigen-cg");
}

TEST(Krylov, UnknownEngineIsAnInputErrorNamingIt) {
  try {
    make_krylov_solver("nope");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("eigen-cg"), std::string::npos) << e.what();  // the list of those built
  }
}

}  // namespace
}  // namespace hemivem
