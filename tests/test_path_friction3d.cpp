// Coulomb's law on a solid's surface along a loading path: a sphere pressed into a block, then
// the block dragged sideways. At every step and every node, checked here from the step's
// results alone: the bound is mu times the node's pressure; the friction force never exceeds
// it; where the node slipped in the step the force is at the bound and points along the step's
// slip (against the motion of the body), and where it stuck the step left its tangential
// displacement unchanged.
#include <gtest/gtest.h>

#include <hemivem/app/run.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace hemivem::app {
namespace {

constexpr double mu = 0.3;

const std::string scene_text = R"toml(schema_version = 1
[mesh]
generator = "cubes"
n = [8, 4, 4]
domain = [-0.25, 0.25, 0.0, 0.25, 0.0, 0.25]
[material]
E = 65.0
nu = 0.3
[[dirichlet]]
side = "bottom"
value = ["0.0015*max(t - 1, 0)", "0.0", "0.004*min(t, 1)"]
[[dirichlet]]
side = "y0"
uy = 0.0
[contact]
side = "top"
law = "zero"
constraint = "one-sided"
[contact.obstacle]
shape = "sphere"
center = [0.0, 0.0, 1.25]
radius = 1.0
[contact.friction]
law = "coulomb"
coefficient = 0.3
[path]
t = [0.5, 1.0, 1.25, 1.5, 1.75, 2.0]
)toml";

TEST(SolidCoulombPath, EveryNodeKeepsCoulombsLawAtEveryStep) {
  const SceneRun run = run_scene(parse_scene_string(scene_text, "coulomb3d.toml"));
  const BasicPathSolution<3>* path = run.solid_path();
  ASSERT_NE(path, nullptr);
  ASSERT_TRUE(path->converged());
  ASSERT_EQ(path->steps.size(), 6u);
  int slipped = 0, stuck = 0;
  for (std::size_t k = 0; k < path->steps.size(); ++k) {
    const BasicPathStep<3>& s = path->steps[k];
    SCOPED_TRACE(testing::Message() << "step " << s.index);
    ASSERT_TRUE(s.converged()) << s.message;
    ASSERT_EQ(s.slip.size(), static_cast<Eigen::Index>(s.contact.size()));
    double force_scale = 0.0;
    for (const auto& n : s.contact) force_scale = std::max(force_scale, std::abs(n.force()));
    ASSERT_GT(force_scale, 0.0);
    const double tol = 1e-8 * force_scale;
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      const auto& n = s.contact[i];
      const auto ii = static_cast<Eigen::Index>(i);
      const double bound = mu * std::max(n.force(), 0.0);  // mu times the normal contact force
      EXPECT_NEAR(s.friction_bound(ii) * n.weight, bound, tol) << "vertex " << n.vertex;
      EXPECT_LE(n.friction_vector.norm(), bound + tol) << "vertex " << n.vertex;
      EXPECT_NEAR(n.friction_vector.dot(n.normal), 0.0, tol);
      const Vec3 before = k == 0 ? Vec3::Zero() : path->steps[k - 1].contact[i].u_tangential;
      const Vec3 slip = n.u_tangential - before;
      EXPECT_NEAR(slip.norm(), s.slip(ii), 1e-12 * std::max(1.0, slip.norm()));
      if (n.friction_state == FrictionState::stick) {
        EXPECT_EQ(s.slip(ii), 0.0) << "vertex " << n.vertex;
        stuck += bound > tol;
      } else if (bound > tol) {
        // slipping under a positive bound: the force at the bound, along the slip
        EXPECT_NEAR(n.friction_vector.norm(), bound, tol) << "vertex " << n.vertex;
        EXPECT_LT((n.friction_vector - bound * slip.normalized()).norm(), tol) << "vertex " << n.vertex;
        ++slipped;
      }
    }
  }
  // the pressed sphere sticks at the centre of its zone and the drag makes the rim slip
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slipped, 0);
}

}  // namespace
}  // namespace hemivem::app
