// Static condensation onto the contact normals (DESIGN §3) with every built engine.
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/example.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include <iostream>
#include <span>
#include <type_traits>

#include "test_support.hpp"

using namespace hemivem;

namespace {

struct Example {
  Mesh mesh;
  ContactProblem problem;
  LinearSystem system;
  ContactBoundary boundary;
};

std::unique_ptr<Example> example(int n, std::shared_ptr<const ContactLaw> law = paper_law(),
                                 ConstraintKind constraint = ConstraintKind::box) {
  auto ex = std::make_unique<Example>();
  ex->mesh = make_squares(n);
  ex->problem = example_4_1(ex->mesh);
  ex->problem.parts[0].law = std::move(law);
  ex->problem.parts[0].constraint = constraint;
  ex->system = assemble(ex->problem.elasticity);
  ex->boundary = make_contact_boundary(ex->mesh, ex->problem.parts[0].facets, ex->system.dofs, ex->problem.parts[0].gap);
  return ex;
}

Condensation condense(const Example& ex, const std::string& engine) {
  FactorizationOptions opt;
  opt.engine = engine;
  return Condensation(ex.system, ex.boundary, make_factorization(opt), ex.problem.parts[0].law, ex.problem.parts[0].constraint);
}

double rel(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a - b).norm() / b.norm(); }

TEST(ContactBoundary, BottomOfExample41) {
  const int n = 16;
  auto ex = example(n);
  const auto& cb = ex->boundary;
  EXPECT_EQ(cb.size(), n - 1);  // the two corner nodes lie on Gamma_1
  EXPECT_EQ(cb.edges.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < cb.size(); ++i) {
    EXPECT_EQ(ex->mesh.vertex(cb.nodes[i]).y(), 0.0);
    EXPECT_NEAR((cb.normals[i] - Vec2(0, -1)).norm(), 0.0, 1e-15);
    EXPECT_NEAR(cb.weights(i), 1.0 / n, 1e-15);  // half of each neighbouring edge
    EXPECT_EQ(cb.gaps(i), 0.02);
  }
}

TEST(ContactBoundary, PolylineNormalsAndWeights) {
  // Gamma_3 = bottom and right sides of a square with the left side clamped: the corner node
  // (1, 0) gets the bisecting normal and the weight of its two half edges.
  const Mesh mesh = make_squares(4);
  const Rectangle unit{};
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{1.0, 0.3});
  p.dirichlet.push_back({select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, "left")}), {}, {true, true}});
  const LinearSystem sys = assemble(p);
  const auto edges = select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, "bottom"), rectangle_side(unit, "right")});
  const ContactBoundary cb = make_contact_boundary(mesh, edges, sys.dofs, [](const Vec2& x) { return 0.1 * x.x(); });
  EXPECT_EQ(cb.size(), 3 + 1 + 4);  // bottom without (0,0), the corner, the right side
  double total = 0.0;
  for (int i = 0; i < cb.size(); ++i) {
    total += cb.weights(i);
    const Vec2 x = mesh.vertex(cb.nodes[i]);
    EXPECT_NEAR(cb.gaps(i), 0.1 * x.x(), 1e-15);
    if (x == Vec2(1, 0)) {
      EXPECT_NEAR((cb.normals[i] - Vec2(1, -1).normalized()).norm(), 0.0, 1e-15);
      EXPECT_NEAR(cb.weights(i), 0.25, 1e-15);
    }
  }
  EXPECT_NEAR(total, 2.0 - 0.125, 1e-14);  // Gamma_3 length less the half edge at the clamped node
}

TEST(Condensation, BodyNotHeldIsReportedBeforeAnyFactorization) {
  const Mesh mesh = make_squares(4);
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(Material{65.0, 0.29});
  try {
    assemble(p);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the body is not held"), std::string::npos) << e.what();
  }
  p.dirichlet.push_back({select_boundary_edges(mesh, std::vector<Segment>{{{5, 5}, {6, 6}, 1e-8}}), {}, {true, true}});
  EXPECT_THROW(assemble(p), InputError);
}

class CondensationEngines : public ::testing::TestWithParam<std::string> {};

TEST_P(CondensationEngines, ExactForAQuadraticPotentialWithoutConstraint) {
  // j = k r^2 / 2 and no gap: the reduced problem is (S + k W) a = c; after back-substitution
  // it must equal the direct solve of (A + k N^T W N) u = b.
  const double k = 100.0;
  auto ex = example(16, linear_law(k), ConstraintKind::none);
  const Condensation cond = condense(*ex, GetParam());
  const ReducedProblem& rp = cond.reduced();
  Eigen::MatrixXd M = rp.S;
  M.diagonal() += k * rp.w;
  const Eigen::VectorXd a = M.llt().solve(rp.c);
  const Eigen::VectorXd u = cond.back_substitute(a);

  SparseMatrix A = ex->system.A;
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < ex->boundary.size(); ++i) {
    const int v = ex->boundary.nodes[i];
    const Vec2 nu = ex->boundary.normals[i];
    const int d[2] = {ex->system.dofs.free_index(2 * v), ex->system.dofs.free_index(2 * v + 1)};
    for (int r = 0; r < 2; ++r)
      for (int c = 0; c < 2; ++c) t.emplace_back(d[r], d[c], k * ex->boundary.weights(i) * nu(r) * nu(c));
  }
  SparseMatrix C(A.rows(), A.cols());
  C.setFromTriplets(t.begin(), t.end());
  A += C;
  Eigen::SimplicialLLT<SparseMatrix> llt(A);
  ASSERT_EQ(llt.info(), Eigen::Success);
  const Eigen::VectorXd uref = ex->system.dofs.expand(llt.solve(ex->system.b));
  EXPECT_LE((u - uref).cwiseAbs().maxCoeff(), 1e-10 * uref.cwiseAbs().maxCoeff());
  EXPECT_LE((ex->boundary.normal_displacements(u) - a).cwiseAbs().maxCoeff(), 1e-12 * a.cwiseAbs().maxCoeff());
}

TEST_P(CondensationEngines, SchurComplementAndLoadAgreeWithEigenOnExample41) {
  auto ex = example(16);
  const Condensation ref = condense(*ex, "eigen");
  const Condensation cond = condense(*ex, GetParam());
  EXPECT_LE(rel(cond.reduced().S, ref.reduced().S), 1e-10);
  EXPECT_LE(rel(cond.reduced().c, ref.reduced().c), 1e-10);
  EXPECT_NEAR(cond.uniqueness_margin(), ref.uniqueness_margin(), 1e-9 * std::abs(ref.uniqueness_margin()));
  // and S against dense blocks of the rotated matrix (independent of every engine)
  if (GetParam() == "eigen") {
    const Eigen::MatrixXd S = ref.reduced().S;
    EXPECT_LE((S - S.transpose()).norm(), 1e-12 * S.norm());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
    EXPECT_GT(eig.eigenvalues()(0), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Engines, CondensationEngines, ::testing::ValuesIn(available_factorizations()),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (auto& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(Condensation, DenseReferenceOnASmallProblem) {
  // S and c from the dense blocks of the rotated system (N = 4; normals (0, -1): the normal
  // dof is -u_y), independent of the engines.
  auto ex = example(4);
  const Condensation cond = condense(*ex, "eigen");
  const Eigen::MatrixXd A = Eigen::MatrixXd(ex->system.A);
  const int n = static_cast<int>(A.rows());
  std::vector<int> b1, b2;
  for (int v : ex->boundary.nodes) b1.push_back(ex->system.dofs.free_index(2 * v + 1));
  for (int i = 0; i < n; ++i)
    if (std::find(b1.begin(), b1.end(), i) == b1.end()) b2.push_back(i);
  const int n1 = static_cast<int>(b1.size()), n2 = static_cast<int>(b2.size());
  Eigen::MatrixXd A11(n1, n1), A12(n1, n2), A22(n2, n2);
  Eigen::VectorXd f1(n1), f2(n2);
  for (int i = 0; i < n1; ++i) {
    f1(i) = -ex->system.b(b1[i]);  // the normal component is -u_y
    for (int j = 0; j < n1; ++j) A11(i, j) = A(b1[i], b1[j]);
    for (int j = 0; j < n2; ++j) A12(i, j) = -A(b1[i], b2[j]);
  }
  for (int i = 0; i < n2; ++i) {
    f2(i) = ex->system.b(b2[i]);
    for (int j = 0; j < n2; ++j) A22(i, j) = A(b2[i], b2[j]);
  }
  const Eigen::MatrixXd S = A11 - A12 * A22.llt().solve(A12.transpose());
  const Eigen::VectorXd c = f1 - A12 * A22.llt().solve(f2);
  EXPECT_LE(rel(cond.reduced().S, S), 1e-12);
  EXPECT_LE(rel(cond.reduced().c, c), 1e-12);
}

TEST(Condensation, UniquenessMarginIsPositiveAndScalesWithH) {
  // An independent P1 computation gives lambda_min(S - 20 W) of about 100 h on Example 4.1.
  std::vector<double> margin;
  for (int n : {16, 32, 64}) {
    auto ex = example(n);
    margin.push_back(condense(*ex, "eigen").uniqueness_margin());
    std::cout << "N = " << n << ": lambda_min(S - alpha W) = " << margin.back() << " = " << margin.back() * n
              << " h\n";
    EXPECT_GT(margin.back(), 0.0);
    EXPECT_GT(margin.back() * n, 90.0);
    EXPECT_LT(margin.back() * n, 110.0);
  }
  EXPECT_NEAR(margin[0] / margin[1], 2.0, 0.3);
  EXPECT_NEAR(margin[1] / margin[2], 2.0, 0.3);
}

TEST(Condensation, ConcaveKinkMakesTheMarginMinusInfinity) {
  auto ex = example(8, sawtooth_law(), ConstraintKind::one_sided);
  EXPECT_EQ(condense(*ex, "eigen").uniqueness_margin(), -std::numeric_limits<double>::infinity());
}

// An engine that works (eigen) until the call `fail_at` (0: schur_complement, k > 0: the k-th
// solve_interior), which returns `status` instead.
class FailingFactorization final : public SparseFactorization {
 public:
  FailingFactorization(FactorizationStatus status, int fail_at) : status_(status), fail_at_(fail_at) {}
  std::string name() const override { return "failing"; }
  FactorizationResult analyze(const SparseMatrix& A) override { return inner_->analyze(A); }
  FactorizationResult factorize(const SparseMatrix& A) override { return inner_->factorize(A); }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override { return inner_->solve(B, X); }
  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1, Eigen::MatrixXd* S) override {
    return next() ? inner_->schur_complement(A, block1, S) : failure();
  }
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override {
    return next() ? inner_->solve_interior(B2, X2) : failure();
  }

 private:
  bool next() const { return calls_++ != fail_at_; }
  FactorizationResult failure() const { return {status_, "injected " + to_string(status_)}; }
  std::unique_ptr<SparseFactorization> inner_ = make_factorization({});
  FactorizationStatus status_;
  int fail_at_;
  mutable int calls_ = 0;
};

class CondensationFailures : public ::testing::TestWithParam<FactorizationStatus> {};

// Every status is the engine's numerical failure (NumericalError, exit 4); a broken contract
// is thrown by the engine itself (InternalError, exit 5).
template <class Call>
void expect_error_kind(FactorizationStatus status, Call call) {
  try {
    call();
    ADD_FAILURE() << "expected an exception for " << to_string(status);
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("injected " + to_string(status)), std::string::npos) << e.what();
  }
}

TEST_P(CondensationFailures, OfTheSchurComplement) {
  auto ex = example(4);
  expect_error_kind(GetParam(), [&] {
    Condensation(ex->system, ex->boundary, std::make_unique<FailingFactorization>(GetParam(), 0), ex->problem.parts[0].law,
                 ex->problem.parts[0].constraint);
  });
}

TEST_P(CondensationFailures, OfTheInteriorSolveForTheLoad) {
  auto ex = example(4);
  expect_error_kind(GetParam(), [&] {
    Condensation(ex->system, ex->boundary, std::make_unique<FailingFactorization>(GetParam(), 1), ex->problem.parts[0].law,
                 ex->problem.parts[0].constraint);
  });
}

TEST_P(CondensationFailures, OfTheBackSubstitution) {
  auto ex = example(4);
  const Condensation cond(ex->system, ex->boundary, std::make_unique<FailingFactorization>(GetParam(), 2),
                          ex->problem.parts[0].law, ex->problem.parts[0].constraint);
  expect_error_kind(GetParam(), [&] { cond.back_substitute(Eigen::VectorXd::Zero(ex->boundary.size())); });
}

INSTANTIATE_TEST_SUITE_P(Statuses, CondensationFailures,
                         ::testing::Values(FactorizationStatus::not_positive_definite,
                                           FactorizationStatus::numerical_failure, FactorizationStatus::out_of_memory),
                         [](const auto& info) { return to_string(info.param); });

TEST(Condensation, ErrorKindsAreDistinctForTheCommandLine) {
  // main.cpp maps InputError to exit 2, NumericalError to 4 and any other Error to 5.
  EXPECT_TRUE((std::is_base_of_v<Error, InternalError>));
  EXPECT_FALSE((std::is_base_of_v<NumericalError, InternalError>));
  EXPECT_FALSE((std::is_base_of_v<InputError, InternalError>));
}

}  // namespace

namespace {

TEST(ContactBoundary, ChosenByNamedGroup) {
  Mesh mesh = make_squares(8);
  const auto bottom = select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(Rectangle{}, "bottom")});
  mesh.set_edge_group("foundation", bottom);
  EXPECT_EQ(select_boundary_edges(mesh, "foundation"), bottom);
  int interior = 0;
  while (mesh.edge(interior).on_boundary()) ++interior;
  mesh.set_edge_group("inside", {interior});
  try {
    select_boundary_edges(mesh, "inside");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is not on the boundary"), std::string::npos) << e.what();
  }
  EXPECT_THROW(select_boundary_edges(mesh, "lid"), InputError);
}

}  // namespace
