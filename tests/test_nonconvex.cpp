// Nonconvex problems (docs/nonconvex.md): laws given as j alone and their computed convex
// split; the global search for the lowest critical point, against an exact enumeration of
// every face of small box problems.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <hemivem/certificate.hpp>
#include <hemivem/error.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "test_support.hpp"

namespace hemivem {
namespace {

/// a + b (r - x) + c (r - x)^2 as coefficients in r.
Polynomial about(double a, double b, double c, double x) { return {a - b * x + c * x * x, b - 2.0 * c * x, c}; }

/// Both parts convex on a fine grid and at every breakpoint (one-sided derivatives do not drop),
/// and j1 - j2 = j (the law's own j) everywhere; checked numerically, independently of the
/// validation in the constructor.
void expect_convex_split(const ContactLaw& law, double lo, double hi) {
  const int n = 4000;
  const double h = (hi - lo) / n;
  for (LawPart part : {LawPart::j1, LawPart::j2}) {
    for (int k = 1; k < n; ++k) {
      const double r = lo + k * h;
      const double second = law.value(part, r - h) - 2.0 * law.value(part, r) + law.value(part, r + h);
      const double size = std::abs(law.value(part, r - h)) + std::abs(law.value(part, r + h)) + 1e-300;
      EXPECT_GE(second, -1e-12 * size) << "part " << static_cast<int>(part) << " at r = " << r;
    }
    for (double b : law.breakpoints())
      EXPECT_GE(law.derivative(part, b, +1), law.derivative(part, b, -1) - 1e-12 * (1.0 + std::abs(law.derivative(part, b, -1))))
          << "at breakpoint " << b;
  }
}

TEST(SplitFromJ, PaperLawReproducesJWithASmallerConcavePart) {
  // (4.7) as j alone
  const auto law = PiecewisePolynomialLaw::from_j(
      "paper-j", {0.0, 0.01, 0.02}, {{0.0}, {0.0, 0.0, 30.0}, {-0.004, 0.8, -10.0}, {0.012, -0.8, 30.0}});
  const auto paper = paper_law();
  EXPECT_DOUBLE_EQ(law.alpha(), 20.0);
  for (int k = 0; k <= 5000; ++k) {
    const double r = -0.01 + 0.05 * k / 5000.0;
    EXPECT_NEAR(law.value(r), paper->value(r), 1e-17) << r;
    EXPECT_NEAR(law.value(LawPart::j1, r) - law.value(LawPart::j2, r), paper->value(r), 1e-17) << r;
    // the computed j2: 0 up to 0.01, 10 (r - 0.01)^2 on (0.01, 0.02], 0.001 + 0.2 (r - 0.02) beyond;
    // below the paper's j2 = 10 r^2 (4.8) everywhere
    const double j2 = r <= 0.01 ? 0.0 : (r <= 0.02 ? 10.0 * (r - 0.01) * (r - 0.01) : 0.001 + 0.2 * (r - 0.02));
    EXPECT_NEAR(law.value(LawPart::j2, r), j2, 1e-17) << r;
    EXPECT_LE(law.value(LawPart::j2, r), paper->value(LawPart::j2, r) + 1e-17) << r;
  }
  expect_convex_split(law, -0.02, 0.05);
}

TEST(SplitFromJ, ConcaveKinksBecomeRampsOfJ2) {
  const auto saw = std::dynamic_pointer_cast<const PiecewisePolynomialLaw>(sawtooth_law());
  ASSERT_TRUE(saw);
  const auto law = PiecewisePolynomialLaw::from_j("saw-j", saw->breakpoints(), saw->pieces(LawPart::j));
  EXPECT_TRUE(std::isinf(law.alpha()));
  EXPECT_EQ(law.kinks(), saw->kinks());
  for (int k = 0; k <= 4000; ++k) {
    const double r = -0.01 + 0.04 * k / 4000.0;
    EXPECT_NEAR(law.value(r), saw->value(r), 1e-16) << r;
    // the shipped split puts the drop (k r1 - residual) (r - r1)^+ into j2: so does from_j
    EXPECT_NEAR(law.value(LawPart::j2, r), saw->value(LawPart::j2, r), 1e-16) << r;
  }
  expect_convex_split(law, -0.01, 0.03);
}

TEST(SplitFromJ, CubicPiecesAndTheDelaminationLaw) {
  // j'' = 2 r - 2 on (-1, 1]: the largest negative curvature is 4, at r = -1
  const auto law = PiecewisePolynomialLaw::from_j(
      "cubic", {-1.0, 1.0}, {about(-4.0 / 3.0, 3.0, 1.0, -1.0), {0.0, 0.0, -1.0, 1.0 / 3.0}, about(-2.0 / 3.0, -1.0, 1.0, 1.0)});
  EXPECT_NEAR(law.alpha(), 4.0, 1e-12);
  for (int k = 0; k <= 400; ++k) {
    const double r = -3.0 + 6.0 * k / 400.0;
    const double j = r <= -1.0 ? -4.0 / 3.0 + 3.0 * (r + 1) + (r + 1) * (r + 1)
                               : (r <= 1.0 ? r * r * r / 3.0 - r * r : -2.0 / 3.0 - (r - 1) + (r - 1) * (r - 1));
    EXPECT_NEAR(law.value(r), j, 1e-13) << r;
  }
  expect_convex_split(law, -3.0, 3.0);

  // scenes/delamination.toml's adhesive (SI units): three concave kinks
  const auto delamination = PiecewisePolynomialLaw::from_j(
      "delamination", {-2e-3, -1e-3, -5e-4, 0.0}, {{4e4}, {1e4, -5e6, 5e9}, {0.0, -1e7, 1e10}, {0.0, 0.0, 3e10}, {0.0}});
  EXPECT_TRUE(std::isinf(delamination.alpha()));
  EXPECT_EQ(delamination.kinks(), (std::vector<double>{-2e-3, -1e-3, -5e-4}));
  for (double s : {1e-4, 5e-4, 7e-4, 1e-3, 1.5e-3, 2e-3, 3e-3}) {
    const double J = s < 5e-4 ? 3e10 * s * s : (s < 1e-3 ? 1e10 * s * s + 1e7 * s : (s < 2e-3 ? 5e9 * s * s + 5e6 * s + 1e4 : 4e4));
    EXPECT_NEAR(delamination.value(-s), J, 1e-9 * J) << s;
  }
  EXPECT_EQ(delamination.value(1e-3), 0.0);
  expect_convex_split(delamination, -4e-3, 1e-3);
}

TEST(SplitFromJ, RefusesWhatHasNoSplit) {
  auto message = [](const std::function<void()>& f) { return test::input_error_of(f); };
  EXPECT_NE(message([] { (void)PiecewisePolynomialLaw::from_j("c", {}, {{0.0, 0.0, 0.0, 1.0}}); })
                .find("curvature is unbounded below on piece 0"),
            std::string::npos);
  EXPECT_NE(message([] { (void)PiecewisePolynomialLaw::from_j("d", {0.0}, {{0.0}, {1.0, 1.0}}); })
                .find("j is not continuous at breakpoint 0 (r = 0): 0 on the left, 1 on the right"),
            std::string::npos);
  EXPECT_NE(message([] { (void)PiecewisePolynomialLaw::from_j("e", {0.0}, {{0.0}}); }).find("need 2 pieces for j; got 1"),
            std::string::npos);
  // a convex j: j2 = 0
  const auto convex = PiecewisePolynomialLaw::from_j("k", {0.0}, {{0.0}, {0.0, 0.3, 50.0}});
  EXPECT_EQ(convex.alpha(), 0.0);
  for (double r : {-1.0, 0.0, 0.5, 2.0}) EXPECT_EQ(convex.value(LawPart::j2, r), 0.0);
}

TEST(SplitFromJ, TheDcEngineReachesTheSameSolutionWithEitherSplit) {
  const auto mine = std::make_shared<PiecewisePolynomialLaw>(PiecewisePolynomialLaw::from_j(
      "paper-j", {0.0, 0.01, 0.02}, {{0.0}, {0.0, 0.0, 30.0}, {-0.004, 0.8, -10.0}, {0.012, -0.8, 30.0}}));
  auto with_paper = test::example("squares", 16);
  auto with_mine = test::example("squares", 16, [&](ContactProblem& p) { p.parts[0].law = mine; });
  ASSERT_GT(with_mine->condensation->reduced().uniqueness_margin, 0.0);
  const auto dca = make_minimizer("bundle-dca");
  const MinimizerResult a = dca->minimize(with_paper->condensation->reduced(), {}, {});
  const MinimizerResult b = dca->minimize(with_mine->condensation->reduced(), {}, {});
  ASSERT_TRUE(a.converged()) << a.message;
  ASSERT_TRUE(b.converged()) << b.message;
  EXPECT_LE((a.a - b.a).lpNorm<Eigen::Infinity>(), 1e-9 * a.a.lpNorm<Eigen::Infinity>());
  EXPECT_NEAR(a.objective, b.objective, 1e-12 * std::abs(a.objective));
}

// ---- the global search ------------------------------------------------------------------

/// The lowest F over every face of a box problem whose law has pieces of degree <= 2: each
/// coordinate either at a breakpoint or a bound, or free inside one piece (where F is smooth in
/// it and its derivative vanishes). Every feasible face point is a point of C, and the global
/// minimizer is the point of its own face, so the lowest is the global minimum.
struct Enumerated {
  double F = std::numeric_limits<double>::infinity();
  Eigen::VectorXd a;
  long faces = 0;
};

Enumerated enumerate_faces(const ReducedProblem& p) {
  const auto* law = dynamic_cast<const PiecewisePolynomialLaw*>(&p.law_by_number(0));
  EXPECT_TRUE(law && !p.coordinatewise());
  const std::vector<double> b = law->breakpoints();
  const std::vector<Polynomial> pieces = law->pieces(LawPart::j);
  for (const auto& q : pieces) EXPECT_LE(q.size(), 3u);
  const Eigen::Index n = p.size();
  constexpr double inf = std::numeric_limits<double>::infinity();
  // per coordinate: fixed values (breakpoints and bounds inside [lo, hi]) and pieces (-1 - q)
  std::vector<std::vector<double>> fixed(static_cast<std::size_t>(n));
  std::vector<std::vector<int>> free_pieces(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lo = p.lower(i), hi = p.upper(i);
    for (double x : b)
      if (x >= lo && x <= hi) fixed[i].push_back(x);
    for (double x : {lo, hi})
      if (std::isfinite(x) && std::find(fixed[i].begin(), fixed[i].end(), x) == fixed[i].end()) fixed[i].push_back(x);
    for (int q = 0; q <= static_cast<int>(b.size()); ++q) {
      const double left = q == 0 ? -inf : b[q - 1], right = q == static_cast<int>(b.size()) ? inf : b[q];
      if (std::max(left, lo) < std::min(right, hi)) free_pieces[i].push_back(q);
    }
  }
  auto coef = [&](int q, std::size_t k) { return k < pieces[q].size() ? pieces[q][k] : 0.0; };
  Enumerated best;
  std::vector<std::size_t> choice(static_cast<std::size_t>(n), 0);
  while (true) {
    ++best.faces;
    Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
    std::vector<int> piece(static_cast<std::size_t>(n), -1);
    std::vector<Eigen::Index> F;
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::size_t c = choice[i];
      if (c < fixed[i].size()) {
        a(i) = fixed[i][c];
      } else {
        piece[i] = free_pieces[i][c - fixed[i].size()];
        F.push_back(i);
      }
    }
    bool ok = true;
    if (!F.empty()) {
      const auto m = static_cast<Eigen::Index>(F.size());
      Eigen::MatrixXd M(m, m);
      Eigen::VectorXd rhs(m);
      for (Eigen::Index r = 0; r < m; ++r) {
        const Eigen::Index i = F[r];
        rhs(r) = p.c(i) - p.w(i) * coef(piece[i], 1);
        for (Eigen::Index k = 0; k < n; ++k)
          if (piece[k] < 0) rhs(r) -= p.S(i, k) * a(k);
        for (Eigen::Index s = 0; s < m; ++s) M(r, s) = p.S(i, F[s]);
        M(r, r) += 2.0 * p.w(i) * coef(piece[i], 2);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(M);
      if (!lu.isInvertible()) ok = false;
      if (ok) {
        const Eigen::VectorXd x = lu.solve(rhs);
        for (Eigen::Index r = 0; r < m && ok; ++r) {
          const Eigen::Index i = F[r];
          const int q = piece[i];
          const double left = std::max(q == 0 ? -inf : b[q - 1], p.lower(i));
          const double right = std::min(q == static_cast<int>(b.size()) ? inf : b[q], p.upper(i));
          ok = x(r) >= left && x(r) <= right;
          a(i) = x(r);
        }
      }
    }
    if (ok) {
      const double f = p.energy(a);
      if (f < best.F) best.F = f, best.a = a;
    }
    Eigen::Index i = 0;
    for (; i < n; ++i) {
      if (++choice[i] < fixed[i].size() + free_pieces[i].size()) break;
      choice[i] = 0;
    }
    if (i == n) break;
  }
  return best;
}

/// A box problem of n coupled coordinates with a double-well law j = k/2 (|r| - d)^2 (a concave
/// kink at 0): 2^n local minima, one per choice of well.
ReducedProblem double_well_problem(int n) {
  const double k = 40.0, d = 0.01;
  auto law = std::make_shared<PiecewisePolynomialLaw>(
      PiecewisePolynomialLaw::from_j("double-well", {0.0}, {about(0.0, 0.0, 0.5 * k, -d), about(0.0, 0.0, 0.5 * k, d)}));
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    S(i, i) = 30.0 + 4.0 * i;
    if (i + 1 < n) S(i, i + 1) = S(i + 1, i) = -12.0;
  }
  Eigen::VectorXd c(n);
  for (int i = 0; i < n; ++i) c(i) = 0.05 * std::sin(1.7 * i + 0.4);
  ReducedProblem p = ReducedProblem::uniform(S, c, Eigen::VectorXd::Constant(n, 1.0), std::move(law),
                                             ConstraintKind::box, Eigen::VectorXd::Constant(n, 0.015));
  p.uniqueness_margin = -std::numeric_limits<double>::infinity();  // alpha_j = +inf: a concave kink
  return p;
}

MinimizerOptions tight() {
  MinimizerOptions o;
  o.tolerance = 1e-10;
  return o;
}

TEST(GlobalSearch, FindsTheEnumeratedGlobalMinimumOfADoubleWellProblem) {
  const ReducedProblem p = double_well_problem(5);
  const Enumerated e = enumerate_faces(p);
  ASSERT_TRUE(std::isfinite(e.F));
  EXPECT_EQ(e.faces, 5L * 5 * 5 * 5 * 5);  // kink, two bounds, two pieces per coordinate

  const auto search = make_global_search("ssn");
  const MinimizerResult r = search->minimize(p, {}, tight());
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_NEAR(r.objective, e.F, 1e-10 * std::abs(e.F));
  EXPECT_LE((r.a - e.a).lpNorm<Eigen::Infinity>(), 1e-8);
  // every critical point reported is certified by an independent call, distinct and sorted
  ASSERT_GE(r.critical_points.size(), 2u);
  EXPECT_EQ(r.critical_points.front().objective, r.objective);
  for (std::size_t k = 0; k < r.critical_points.size(); ++k) {
    const CriticalPoint& c = r.critical_points[k];
    EXPECT_TRUE(certificate(p, c.a, 1e-10).converged()) << k;
    EXPECT_GE(c.starts, 1);
    EXPECT_FALSE(c.engines.empty());
    EXPECT_GE(c.objective, e.F - 1e-12 * std::abs(e.F));
    if (k > 0) {
      EXPECT_GE(c.objective, r.critical_points[k - 1].objective);
      EXPECT_GT((c.a - r.critical_points[k - 1].a).lpNorm<Eigen::Infinity>(), 1e-6 * c.certificate.length_scale);
    }
  }
  EXPECT_TRUE(r.may_be_nonunique);
  EXPECT_NE(r.message.find("global search:"), std::string::npos);
}

TEST(GlobalSearch, ALocalEngineFromABadStartLandsHigherTheSearchDoesNot) {
  const ReducedProblem p = double_well_problem(5);
  const Enumerated e = enumerate_faces(p);
  // the bad start: every coordinate in the other well than at the global minimum
  Eigen::VectorXd bad(p.size());
  for (Eigen::Index i = 0; i < p.size(); ++i) bad(i) = e.a(i) > 0.0 ? -0.01 : 0.01;
  int certified = 0;
  for (const auto& name : available_minimizers()) {
    const MinimizerResult local = make_minimizer(name)->minimize(p, bad, tight());
    if (!local.converged()) continue;  // no claim to compare
    ++certified;
    EXPECT_GT(local.objective, e.F + 1e-6 * std::abs(e.F)) << name << " from the bad start";
  }
  EXPECT_GE(certified, 1);
  const MinimizerResult ssn = make_minimizer("ssn")->minimize(p, bad, tight());
  EXPECT_TRUE(ssn.converged()) << ssn.message;
  // the search given the same start
  const MinimizerResult r = make_global_search("ssn")->minimize(p, bad, tight());
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_NEAR(r.objective, e.F, 1e-10 * std::abs(e.F));
}

TEST(GlobalSearch, Example41WithTheSawtoothLawAgainstEnumeration) {
  // N = 6: 5 contact nodes; every face of the box problem enumerated (9^5)
  auto ex = test::example("squares", 6, [](ContactProblem& p) { p.parts[0].law = sawtooth_law(); });
  const ReducedProblem& p = ex->condensation->reduced();
  ASSERT_EQ(p.size(), 5);
  ASSERT_LT(p.uniqueness_margin, 0.0);
  const Enumerated e = enumerate_faces(p);
  const MinimizerResult r = make_global_search("ssn")->minimize(p, {}, tight());
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_NEAR(r.objective, e.F, 1e-10 * std::abs(e.F));
  EXPECT_NEAR(r.objective, -0.0186541, 5e-7);
  for (const auto& name : available_minimizers()) {
    const MinimizerResult local = make_minimizer(name)->minimize(p, {}, tight());
    if (local.converged()) EXPECT_GE(local.objective, r.objective - 1e-12 * std::abs(r.objective)) << name;
  }
}

TEST(GlobalSearch, AUniqueProblemIsSolvedOnce) {
  auto ex = test::example("squares", 16);
  const ReducedProblem& p = ex->condensation->reduced();
  ASSERT_GT(p.uniqueness_margin, 0.0);
  const MinimizerResult r = make_global_search("ssn")->minimize(p, {}, tight());
  ASSERT_TRUE(r.converged());
  EXPECT_EQ(r.history.size(), 1u);
  ASSERT_EQ(r.critical_points.size(), 1u);
  EXPECT_EQ(r.critical_points[0].engines, std::vector<std::string>{"ssn"});
  EXPECT_NE(r.message.find("uniqueness margin is positive"), std::string::npos);
  EXPECT_FALSE(r.may_be_nonunique);
  const MinimizerResult local = make_minimizer("ssn")->minimize(p, {}, tight());
  EXPECT_EQ(r.a, local.a);
}

TEST(GlobalSearch, BudgetStartsAndOptions) {
  const ReducedProblem p = double_well_problem(4);
  GlobalSearchOptions o;
  o.max_starts = 3;
  int reports = 0;
  o.progress = [&](const GlobalSearchProgress& g) {
    ++reports;
    EXPECT_EQ(g.run, reports);
    EXPECT_EQ(g.max_runs, 3);
  };
  const MinimizerResult r = make_global_search("ssn", {}, o)->minimize(p, {}, tight());
  EXPECT_EQ(reports, 3);
  EXPECT_EQ(r.history.size(), 3u);
  EXPECT_NE(r.message.find("budget spent"), std::string::npos);

  const auto search = make_global_search("bundle-dca");
  EXPECT_EQ(search->engine_names().front(), "bundle-dca");
  EXPECT_EQ(search->engine_names().size(), available_minimizers().size());
  const auto starts = search->starts(p, {});
  std::vector<std::string> names;
  for (const auto& s : starts) names.push_back(s.name);
  for (const char* expected : {"given", "quadratic minimizer", "lower bounds", "upper bounds", "random 1", "random 8"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  for (const auto& s : starts) EXPECT_EQ(s.a, p.project(s.a)) << s.name;
  // deterministic for a seed, different for another
  const auto again = make_global_search("bundle-dca")->starts(p, {});
  ASSERT_EQ(again.size(), starts.size());
  for (std::size_t k = 0; k < starts.size(); ++k) EXPECT_EQ(again[k].a, starts[k].a);
  GlobalSearchOptions other;
  other.seed = 2;
  EXPECT_NE(make_global_search("bundle-dca", {}, other)->starts(p, {}).back().a, starts.back().a);

  GlobalSearchOptions bad;
  bad.max_starts = 0;
  EXPECT_NE(test::input_error_of([&] { (void)make_global_search("ssn", {}, bad); }).find("max_starts: must be >= 1"),
            std::string::npos);
  EXPECT_NE(test::input_error_of([] { (void)make_global_search("newton"); }).find("unknown minimizer 'newton'"),
            std::string::npos);
}

}  // namespace
}  // namespace hemivem
