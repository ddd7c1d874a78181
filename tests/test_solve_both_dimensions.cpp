// One suite for plane and solid bodies (a typed test over the dimension), through the one entry
// point: a block between rollers on a linear foundation (scenes/block-between-rollers.toml and
// its solid twin) is in uniaxial strain, exact for the lowest-order virtual element. Every
// contact node settles by the load over the foundation's stiffness, 2 / 50 = 0.04; the top by
// 0.04 + p H / (lambda + 2 mu) with H = 1 (plane strain and the solid share lambda + 2 mu =
// 134.615...); the foundation carries the pressure 2 over the contact boundary; the potential
// energy is -1/2 p |top| u_top; the only motion the supports leave is held by the foundation;
// along a path every step is t times this, and the last is the static solve.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "test_support.hpp"

namespace hemivem::app {
namespace {

template <int d>
using Dim = std::integral_constant<int, d>;

template <class D>
class BothDimensions : public ::testing::Test {
 public:
  static constexpr int dim = D::value;
  /// The scene, on a small mesh, with `overrides`.
  static Scene scene(std::vector<std::string> overrides = {}) {
    Scene s = parse_scene(test::scenes_dir() / (dim == 2 ? "block-between-rollers.toml" : "block-between-rollers-3d.toml"));
    overrides.insert(overrides.begin(), dim == 2 ? "mesh.n=[8, 2]" : "mesh.n=[4, 3, 2]");
    apply_overrides(s, overrides);
    return s;
  }
  /// The length (2D) or area (3D) of the contact boundary and of the loaded top.
  static double measure() { return dim == 2 ? 4.0 : 3.0; }
};

using Dimensions = ::testing::Types<Dim<2>, Dim<3>>;
class DimensionName {
 public:
  template <class D>
  static std::string GetName(int) {
    return D::value == 2 ? "plane" : "solid";
  }
};
TYPED_TEST_SUITE(BothDimensions, Dimensions, DimensionName);

constexpr double kSettle = 2.0 / 50.0;
const double kTop = kSettle + 2.0 / (100.0 * (1.0 - 0.3) / ((1.0 + 0.3) * (1.0 - 2.0 * 0.3)));

TYPED_TEST(BothDimensions, ABlockOnAFoundationSettlesByTheLoadOverTheStiffness) {
  constexpr int dim = TestFixture::dim;
  const SceneRun run = run_scene(TestFixture::scene());
  ASSERT_EQ(run.dimension(), dim);
  const auto* solved = run.template solve<dim>();
  ASSERT_NE(solved, nullptr);
  const auto& sol = solved->solution;
  ASSERT_TRUE(sol.converged()) << sol.message;
  ASSERT_FALSE(sol.contact.empty());
  for (const auto& n : sol.contact) {
    EXPECT_NEAR(n.u_nu, kSettle, 1e-10) << n.vertex;
    EXPECT_NEAR(n.pressure(), 2.0, 1e-8) << n.vertex;
  }
  EXPECT_NEAR(sol.contact_force()(dim - 1), 2.0 * TestFixture::measure(), 1e-8);
  // the top: every vertex at the largest last coordinate settles by kTop
  const auto& mesh = solved->built->mesh;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.vertex(v)(dim - 1) == 1.0) EXPECT_NEAR(sol.u(dim * v + dim - 1), -kTop, 1e-10) << v;
  EXPECT_NEAR(sol.energy, -0.5 * 2.0 * TestFixture::measure() * kTop, 1e-10);
  EXPECT_LE(sol.forces.residual(), 1e-12);
}

TYPED_TEST(BothDimensions, TheFoundationAloneHoldsTheVerticalTranslation) {
  constexpr int dim = TestFixture::dim;
  const SceneRun run = run_scene(TestFixture::scene());
  const auto& held = run.template solve<dim>()->solution.held_by_contact;
  ASSERT_EQ(held.size(), 1u);
  EXPECT_NE(held[0].find("translation"), std::string::npos) << held[0];
}

TYPED_TEST(BothDimensions, EveryStepOfAPathIsTTimesTheStaticSolve) {
  constexpr int dim = TestFixture::dim;
  const SceneRun statics = run_scene(TestFixture::scene());
  const SceneRun path = run_scene(TestFixture::scene({"path.steps=4"}));
  const auto* solved = path.template solve<dim>();
  ASSERT_NE(solved, nullptr);
  ASSERT_NE(solved->path, nullptr);
  ASSERT_EQ(solved->path->steps.size(), 4u);
  for (const auto& step : solved->path->steps) {
    ASSERT_TRUE(step.converged()) << step.index << ": " << step.message;
    for (const auto& n : step.contact) EXPECT_NEAR(n.u_nu, kSettle * step.t, 1e-10) << step.index;
    EXPECT_NEAR(step.contact_force(dim - 1), 2.0 * TestFixture::measure() * step.t, 1e-8) << step.index;
  }
  const Eigen::VectorXd& u = statics.template solve<dim>()->solution.u;
  EXPECT_LE((solved->solution.u - u).cwiseAbs().maxCoeff(), 1e-10 * u.cwiseAbs().maxCoeff());
}

TYPED_TEST(BothDimensions, TheReportNamesWhatTheSolveFound) {
  const SceneRun run = run_scene(TestFixture::scene());
  const std::string report = run.report(run.info());
  for (const char* line : {"  status        converged", "  supports      free, held by the contact alone: translation",
                           "  uniqueness    ", "  forces        applied ", "  energy        potential "})
    EXPECT_NE(report.find(line), std::string::npos) << line << "\n" << report;
  EXPECT_EQ(report.find("(three-dimensional)") != std::string::npos, TestFixture::dim == 3) << report;
}

}  // namespace
}  // namespace hemivem::app
