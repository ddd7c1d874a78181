// Checks of the share of a problem a process poses (pose_share, hemivem/contact/pose_share.hpp).
#pragma once

#include <hemivem/contact/pose_share.hpp>

#include <gtest/gtest.h>

#include <Eigen/Core>

namespace hemivem::test {

/// Two shares are the same to the bit.
inline void expect_same_share(const PosedShare& a, const PosedShare& b) {
  EXPECT_EQ(a.layout.first, b.layout.first);
  EXPECT_EQ(a.layout.owned, b.layout.owned);
  EXPECT_EQ(a.layout.global, b.layout.global);
  EXPECT_EQ(a.layout.ghosts, b.layout.ghosts);
  ASSERT_EQ(a.share.matrix.rows(), b.share.matrix.rows());
  ASSERT_EQ(a.share.matrix.cols(), b.share.matrix.cols());
  ASSERT_EQ(a.share.matrix.nonZeros(), b.share.matrix.nonZeros());
  EXPECT_EQ(Eigen::MatrixXd(a.share.matrix), Eigen::MatrixXd(b.share.matrix));
  EXPECT_EQ(a.share.load, b.share.load);
  EXPECT_EQ(a.share.coordinate_numbers, b.share.coordinate_numbers);
  EXPECT_EQ(a.share.coordinate_rows, b.share.coordinate_rows);
  EXPECT_EQ(a.share.tied_rows, b.share.tied_rows);
  EXPECT_EQ(a.share.coordinates.w, b.share.coordinates.w);
  EXPECT_EQ(a.share.coordinates.lo, b.share.coordinates.lo);
  EXPECT_EQ(a.share.coordinates.hi, b.share.coordinates.hi);
  EXPECT_EQ(a.share.origin, b.share.origin);
  EXPECT_EQ(a.near_null_space, b.near_null_space);
  EXPECT_EQ(a.block_size, b.block_size);
}

}  // namespace hemivem::test
