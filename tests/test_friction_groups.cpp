// The motion of a group of two friction coordinates in a projected Newton iteration
// (hemivem/group_motion.hpp): the classification at and near the cone point 0 of a Tresca law,
// and the trial points of a group pinned onto it.
#include <hemivem/group_motion.hpp>

#include <hemivem/contact/piecewise_law.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace hemivem;

namespace {

constexpr double kBound = 0.8, kWeight = 0.25;  // the force bound w g = 0.2

const Eigen::Matrix2d kBlock = (Eigen::Matrix2d() << 4.0, 1.0, 1.0, 3.0).finished();

TEST(FrictionGroups, AtTheConePointAGroupSticksWithinTheBoundAndLeavesAlongItsGradientBeyond) {
  const auto law = tresca_law(kBound);
  const GroupMotion stuck = group_motion(*law, kWeight, Eigen::Vector2d::Zero(), Eigen::Vector2d(0.12, -0.16), kBlock);
  EXPECT_EQ(stuck.mode, GroupMotion::Mode::stuck);  // |gq| = 0.2 <= w g
  EXPECT_EQ(stuck.grad, Eigen::Vector2d::Zero());
  const GroupMotion ray = group_motion(*law, kWeight, Eigen::Vector2d::Zero(), Eigen::Vector2d(0.3, -0.4), kBlock);
  ASSERT_EQ(ray.mode, GroupMotion::Mode::ray);  // |gq| = 0.5 > w g
  EXPECT_NEAR(ray.e(0), -0.6, 1e-15);
  EXPECT_NEAR(ray.e(1), 0.8, 1e-15);
  // the gradient along the ray: |gq| less the bound, against e
  EXPECT_NEAR(ray.grad.dot(ray.e), -(0.5 - kWeight * kBound), 1e-15);
}

// A group a hair's breadth from 0 (a radius of 1e-28, its frame v / |v| set by that hair) pushed
// towards 0 is pinned onto it, and every trial point of its step is exactly 0: a step shortened
// by the line search must not leave it at v / 2, v / 4, ..., where its frame never says which way
// it should leave.
TEST(FrictionGroups, AGroupPinnedOntoTheConePointIsThereAtEveryStep) {
  const auto law = tresca_law(kBound);
  const Eigen::Vector2d v(1e-28, 0.0);
  GroupMotion g = group_motion(*law, kWeight, v, Eigen::Vector2d(0.3, -0.4), kBlock);
  ASSERT_EQ(g.mode, GroupMotion::Mode::plane);
  ASSERT_GT(g.grad.dot(g.e), 0.0);  // pushed towards 0
  pin_group(g, 1e-12);
  ASSERT_EQ(g.pin, 0.0);
  for (const double t : {1.0, 0.5, 0.25, 1.0 / 1024.0}) {
    SCOPED_TRACE(t);
    const Eigen::Vector2d y = group_trial(g, -v, t);
    EXPECT_EQ(y(0), 0.0);
    EXPECT_EQ(y(1), 0.0);
  }
  // at 0 the group is classified afresh: it leaves along its gradient
  const GroupMotion at0 = group_motion(*law, kWeight, Eigen::Vector2d::Zero(), Eigen::Vector2d(0.3, -0.4), kBlock);
  EXPECT_EQ(at0.mode, GroupMotion::Mode::ray);
  // farther from 0 than eps it is not pinned
  GroupMotion far = group_motion(*law, kWeight, Eigen::Vector2d(1e-3, 0.0), Eigen::Vector2d(0.3, -0.4), kBlock);
  pin_group(far, 1e-6);
  EXPECT_TRUE(std::isnan(far.pin));
}

}  // namespace
