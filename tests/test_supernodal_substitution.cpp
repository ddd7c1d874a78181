// The substitutions with a supernodal factor for a few right-hand sides
// (backends/linear/common/supernodal_substitution.hpp), on one thread and split between two,
// against a dense triangular solve with the same factor.
#include "supernodal_substitution.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace hemivem::linear_detail {
namespace {

/// A supernodal factor written by hand: each supernode's first column, its rows (its own
/// columns, then the rows below) and a column-major block whose unused upper part is NaN, so
/// that a substitution that reads it gives NaN.
struct HandFactor {
  int n2 = 0, end = 0;
  std::vector<std::vector<int>> rows;
  std::vector<std::vector<double>> blocks;
  std::vector<SupernodePiece> pieces;
  Eigen::MatrixXd dense;  // end x n2: L22 above L21

  HandFactor(int n2_, int end_, const std::vector<std::pair<int, std::vector<int>>>& supernodes) : n2(n2_), end(end_) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> off(-0.5, 0.5), diag(3.0, 5.0);
    dense = Eigen::MatrixXd::Zero(end, n2);
    for (std::size_t k = 0; k < supernodes.size(); ++k) {
      const int j0 = supernodes[k].first;
      const int j1 = k + 1 < supernodes.size() ? supernodes[k + 1].first : n2;
      std::vector<int> r;
      for (int j = j0; j < j1; ++j) r.push_back(j);
      r.insert(r.end(), supernodes[k].second.begin(), supernodes[k].second.end());
      const int nc = j1 - j0, ld = static_cast<int>(r.size());
      std::vector<double> b(static_cast<std::size_t>(ld * nc), std::numeric_limits<double>::quiet_NaN());
      for (int j = 0; j < nc; ++j)
        for (int i = j; i < ld; ++i) {
          const double v = i == j ? diag(random) : off(random);
          b[static_cast<std::size_t>(j * ld + i)] = v;
          dense(r[static_cast<std::size_t>(i)], j0 + j) = v;
        }
      rows.push_back(std::move(r));
      blocks.push_back(std::move(b));
    }
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const int j0 = supernodes[k].first;
      const int nc = (k + 1 < supernodes.size() ? supernodes[k + 1].first : n2) - j0;
      pieces.push_back({j0, nc, static_cast<int>(rows[k].size()) - nc, static_cast<int>(rows[k].size()), rows[k].data(),
                        blocks[k].data()});
    }
  }

  /// forward: Z2 = L22^{-1} Z2, Z1 -= L21 Z2; backward: Z2 = L22^{-T} (Z2 - L21^T Z1).
  Eigen::MatrixXd reference(const Eigen::MatrixXd& B, bool forward) const {
    const Eigen::MatrixXd L22 = dense.topRows(n2), L21 = dense.bottomRows(end - n2);
    Eigen::MatrixXd X = B;
    if (forward) {
      X.topRows(n2) = L22.triangularView<Eigen::Lower>().solve(B.topRows(n2));
      X.bottomRows(end - n2) -= L21 * X.topRows(n2);
    } else {
      X.topRows(n2) = L22.transpose().triangularView<Eigen::Upper>().solve(B.topRows(n2) - L21.transpose() * B.bottomRows(end - n2));
    }
    return X;
  }
};

template <int M>
Eigen::MatrixXd substituted(const HandFactor& f, const SubstitutionSchedule& s, const Eigen::MatrixXd& B, bool forward) {
  Eigen::MatrixXd z = B.transpose();  // row-major rows of M values
  if (forward)
    forward_few<M>(f.pieces, s, z.data());
  else
    backward_few<M>(f.pieces, s, z.data());
  return z.transpose();
}

template <int M>
void expect_both_passes_match(const HandFactor& f, const SubstitutionSchedule& s) {
  std::mt19937 random(11 + M);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(f.end, M);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = u(random);
  for (bool forward : {true, false}) {
    const Eigen::MatrixXd X = substituted<M>(f, s, B, forward), R = f.reference(B, forward);
    ASSERT_TRUE(X.allFinite()) << "M = " << M << (forward ? " forward" : " backward");
    EXPECT_LE((X - R).cwiseAbs().maxCoeff(), 1e-13 * R.cwiseAbs().maxCoeff())
        << "M = " << M << (forward ? " forward" : " backward");
  }
}

template <int... M>
void expect_all_match(const HandFactor& f, const SubstitutionSchedule& s) {
  (expect_both_passes_match<M>(f, s), ...);
}

// Two chains of two supernodes under one top supernode, with rows below L22 (end > n2): the
// chains hold the same work, so the schedule gives one to each thread and keeps the top.
HandFactor two_balanced_chains() {
  return HandFactor(16, 18,
                    {{0, {3, 4, 5, 12, 14}},
                     {3, {12, 13, 15, 16, 17}},
                     {6, {9, 10, 13, 15, 16}},
                     {9, {12, 13, 14, 15, 17}},
                     {12, {16, 17}}});
}

TEST(SupernodalSubstitution, SplitBetweenTwoThreadsMatchesTheDenseSolve) {
  const HandFactor f = two_balanced_chains();
  const SubstitutionSchedule s = schedule_substitution(f.pieces, f.n2, f.end, 0.0);
  ASSERT_TRUE(s.split);
  ASSERT_EQ(s.top, std::vector<int>{4});
  ASSERT_EQ(s.ranges[0].size(), 1u);
  ASSERT_EQ(s.ranges[1].size(), 1u);
  EXPECT_EQ(s.ranges[0][0].end - s.ranges[0][0].begin, 2);
  EXPECT_EQ(s.ranges[1][0].end - s.ranges[1][0].begin, 2);
  // the top's four columns and the two rows below L22 take their updates in slots
  EXPECT_EQ(s.slot_row, (std::vector<int>{12, 13, 14, 15, 16, 17}));
  expect_all_match<1, 2, 3, 4>(f, s);
}

TEST(SupernodalSubstitution, InOrderOnOneThreadMatchesTheDenseSolve) {
  const HandFactor f = two_balanced_chains();
  const SubstitutionSchedule s = schedule_substitution(f.pieces, f.n2, f.end, 1e12);  // too small to split
  EXPECT_FALSE(s.split);
  expect_all_match<1, 2, 3, 4>(f, s);
}

TEST(SupernodalSubstitution, InteriorRowsOnlyAndTheSplitGiveTheSameAsInOrder) {
  // the interior solve reads the rows up to n2 only: drop the rows below L22
  const HandFactor whole = two_balanced_chains();
  HandFactor f = whole;
  f.end = f.n2;
  f.dense = whole.dense.topRows(f.n2);
  for (std::size_t k = 0; k < f.pieces.size(); ++k) {
    f.pieces[k].rows = f.rows[k].data();
    f.pieces[k].values = f.blocks[k].data();
    int count = 0;
    while (count < f.pieces[k].count && f.rows[k][static_cast<std::size_t>(f.pieces[k].nc + count)] < f.n2) ++count;
    f.pieces[k].count = count;
  }
  const SubstitutionSchedule split = schedule_substitution(f.pieces, f.n2, f.end, 0.0), in_order;
  ASSERT_TRUE(split.split);
  expect_all_match<1, 3>(f, split);
  // the backward pass does the same operations in either schedule: the same to the bit
  const Eigen::MatrixXd B = Eigen::VectorXd::LinSpaced(f.end * 2, -1.0, 2.0).reshaped(f.end, 2);
  EXPECT_TRUE(substituted<2>(f, split, B, false) == substituted<2>(f, in_order, B, false));
}

TEST(SupernodalSubstitution, NoSplitWhenOneSubtreeHoldsMostOfTheWork) {
  // one long chain: every split leaves a set far heavier than the other
  const HandFactor f(12, 12, {{0, {4, 8}}, {4, {8, 9}}, {8, {}}});
  const SubstitutionSchedule s = schedule_substitution(f.pieces, f.n2, f.end, 0.0);
  EXPECT_FALSE(s.split);
  expect_all_match<1, 2>(f, s);
}

TEST(SupernodalSubstitution, ANotPostorderedFactorIsNotSplit) {
  // the first supernode's rows below name a supernode before it
  const HandFactor f(8, 8, {{0, {}}, {4, {1, 2}}});
  // (a factor in postorder never has this; the schedule refuses to split it)
  const SubstitutionSchedule s = schedule_substitution(f.pieces, f.n2, f.end, 0.0);
  EXPECT_FALSE(s.split);
}

}  // namespace
}  // namespace hemivem::linear_detail
