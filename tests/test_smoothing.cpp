// The smoothed contact law j_eps shared by the smoothing-based engines (nlopt-mma,
// ceres-active-set): equal to j away from the rounded breakpoints, C^1 across the windows,
// |j_eps - j| = O(eps |jump of j'|), bounded curvature, accurate differences.
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/smoothed_law.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace hemivem;
using hemivem::smoothing::SmoothedLaw;

namespace {

double jump(const ContactLaw& law, double b) {
  return std::abs(law.derivative(LawPart::j, b, +1) - law.derivative(LawPart::j, b, -1));
}

// max |j_eps - j| over a fine grid of the windows
double max_value_error(const SmoothedLaw& s) {
  double e = 0.0;
  for (const auto& w : s.windows())
    for (int k = 0; k <= 1000; ++k) {
      const double r = w.lo + (w.hi - w.lo) * k / 1000.0;
      e = std::max(e, std::abs(s.value(r) - s.law().value(r)));
    }
  return e;
}

TEST(SmoothedLaw, KinksAreCountedAndOnlyTheyAreRoundedByDefault) {
  EXPECT_EQ(SmoothedLaw(paper_law(), 1e-3).kinks(), 0);  // j' is continuous, only j'' jumps
  EXPECT_TRUE(SmoothedLaw(paper_law(), 1e-3).windows().empty());
  EXPECT_EQ(SmoothedLaw(paper_law(), 1e-3, true).windows().size(), 3u);
  EXPECT_EQ(SmoothedLaw(kinked_law(), 1e-3).kinks(), 1);
  EXPECT_EQ(SmoothedLaw(sawtooth_law(), 1e-3).kinks(), 1);  // the drop at r1; 0 and r2 are j'' jumps
  EXPECT_EQ(SmoothedLaw(linear_law(), 1e-3).kinks(), 0);
  EXPECT_TRUE(SmoothedLaw(kinked_law(), 0.0).windows().empty());  // eps = 0: j itself
}

TEST(SmoothedLaw, EqualsTheLawAwayFromTheBreakpoints) {
  for (const std::string name : contact_law_names()) {
    SCOPED_TRACE(name);
    const auto law = make_contact_law(name);
    for (bool curvature : {false, true}) {
      const SmoothedLaw s(law, 1e-3, curvature);
      for (int k = -300; k <= 500; ++k) {
        const double r = 1e-4 * k + 3e-6;
        bool near = false;
        for (double b : law->breakpoints()) near = near || std::abs(r - b) <= 1e-3;
        if (near) continue;
        EXPECT_EQ(s.value(r), law->value(r)) << r;
        EXPECT_EQ(s.derivative(r), law->derivative(LawPart::j, r, +1)) << r;
        EXPECT_EQ(s.second_derivative(r), law->second_derivative(LawPart::j, r, +1)) << r;
      }
    }
  }
}

TEST(SmoothedLaw, ConvergesToTheLawAtFirstOrderInEpsilon) {
  for (const std::string name : {"kinked", "sawtooth"}) {
    SCOPED_TRACE(name);
    const auto law = make_contact_law(name);
    double J = 0.0;
    for (double b : law->breakpoints()) J = std::max(J, jump(*law, b));
    double previous = 0.0;
    for (double eps : {1e-3, 1e-4, 1e-5, 1e-6}) {
      const SmoothedLaw s(law, eps);
      const double e = max_value_error(s);
      EXPECT_LE(e, eps * J) << eps;  // |j_eps - j| <= h |jump| (3/8 h |jump| for a pure kink)
      EXPECT_GT(e, 0.05 * eps * J) << eps;
      if (previous > 0.0) {
        EXPECT_NEAR(previous / e, 10.0, 1.0) << "first order: the error falls with eps";
      }
      previous = e;
    }
  }
}

TEST(SmoothedLaw, IsC1AcrossTheWindowsWithBoundedCurvature) {
  for (const std::string name : {"kinked", "sawtooth", "paper"}) {
    SCOPED_TRACE(name);
    const auto law = make_contact_law(name);
    for (double eps : {1e-3, 1e-6}) {
      const SmoothedLaw s(law, eps, true);
      ASSERT_FALSE(s.windows().empty());
      for (const auto& w : s.windows()) {
        const double J = jump(*law, w.breakpoint);
        const double h = 0.5 * (w.hi - w.lo), d = 1e-6 * h;
        for (double x : {w.lo, w.hi}) {
          // value and slope continuous at the window ends (differences O(d))
          EXPECT_NEAR(s.value(x - d), s.value(x + d), 2 * d * (1.0 + std::abs(s.derivative(x))));
          EXPECT_NEAR(s.derivative(x - d), s.derivative(x + d), 1e-4 * (J + 1.0) + 100 * d * (1.0 + std::abs(s.second_derivative(x - d))));
        }
        // slope continuous inside the window, curvature O(jump / h)
        double max_curv = 0.0;
        for (int k = 0; k < 1000; ++k) {
          const double r = w.lo + (w.hi - w.lo) * (k + 0.5) / 1000.0, r2 = r + (w.hi - w.lo) / 1000.0;
          max_curv = std::max(max_curv, std::abs(s.second_derivative(r)));
          if (r2 < w.hi)  // j_eps' is the integral of j_eps'' (trapezoid rule)
            EXPECT_NEAR(s.derivative(r2) - s.derivative(r),
                        0.5 * (s.second_derivative(r) + s.second_derivative(r2)) * (r2 - r), 1e-6 * (J + 1.0));
        }
        const double smooth = std::abs(law->second_derivative(LawPart::j, w.lo, -1)) +
                              std::abs(law->second_derivative(LawPart::j, w.hi, +1));
        EXPECT_LE(max_curv, 3.0 * J / h + 3.0 * smooth + 1e-12);
      }
    }
  }
}

TEST(SmoothedLaw, KeepsAConvexKinkConvex) {
  const SmoothedLaw s(kinked_law(), 1e-4);
  ASSERT_EQ(s.windows().size(), 1u);
  for (int k = 0; k <= 1000; ++k) EXPECT_GE(s.second_derivative(-1e-4 + 2e-7 * k), -1e-9);
}

TEST(SmoothedLaw, WindowsDoNotOverlapNeighbouringBreakpoints) {
  const SmoothedLaw s(sawtooth_law(), 1.0, true);  // eps far above the spacing 0.01
  ASSERT_EQ(s.windows().size(), 3u);
  for (std::size_t k = 0; k + 1 < s.windows().size(); ++k) EXPECT_LT(s.windows()[k].hi, s.windows()[k + 1].lo);
  for (const auto& w : s.windows()) EXPECT_LE(w.hi - w.lo, 0.5 * 0.01 + 1e-15);
}

TEST(SmoothedLaw, DifferencesAreAccurate) {
  for (const std::string name : {"kinked", "sawtooth", "paper"}) {
    SCOPED_TRACE(name);
    const SmoothedLaw s(make_contact_law(name), 1e-3, true);
    for (double x : {-0.013, -4e-4, 0.0, 3e-4, 0.0095, 0.017})
      for (double y : {-0.02, -1e-4, 2e-4, 0.0101, 0.03}) EXPECT_NEAR(s.difference(x, y), s.value(y) - s.value(x), 1e-15);
    // near a minimizer differences far below the roundoff of the values themselves
    const double x = 0.0123456, y = x + 1e-13, dx = y - x;  // dx exact
    EXPECT_NEAR(s.difference(x, y), s.derivative(x) * dx + 0.5 * s.second_derivative(x) * dx * dx, 1e-27);
    EXPECT_GT(std::abs((s.value(y) - s.value(x)) - s.derivative(x) * dx), 1e-22) << "values alone cancel";
  }
}

}  // namespace
