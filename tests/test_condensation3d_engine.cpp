// The Schur complement of a three-dimensional stiffness through each linear engine built
// (schur_complement, then condense_rhs / expand or solve_interior), against one factorization
// of the whole matrix by the same engine. The cube of 20^3 boxes is large enough for the cholmod
// engine to order the interior block by METIS (AMD's fill there is that of a 3D body: 21 times
// the entries of A22's lower triangle, 1600 flops per entry of the factor): its
// three-dimensional path.
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/sparse_factorization.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "linear_support.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace hemivem {
namespace {

/// The elastic cube of n^3 boxes held on its four vertical sides, and block1 the vertical
/// displacements of the free vertices of its bottom face (the contact unknowns of a body
/// pressed on a plane), with a load pulling the top face.
struct Cube {
  LinearSystem system;
  std::vector<int> block1;
};

const Cube& cube() {
  static const Cube c = [] {
    const int n = 20;
    const Mesh3D mesh = make_cubes(n);
    const Box box;
    ElasticityProblem3D p;
    p.mesh = &mesh;
    p.materials = MaterialTable(Material{65.0, 0.29});
    for (const char* side : {"x0", "x1", "y0", "y1"})
      p.dirichlet.push_back({select_box_side(mesh, box, side), {}, {true, true, true}, side});
    p.tractions.push_back({select_box_side(mesh, box, "top"), [](const Vec3& x) { return Vec3(x[1], -x[0], 10.0); }, {}});
    Cube out;
    out.system = assemble(p);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const int k = out.system.dofs.free_index(3 * v + 2);
      if (mesh.vertex(v)[2] == 0.0 && k >= 0) out.block1.push_back(k);
    }
    return out;
  }();
  return c;
}

std::unique_ptr<SparseFactorization> engine(const std::string& name) {
  FactorizationOptions options;
  options.engine = name;
  return make_factorization(options);
}

/// S, then the solution of A u = b through S: c = b1 - A12 A22^{-1} b2, u1 = S^{-1} c and
/// u2 = A22^{-1} (b2 - A21 u1), returned as u (A's numbering).
struct Condensed {
  Eigen::MatrixXd S;
  Eigen::VectorXd u;
};

Condensed condense(SparseFactorization& f, const SparseMatrix& A, const Eigen::VectorXd& b,
                   const std::vector<int>& block1) {
  const int n = static_cast<int>(A.rows());
  const std::vector<int> block2 = test::complement(n, block1);
  Condensed out;
  const FactorizationResult r = f.schur_complement(A, block1, &out.S);
  EXPECT_TRUE(r.ok()) << r.message;
  Eigen::VectorXd b1(static_cast<Eigen::Index>(block1.size())), b2(static_cast<Eigen::Index>(block2.size()));
  for (std::size_t i = 0; i < block1.size(); ++i) b1(static_cast<Eigen::Index>(i)) = b(block1[i]);
  for (std::size_t i = 0; i < block2.size(); ++i) b2(static_cast<Eigen::Index>(i)) = b(block2[i]);
  Eigen::VectorXd c, u1, u2;
  if (SplitInteriorSolve* split = split_interior_solve(f)) {
    EXPECT_TRUE(split->condense_rhs(b1, b2, &c).ok());
    u1 = out.S.llt().solve(c);
    EXPECT_TRUE(split->expand(u1, &u2).ok());
  } else {
    // c and u2 by interior solves, with A21 applied through A
    Eigen::MatrixXd y;
    EXPECT_TRUE(f.solve_interior(b2, &y).ok());
    Eigen::VectorXd full = Eigen::VectorXd::Zero(n);
    for (std::size_t i = 0; i < block2.size(); ++i) full(block2[i]) = y(static_cast<Eigen::Index>(i), 0);
    const Eigen::VectorXd Ay = A * full;
    c = b1;
    for (std::size_t i = 0; i < block1.size(); ++i) c(static_cast<Eigen::Index>(i)) -= Ay(block1[i]);
    u1 = out.S.llt().solve(c);
    full.setZero();
    for (std::size_t i = 0; i < block1.size(); ++i) full(block1[i]) = u1(static_cast<Eigen::Index>(i));
    const Eigen::VectorXd Au1 = A * full;
    Eigen::VectorXd rhs = b2;
    for (std::size_t i = 0; i < block2.size(); ++i) rhs(static_cast<Eigen::Index>(i)) -= Au1(block2[i]);
    EXPECT_TRUE(f.solve_interior(rhs, &y).ok());
    u2 = y.col(0);
  }
  out.u.resize(n);
  for (std::size_t i = 0; i < block1.size(); ++i) out.u(block1[i]) = u1(static_cast<Eigen::Index>(i));
  for (std::size_t i = 0; i < block2.size(); ++i) out.u(block2[i]) = u2(static_cast<Eigen::Index>(i));
  return out;
}

/// The engines built but eigen (a simplicial factorization: slow on a 3D body).
std::vector<std::string> engines() {
  std::vector<std::string> names;
  for (const std::string& name : available_factorizations())
    if (name != "eigen") names.push_back(name);
  return names;
}

class Condensation3DEngine : public ::testing::TestWithParam<std::string> {};

TEST_P(Condensation3DEngine, SchurComplementAndSolveAgreeWithOneFactorizationOfTheWholeMatrix) {
  const Cube& c = cube();
  const SparseMatrix& A = c.system.A;
  const auto n1 = static_cast<Eigen::Index>(c.block1.size());
  ASSERT_EQ(n1, 19 * 19);
  ASSERT_GT(A.rows(), 20000);
  // S^{-1} = (A^{-1})_11, probed: S^{-1} V against the block1 rows of A^{-1} E1 V, E1 V the
  // columns of V placed on block1
  const Eigen::MatrixXd V = test::random_matrix(n1, 4, 7);
  Eigen::MatrixXd E1V = Eigen::MatrixXd::Zero(A.rows(), V.cols());
  for (Eigen::Index i = 0; i < n1; ++i) E1V.row(c.block1[static_cast<std::size_t>(i)]) = V.row(i);
  auto f = engine(GetParam());
  const Condensed k = condense(*f, A, c.system.b, c.block1);
  ASSERT_EQ(k.S.rows(), n1);
  EXPECT_LT(test::relative_error(k.S, k.S.transpose()), 1e-14);
  // the reference: one factorization of A in the engine's own fill-reducing order
  auto whole = engine(GetParam());
  ASSERT_TRUE(whole->factorize(A).ok());
  Eigen::MatrixXd u, X;
  ASSERT_TRUE(whole->solve(c.system.b, &u).ok());
  ASSERT_TRUE(whole->solve(E1V, &X).ok());
  EXPECT_LT(test::relative_error(k.u, u), 1e-12);
  Eigen::MatrixXd X1(n1, V.cols());
  for (Eigen::Index i = 0; i < n1; ++i) X1.row(i) = X.row(c.block1[static_cast<std::size_t>(i)]);
  EXPECT_LT(test::relative_error(k.S.llt().solve(V), X1), 1e-12);
}

TEST_P(Condensation3DEngine, ExactZerosOfThePatternDoNotChangeTheSchurComplement) {
  // The condensation gives the engine a 3D stiffness with its exact zeros stored (a third of a
  // cube stiffness's entries): the ordering differs, S and the solve do not.
  const Cube& c = cube();
  // the symmetric part of A, so that dropping its exact zeros keeps the pattern symmetric
  const SparseMatrix A = 0.5 * (c.system.A + SparseMatrix(c.system.A.transpose()));
  SparseMatrix pruned = A;
  pruned.prune(0.0);
  ASSERT_LT(pruned.nonZeros(), 0.9 * static_cast<double>(A.nonZeros()));
  auto f = engine(GetParam());
  auto g = engine(GetParam());
  const Condensed a = condense(*f, A, c.system.b, c.block1);
  const Condensed b = condense(*g, pruned, c.system.b, c.block1);
  EXPECT_LT(test::relative_error(b.S, a.S), 1e-12);
  EXPECT_LT(test::relative_error(b.u, a.u), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Engines, Condensation3DEngine, ::testing::ValuesIn(engines()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Condensation3DEngine);

TEST(Condensation3DBlas, BlasCallsBindToTheBlasCholmodIsBuiltAgainst) {
  // Debian's CHOLMOD needs libblas.so.3 (an alternative: OpenBLAS here). A BLAS loaded before it
  // (Ceres' link interface named ATLAS's libf77blas) takes every BLAS call of the process,
  // CHOLMOD's factorization among them: twice as slow on a 3D factorization.
  void* blas = dlopen("libblas.so.3", RTLD_LAZY | RTLD_NOLOAD);
  if (blas == nullptr) GTEST_SKIP() << "libblas.so.3 is not loaded by this program";
  void* own = dlsym(blas, "dgemm_");
  void* bound = dlsym(RTLD_DEFAULT, "dgemm_");
  dlclose(blas);
  ASSERT_NE(own, nullptr);
  Dl_info info{};
  const std::string where = dladdr(bound, &info) != 0 && info.dli_fname != nullptr ? info.dli_fname : "?";
  EXPECT_EQ(bound, own) << "dgemm_ binds to " << where;
}

}  // namespace
}  // namespace hemivem
