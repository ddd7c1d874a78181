// Piecewise-polynomial contact laws: values by hand, DC split, one-sided derivatives,
// Clarke subdifferential, alpha_j and the validation of malformed laws.
#include <hemivem/error.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace hemivem;

namespace {

// (4.7) written out independently
double paper_j(double r) {
  if (r <= 0) return 0;
  if (r <= 0.01) return 30 * r * r;
  if (r < 0.02) return 0.8 * r - 10 * r * r - 0.004;
  return 30 * r * r - 0.8 * r + 0.012;
}

TEST(ContactLaw, PaperLawValuesSplitAndAlpha) {
  const auto law = paper_law();
  for (double r = -0.05; r <= 0.06; r += 0.00037) {
    EXPECT_NEAR(law->value(r), paper_j(r), 1e-15);
    EXPECT_NEAR(law->value(LawPart::j2, r), 10 * r * r, 1e-15);  // the split (4.8) leaves j2 = 10 r^2
    EXPECT_NEAR(law->value(LawPart::j1, r) - law->value(LawPart::j2, r), law->value(r), 1e-15);
    // derivative by central differences away from breakpoints
    const double d = 1e-7;
    EXPECT_NEAR(law->derivative(LawPart::j, r, +1), (paper_j(r + d) - paper_j(r - d)) / (2 * d), 1e-6);
  }
  EXPECT_DOUBLE_EQ(law->alpha(), 20.0);
  EXPECT_FALSE(law->is_convex());
  // the law is C^1: the Clarke subdifferential is a point everywhere
  for (double b : {0.0, 0.01, 0.02}) {
    const Interval c = law->clarke(b);
    EXPECT_NEAR(c.hi - c.lo, 0.0, 1e-14) << b;
  }
  EXPECT_NEAR(law->clarke(0.01).lo, 0.6, 1e-14);
  EXPECT_NEAR(law->clarke(0.02).lo, 0.4, 1e-14);
  EXPECT_DOUBLE_EQ(law->second_derivative(LawPart::j, 0.015, -1), -20.0);
  EXPECT_DOUBLE_EQ(law->second_derivative(LawPart::j, 0.01, -1), 60.0);
  EXPECT_DOUBLE_EQ(law->second_derivative(LawPart::j, 0.01, +1), -20.0);
}

TEST(ContactLaw, SawtoothHasAConcaveKink) {
  const double k = 100, r1 = 0.01, res = 0.2, r2 = 0.02;
  const auto law = sawtooth_law(k, r1, res, r2);
  EXPECT_EQ(law->alpha(), std::numeric_limits<double>::infinity());
  EXPECT_NEAR(law->derivative(LawPart::j, r1, -1), k * r1, 1e-14);
  EXPECT_NEAR(law->derivative(LawPart::j, r1, +1), res, 1e-14);
  const Interval c = law->clarke(r1);
  EXPECT_NEAR(c.lo, res, 1e-14);
  EXPECT_NEAR(c.hi, k * r1, 1e-14);
  EXPECT_TRUE(c.contains(0.5));
  // continuity of j and values by hand
  EXPECT_NEAR(law->value(r1), 0.5 * k * r1 * r1, 1e-16);
  EXPECT_NEAR(law->value(0.015), 0.5 * k * r1 * r1 + res * 0.005, 1e-16);
  EXPECT_NEAR(law->value(0.03), 0.5 * k * r1 * r1 + res * 0.02 + 0.5 * k * 0.01 * 0.01, 1e-15);
  EXPECT_NEAR(law->derivative(LawPart::j, 0.03, +1), res + k * 0.01, 1e-13);
  // j1, j2 convex: derivatives do not drop at the breakpoints
  for (LawPart p : {LawPart::j1, LawPart::j2})
    for (double b : law->breakpoints()) EXPECT_GE(law->derivative(p, b, +1), law->derivative(p, b, -1) - 1e-14);
}

TEST(ContactLaw, LinearAndZeroLaws) {
  const auto lin = linear_law(50.0);
  EXPECT_DOUBLE_EQ(lin->value(-0.2), 0.5 * 50 * 0.04);
  EXPECT_DOUBLE_EQ(lin->derivative(LawPart::j, 0.3, -1), 15.0);
  EXPECT_TRUE(lin->is_convex());
  const auto zero = zero_law();
  EXPECT_EQ(zero->value(3.0), 0.0);
  EXPECT_EQ(zero->clarke(1.0).hi, 0.0);
  EXPECT_TRUE(zero->is_convex());
}

TEST(ContactLaw, ConvexKinkKeepsAlphaZero) {
  // j = |r|: convex with a kink; Clarke subdifferential [-1, 1] at 0
  const PiecewisePolynomialLaw law("abs", {0.0}, {{0.0, -1.0}, {0.0, 1.0}}, {{0.0}, {0.0}});
  EXPECT_EQ(law.alpha(), 0.0);
  EXPECT_DOUBLE_EQ(law.clarke(0.0).lo, -1.0);
  EXPECT_DOUBLE_EQ(law.clarke(0.0).hi, 1.0);
  EXPECT_DOUBLE_EQ(law.clarke(0.5).lo, 1.0);
}

void expect_invalid(const std::function<void()>& build, const std::string& fragment) {
  try {
    build();
    FAIL() << "expected InputError containing '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(ContactLaw, MalformedLawsAreRejected) {
  expect_invalid([] { PiecewisePolynomialLaw("gap", {0.0}, {{0.0}, {1.0}}, {{0.0}, {0.0}}); },
                 "j1 is not continuous at breakpoint 0");
  expect_invalid([] { PiecewisePolynomialLaw("concave", {}, {{0.0, 0.0, -1.0}}, {{0.0}}); }, "j1 is not convex on piece 0");
  expect_invalid([] { PiecewisePolynomialLaw("kink", {0.0}, {{0.0}, {0.0}}, {{0.0, 1.0}, {0.0, -1.0}}); },
                 "j2 is not convex at breakpoint 0");
  expect_invalid([] { PiecewisePolynomialLaw("order", {0.1, 0.1}, {{0}, {0}, {0}}, {{0}, {0}, {0}}); },
                 "breakpoints must increase strictly");
  expect_invalid([] { PiecewisePolynomialLaw("count", {0.1}, {{0}}, {{0}, {0}}); }, "need 2 pieces");
  expect_invalid([] { PiecewisePolynomialLaw("cubic", {}, {{0.0, 0.0, 0.0, 1.0}}, {{0.0}}); }, "j1 is not convex on piece 0");
  expect_invalid([] { PiecewisePolynomialLaw("nan", {}, {{std::nan("")}}, {{0.0}}); }, "non-finite coefficient");
  expect_invalid([] { make_contact_law("coulomb"); }, "expected one of: paper, linear, kinked, sawtooth, zero");
  expect_invalid([] { sawtooth_law(100, 0.01, 5.0, 0.02); }, "residual < stiffness * r1");
}

TEST(ContactLaw, LookupByName) {
  for (const auto& n : contact_law_names()) EXPECT_EQ(make_contact_law(n)->name(), n);
  EXPECT_EQ(make_contact_law("PAPER")->name(), "paper");
}

}  // namespace
