// Stiff and extreme cases: the guarantees of solve_contact (never a false "converged"), the
// engine-independent condition estimate, memory estimates, region boxes, and the scenes of
// scenes/extreme/ with the properties their titles claim.
#include <gtest/gtest.h>

#include <hemivem/support/condition.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <random>
#include <span>
#include <utility>

#include "test_support.hpp"

namespace hemivem {
namespace {

std::filesystem::path extreme_dir() { return test::data_dir() / ".." / ".." / "scenes" / "extreme"; }

// An engine that delegates to another and poisons solutions with NaN from its
// `poison_after`-th interior solve (or plain solve) on, to check what solve_contact claims.
class PoisonedFactorization final : public SparseFactorization {
 public:
  PoisonedFactorization(std::unique_ptr<SparseFactorization> inner, int poison_after)
      : inner_(std::move(inner)), poison_after_(poison_after) {}
  std::string name() const override { return "poisoned"; }
  FactorizationResult analyze(const SparseMatrix& A) override { return inner_->analyze(A); }
  FactorizationResult factorize(const SparseMatrix& A) override { return inner_->factorize(A); }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override {
    auto r = inner_->solve(B, X);
    poison(X);
    return r;
  }
  FactorizationResult schur_complement(const SparseMatrix& A, std::span<const int> block1, Eigen::MatrixXd* S) override {
    return inner_->schur_complement(A, block1, S);
  }
  FactorizationResult solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const override {
    auto r = inner_->solve_interior(B2, X2);
    poison(X2);
    return r;
  }

 private:
  void poison(Eigen::MatrixXd* X) const {
    if (calls_++ >= poison_after_ && X && X->size()) (*X)(0, 0) = std::numeric_limits<double>::quiet_NaN();
  }
  std::unique_ptr<SparseFactorization> inner_;
  int poison_after_;
  mutable int calls_ = 0;
};

// Example 4.1 (loads, contact) with the given overrides.
Scene example_scene(std::initializer_list<const char*> overrides) {
  Scene s = default_scene();
  for (const char* o : overrides) apply_override(s, o);
  return s;
}

std::unique_ptr<SparseFactorization> engine(const std::string& name) {
  FactorizationOptions o;
  o.engine = name;
  return make_factorization(o);
}

TEST(Guarantees, NonFiniteDisplacementAfterAConvergedMinimizerIsNotConverged) {
  const Scene scene = example_scene({"mesh.n=8"});
  const auto built = build_problem(scene);
  const auto ssn = make_minimizer("ssn");
  // the first interior solve (c) is clean: the minimizer converges; back-substitution is poisoned
  const ContactSolution sol = solve_contact(built->problem, std::make_unique<PoisonedFactorization>(engine("eigen"), 1),
                                            *ssn, MinimizerOptions{});
  EXPECT_TRUE(sol.minimizer->certificate.dual <= 1e-10) << "the reduced problem itself is clean";
  EXPECT_FALSE(sol.u.allFinite());
  EXPECT_FALSE(sol.converged());
  EXPECT_EQ(sol.status, MinimizerStatus::failed);
  EXPECT_NE(sol.message.find("not finite"), std::string::npos) << sol.message;

  // a clean run of the same problem converges
  const ContactSolution clean = solve_contact(built->problem, engine("eigen"), *ssn, MinimizerOptions{});
  EXPECT_TRUE(clean.converged());
  EXPECT_TRUE(clean.u.allFinite());
}

TEST(Guarantees, PoisonedCondensationNeverConverges) {
  const Scene scene = example_scene({"mesh.n=8"});
  const auto built = build_problem(scene);
  for (const auto& m : available_minimizers()) {
    const auto minimizer = make_minimizer(m);
    const ContactSolution sol = solve_contact(
        built->problem, std::make_unique<PoisonedFactorization>(engine("eigen"), 0), *minimizer, MinimizerOptions{});
    EXPECT_FALSE(sol.converged()) << m;
  }
}

TEST(Guarantees, LinearSolveReportsItsResidualAndRefusesNaN) {
  const Scene scene = example_scene({"mesh.n=8"});
  Scene no_contact = scene;
  no_contact.contact.reset();
  const auto built = build_problem(no_contact);
  const auto ssn = make_minimizer("ssn");
  const ContactSolution clean = solve_contact(built->problem, engine("eigen"), *ssn, MinimizerOptions{});
  EXPECT_TRUE(clean.converged());
  EXPECT_LT(clean.certificate.dual, 1e-12);
  EXPECT_GT(clean.certificate.dual, 0.0) << "a real residual, not a placeholder";
  const ContactSolution bad = solve_contact(built->problem, std::make_unique<PoisonedFactorization>(engine("eigen"), 0),
                                            *ssn, MinimizerOptions{});
  EXPECT_FALSE(bad.converged());
  EXPECT_FALSE(std::isfinite(bad.certificate.dual));
}

// ---- condition estimate ----------------------------------------------------------------

TEST(ConditionEstimate, MatchesTheExactOneNormOfInversesWithinItsGuarantee) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int n : {1, 2, 5, 20, 60}) {
    Eigen::MatrixXd M(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) M(i, j) = normal(rng);
    // SPD with a spread of eigenvalues 1e-6 .. 1
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(M);
    const Eigen::MatrixXd Qm = qr.householderQ();
    Eigen::VectorXd d(n);
    for (int i = 0; i < n; ++i) d(i) = std::pow(10.0, -6.0 * i / std::max(1, n - 1));
    const Eigen::MatrixXd A = Qm * d.asDiagonal() * Qm.transpose();
    const Eigen::MatrixXd Ainv = A.inverse();
    const double exact = Ainv.cwiseAbs().colwise().sum().maxCoeff();
    int blocks = 0;
    std::vector<Eigen::Index> widths;
    const double est = estimate_norm1_symmetric_blocks(n, [&](const Eigen::MatrixXd& x) {
      ++blocks;
      widths.push_back(x.cols());
      return Eigen::MatrixXd(Ainv * x);
    });
    EXPECT_EQ(blocks, 2) << "a fixed number of solves";
    EXPECT_EQ(widths, (std::vector<Eigen::Index>{2, 3}));
    EXPECT_LE(est, exact * (1 + 1e-12)) << n;
    EXPECT_GE(est, exact / 3.0) << n;
  }
}

TEST(ConditionEstimate, SameForEveryEngineAndGrowsTowardsIncompressibility) {
  double previous = 0.0;
  for (const char* nu : {"0.29", "0.49", "0.4999"}) {
    const Scene scene = example_scene({"mesh.n=8", (std::string("material.nu=") + nu).c_str()});
    const auto built = build_problem(scene);
    const auto ssn = make_minimizer("ssn");
    const NonsmoothMinimizer* one[] = {ssn.get()};
    std::vector<double> kappas;
    for (const auto& name : available_factorizations()) {
      const auto sols = solve_contact(built->problem, engine(name), one, MinimizerOptions{}, nullptr, true);
      ASSERT_EQ(sols.size(), 1u);
      kappas.push_back(sols[0].condition_estimate);
    }
    for (double k : kappas) EXPECT_NEAR(k, kappas.front(), 1e-6 * kappas.front()) << nu;
    EXPECT_GT(kappas.front(), previous) << nu;
    previous = kappas.front();
  }
}

// ---- memory ----------------------------------------------------------------------------

class MemoryLimit : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* v = std::getenv("HEMIVEM_MEMORY_LIMIT")) saved_ = v, had_ = true;
  }
  void TearDown() override {
    if (had_) setenv("HEMIVEM_MEMORY_LIMIT", saved_.c_str(), 1);
    else unsetenv("HEMIVEM_MEMORY_LIMIT");
  }
  std::string saved_;
  bool had_ = false;
};

TEST_F(MemoryLimit, EstimatesFollowTheMeasuredPeaks) {
  // measured peaks of `hemivem solve` (Example 4.1, all outputs): squares 512: cholmod
  // 1.06 GB, mumps 1.06 GB, eigen 1.14 GB; voronoi 256: cholmod 0.90 GB, mumps 0.90 GB, eigen
  // 0.97 GB. The estimate is above every engine's peak and within 20 % above the default's.
  const double sq512 = estimate_memory("squares", 512).solve_bytes;
  EXPECT_GT(sq512, 1.14e9);
  EXPECT_LT(sq512, 1.2 * 1.06e9);
  const double vo256 = estimate_memory("voronoi", 256).solve_bytes;
  EXPECT_GT(vo256, 0.97e9);
  EXPECT_LT(vo256, 1.2 * 0.90e9);
  EXPECT_NEAR(estimate_memory("squares", 64).vertices, 65.0 * 65.0, 0.5);
  EXPECT_THROW(estimate_memory("hexagons", 4), InputError);
  EXPECT_GT(estimate_memory("squares", 1000000).solve_bytes, 1e15);
}

TEST_F(MemoryLimit, ThreeDimensionalEstimatesFollowTheMeasuredPeaks) {
  // measured peaks of 3D solves on cubes (cholmod, contact on one side): n = 16: 104 MB,
  // n = 24: 454 MB, n = 32: 1.36 GB
  const std::pair<int, double> measured[] = {{16, 104e6}, {24, 454e6}, {32, 1.36e9}};
  for (const auto& [n, peak] : measured) {
    const double e = estimate_memory_3d("cubes", n, n, n).solve_bytes;
    EXPECT_GT(e, peak) << n;
    EXPECT_LT(e, 1.3 * peak) << n;
  }
  // Voronoi cells: n = 16 (27 861 vertices) peaked at 2.78 GB with mumps, 1.87 GB with cholmod
  const double voronoi = estimate_memory_3d("voronoi", 16, 16, 16).solve_bytes;
  EXPECT_GT(voronoi, 2.78e9);
  EXPECT_LT(voronoi, 1.3 * 2.78e9);
  // the factor grows like V^(4/3): 64^3 cubes need more than 8 times 32^3
  EXPECT_GT(estimate_memory_3d("cubes", 64, 64, 64).solve_bytes, 8.0 * estimate_memory_3d("cubes", 32, 32, 32).solve_bytes);
  EXPECT_THROW(estimate_memory_3d("squares", 4, 4, 4), InputError);
  EXPECT_THROW(estimate_memory_3d("cubes", 4, 0, 4), InputError);
}

TEST_F(MemoryLimit, RefusesBeforeBuildingAndNamesTheLimit) {
  setenv("HEMIVEM_MEMORY_LIMIT", "64M", 1);
  EXPECT_DOUBLE_EQ(available_memory(), 64.0 * 1024 * 1024);
  const Scene scene = parse_scene_string("schema_version = 1\n[mesh]\nn = 400\n", "big.toml");
  try {
    build_problem(scene);
    FAIL() << "expected a refusal";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("big.toml:3"), std::string::npos) << m;
    EXPECT_NE(m.find("needs an estimated"), std::string::npos) << m;
    EXPECT_NE(m.find("HEMIVEM_MEMORY_LIMIT"), std::string::npos) << m;
  }
  const Scene small = parse_scene_string("schema_version = 1\n[mesh]\nn = 4\n", "small.toml");
  EXPECT_NO_THROW(build_problem(small));
  for (const char* bad : {"lots", "-5G", "12X", "0"}) {
    setenv("HEMIVEM_MEMORY_LIMIT", bad, 1);
    EXPECT_THROW(available_memory(), InputError) << bad;
  }
  unsetenv("HEMIVEM_MEMORY_LIMIT");
  EXPECT_GT(available_memory(), 0.0);
}

// Across processes the check counts every process: measured (petsc-gamg, the 3D Example 4.1,
// result.json only, each process's peak resident memory added up on this 2-core machine):
// cubes n = 24 one process 218 MB, 2: 271, 4: 404, 8: 681, 16: 1258 MB; n = 48 one process
// 1426 MB, 2: 1464, 4: 1618, 8: 2054, 16: 3048 MB.
TEST_F(MemoryLimit, ARunAcrossProcessesCountsEveryProcess) {
  const auto full_space = [](int n) {
    return full_space_memory(estimate_memory_3d("cubes", n, n, n), full_space_cost(3, "cubes", "petsc-gamg"));
  };
  const double base = full_space_cost(3, "cubes", "petsc-gamg").base_bytes;
  EXPECT_EQ(run_processes(), 1);
  EXPECT_DOUBLE_EQ(run_memory(1e9), 1e9) << "one process: its own estimate";
  const std::pair<int, double> totals24[] = {{2, 271e6}, {4, 404e6}, {8, 681e6}, {16, 1258e6}};
  const std::pair<int, double> totals48[] = {{2, 1464e6}, {4, 1618e6}, {8, 2054e6}, {16, 3048e6}};
  for (const auto& [n, totals] : {std::pair{24, std::span(totals24)}, std::pair{48, std::span(totals48)}}) {
    const double one = full_space(n).solve_bytes;
    for (const auto& [processes, measured] : totals) {
      const MemoryOfProcesses run(processes, false, base);
      EXPECT_EQ(run_processes(), processes);
      const double need = run_memory(one);
      EXPECT_DOUBLE_EQ(need, one + (processes - 1) * (base + 0.05 * (one - base))) << "the formula, by hand";
      EXPECT_GT(need, measured) << "n = " << n << ", " << processes << " processes";
      EXPECT_LT(need, 1.4 * measured) << "n = " << n << ", " << processes << " processes";
    }
  }
  {  // mumps-mpi: every process the whole problem
    const MemoryOfProcesses run(3, true, 0.0);
    EXPECT_DOUBLE_EQ(run_memory(1e9), 3e9);
  }
  EXPECT_EQ(run_processes(), 1) << "a scope ends with its object";
  // an earlier object ending first leaves the later one counting
  auto first = std::make_unique<MemoryOfProcesses>(2, true, 0.0);
  const MemoryOfProcesses second(4, true, 0.0);
  first.reset();
  EXPECT_EQ(run_processes(), 4);
  // the refusal says across how many processes, with one process's estimate
  setenv("HEMIVEM_MEMORY_LIMIT", "3G", 1);
  EXPECT_NO_THROW(require_memory(0.7 * 1024 * 1024 * 1024, "a mesh", "here"));
  try {
    require_memory(1024.0 * 1024 * 1024, "a mesh", "here");
    FAIL() << "4 processes of 1 GiB each are more than 3 GiB";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("needs an estimated 4.0 GiB of memory across 4 processes (1.0 GiB in one process)"),
              std::string::npos)
        << m;
  }
}

// ---- regions by box ----------------------------------------------------------------------

TEST(SceneRegions, BoxesAssignRegionsByCentroidAndRoundTrip) {
  const Scene scene = parse_scene_string(
      "schema_version = 1\n[mesh]\nn = 4\n[material]\nE = 1.0\n[[material.region]]\nid = 1\nE = 1e6\nnu = 0.3\n"
      "box = [0.0, 1.0, 0.5, 1.0]\n",
      "regions.toml");
  ASSERT_EQ(scene.material.regions.size(), 1u);
  const auto built = build_problem(scene);
  int upper = 0;
  for (int e = 0; e < built->mesh.num_elements(); ++e) {
    const bool top = built->mesh.centroid(e).y() > 0.5;
    EXPECT_EQ(built->mesh.region(e), top ? 1 : 0) << e;
    upper += top;
  }
  EXPECT_EQ(upper, 8);
  EXPECT_EQ(parse_scene_string(to_toml(scene), "again.toml"), scene);
  EXPECT_THROW(parse_scene_string("schema_version = 1\n[[material.region]]\nid = 1\nE = 1.0\nnu = 0.3\nbox = [1.0, 0.0, 0.0, 1.0]\n",
                                  "bad.toml"),
               InputError);
}

// ---- the extreme scenes ------------------------------------------------------------------

ContactSolution solve_file(const std::string& name, const std::string& linear = "eigen") {
  const Scene scene = parse_scene(extreme_dir() / (name + ".toml"));
  const auto built = build_problem(scene);
  const auto ssn = make_minimizer("ssn");
  return solve_contact(built->problem, engine(linear), *ssn, MinimizerOptions{});
}

TEST(ExtremeScenes, LoadsPressEveryNodeToTheBoundOrLiftTheBodyOff) {
  const ContactSolution pressed = solve_file("all-at-bound");
  ASSERT_TRUE(pressed.converged());
  ASSERT_FALSE(pressed.contact.empty());
  for (const auto& c : pressed.contact) EXPECT_EQ(c.state, ContactState::at_gap) << c.vertex;
  const ContactSolution lifted = solve_file("lift-off");
  ASSERT_TRUE(lifted.converged());
  for (const auto& c : lifted.contact) {
    EXPECT_EQ(c.state, ContactState::separated) << c.vertex;
    EXPECT_LT(c.u_nu, 0.0) << c.vertex;
    EXPECT_EQ(c.reaction, 0.0);
  }
}

TEST(ExtremeScenes, GapsZeroAndTinyHoldTheContactNodes) {
  for (const char* name : {"gap-zero", "gap-1e-10"}) {
    const ContactSolution s = solve_file(name);
    ASSERT_TRUE(s.converged()) << name;
    const double g = std::string(name) == "gap-zero" ? 0.0 : 1e-10;
    for (const auto& c : s.contact) EXPECT_LE(std::abs(c.u_nu), g + 1e-12 * std::max(g, 1e-300)) << name;
  }
}

TEST(ExtremeScenes, PolylineNormalBisectsAtTheKink) {
  const Scene scene = parse_scene(extreme_dir() / "polyline-contact.toml");
  const auto built = build_problem(scene);
  const LinearSystem sys = assemble(built->problem.elasticity);
  const ContactBoundary b = make_contact_boundary(built->mesh, built->problem.parts[0].facets, sys.dofs,
                                                  [](const Vec2&) { return 0.02; });
  ASSERT_EQ(b.size(), 31);
  const double s = 1.0 / std::sqrt(1.0 + 0.04);  // edge normals (+-0.2, -1)/|.|
  for (int i = 0; i < b.size(); ++i) {
    const Vec2 x = built->mesh.vertex(b.nodes[static_cast<std::size_t>(i)]);
    const Vec2 n = b.normals[static_cast<std::size_t>(i)];
    if (std::abs(x.x() - 0.5) < 1e-12) {
      EXPECT_NEAR(n.x(), 0.0, 1e-14);
      EXPECT_NEAR(n.y(), -1.0, 1e-14);
    } else {
      EXPECT_NEAR(n.x(), (x.x() < 0.5 ? -0.2 : 0.2) * s, 1e-14) << x.transpose();
      EXPECT_NEAR(n.y(), -s, 1e-14);
    }
  }
}

TEST(ExtremeScenes, EveryEngineCondensesTheAspectRatio1000Strip) {
  // Q^T A Q of this strip has round-off asymmetry that once made MUMPS reject the pattern
  const ContactSolution ref = solve_file("aspect-1000", "eigen");
  ASSERT_TRUE(ref.converged());
  const double scale = ref.u.cwiseAbs().maxCoeff();
  for (const auto& name : available_factorizations()) {
    const ContactSolution s = solve_file("aspect-1000", name);
    ASSERT_TRUE(s.converged()) << name;
    EXPECT_LT((s.u - ref.u).cwiseAbs().maxCoeff(), 1e-8 * scale) << name;
  }
}

TEST(ExtremeScenes, NearlyIncompressibleAndStiffCasesConvergeAndAgree) {
  for (const char* name : {"nu-0.4999", "bimaterial-1e6", "stiff-law-1e6", "jump-law", "tiny-edges"}) {
    const ContactSolution a = solve_file(name, "eigen");
    ASSERT_TRUE(a.converged()) << name;
    EXPECT_TRUE(a.u.allFinite()) << name;
    for (const auto& linear : available_factorizations()) {
      const ContactSolution b = solve_file(name, linear);
      ASSERT_TRUE(b.converged()) << name << " " << linear;
      EXPECT_LT((a.u - b.u).cwiseAbs().maxCoeff(), 1e-6 * a.u.cwiseAbs().maxCoeff()) << name << " " << linear;
    }
  }
}

}  // namespace
}  // namespace hemivem
