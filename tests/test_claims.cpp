// Claims the numbers support: a uniqueness margin within round-off is zero, a margin always
// belongs to the problem and law it is used with, and a tolerance is one at which "converged"
// means something. The command's side of the same claims: test_cli_claims.cpp.
#include <Eigen/Eigenvalues>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <hemivem/certificate.hpp>
#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/error.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/scene/scene.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace hemivem;

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// k [[1, -1], [-1, 1 + d]]: positive semidefinite up to d, whose exact smallest eigenvalue is
// k d / (2 + d) + O(d^2), far below the round-off of an eigensolver for d = 1e-15.
Eigen::MatrixXd nearly_singular(double k, double d) {
  Eigen::MatrixXd S(2, 2);
  S << k, -k, -k, k * (1.0 + d);
  return S;
}

ReducedProblem problem_with_law(Eigen::MatrixXd S, const std::string& law) {
  const Eigen::Index n = S.rows();
  ReducedProblem p = ReducedProblem::uniform(std::move(S), Eigen::VectorXd::Constant(n, 0.1),
                                             Eigen::VectorXd::Ones(n), make_contact_law(law), ConstraintKind::box,
                                             Eigen::VectorXd::Constant(n, 0.05));
  p.uniqueness_margin = uniqueness_margin(p.S, p.w, p.alphas());
  return p;
}

void replace_margin_line(const fs::path& folder, const std::string& line) {
  std::ifstream in(folder / "problem.txt");
  std::string text, l;
  while (std::getline(in, l))
    if (l.rfind("uniqueness_margin", 0) != 0) text += l + "\n";
  in.close();
  std::ofstream(folder / "problem.txt") << text << line << "\n";
}

}  // namespace

// ---- 1. a margin within round-off is zero, and "unique" is never claimed from it ---------

TEST(Claims, MarginWithinRoundoffIsReportedAsZero) {
  for (double k : {1.0, 65.0, 1e6}) {
    const Eigen::MatrixXd S = nearly_singular(k, 1e-15);
    const Eigen::VectorXd w = Eigen::VectorXd::Ones(2);
    // the eigensolver's own answer is within a few eps * ||S|| of zero, of either sign
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S, Eigen::EigenvaluesOnly);
    ASSERT_LE(std::abs(eig.eigenvalues()(0)), 8 * std::numeric_limits<double>::epsilon() * 2 * k);
    EXPECT_EQ(uniqueness_margin(S, w, 0.0), 0.0) << k;
    // a margin well above round-off stays as computed: exact eigenvalues k (1 -+ 1/2) here
    Eigen::MatrixXd T(2, 2);
    T << k, 0.5 * k, 0.5 * k, k;
    EXPECT_NEAR(uniqueness_margin(T, w, 0.0), 0.5 * k, 1e-14 * k);
    // and so does a clearly negative one: S - 2k W has exact smallest eigenvalue -2k + O(k d)
    EXPECT_NEAR(uniqueness_margin(S, w, 2.0 * k), -2.0 * k, 1e-12 * k);
  }
}

TEST(Claims, MinimizerDoesNotClaimUniquenessFromAZeroMargin) {
  ReducedProblem p = problem_with_law(nearly_singular(65.0, 1e-15), "linear");
  ASSERT_EQ(p.uniqueness_margin, 0.0);
  const MinimizerResult r = make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), MinimizerOptions{});
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_TRUE(r.may_be_nonunique);
}

TEST(Claims, VerdictsOfAMargin) {
  EXPECT_EQ(uniqueness_verdict(0.5), "unique");
  EXPECT_EQ(uniqueness_verdict(0.0), "zero");
  EXPECT_EQ(uniqueness_verdict(-1.0), "negative");
  EXPECT_EQ(uniqueness_verdict(-inf), "negative");
  EXPECT_EQ(uniqueness_verdict(std::numeric_limits<double>::quiet_NaN()), "unknown");
  EXPECT_NE(uniqueness_meaning(0.0).find("not strongly convex"), std::string::npos);
  EXPECT_EQ(uniqueness_meaning(0.0).find("is unique"), std::string::npos);
  EXPECT_NE(uniqueness_meaning(1.0).find("is unique"), std::string::npos);
}

// ---- 2. a change of law recomputes the margin ---------------------------------------------

TEST(Claims, ReadingWithAnotherLawRecomputesTheMargin) {
  Eigen::MatrixXd S(2, 2);
  S << 100.0, -10.0, -10.0, 100.0;
  const ReducedProblem p = problem_with_law(S, "paper");
  ASSERT_GT(p.uniqueness_margin, 0.0);
  const fs::path dir = test::scratch("claims-stale");
  write_reduced_problem(dir, p);
  EXPECT_EQ(read_reduced_problem(dir).uniqueness_margin, p.uniqueness_margin);
  // the saw-tooth law has concave kinks: no margin proves uniqueness
  const ReducedProblem q = read_reduced_problem(dir, make_contact_law("sawtooth"));
  EXPECT_EQ(q.uniqueness_margin, -inf);
  const MinimizerResult r = make_minimizer("ssn")->minimize(q, Eigen::VectorXd(), MinimizerOptions{});
  EXPECT_TRUE(r.may_be_nonunique);
}

// ---- 3. a margin given with a problem is checked, never trusted ---------------------------

TEST(Claims, AStoredMarginThatIsNotTheProblemsIsRefused) {
  const ReducedProblem p = problem_with_law(-Eigen::MatrixXd::Identity(2, 2), "linear");
  ASSERT_EQ(p.uniqueness_margin, -1.0);  // the exact eigenvalue of -I
  const fs::path dir = test::scratch("claims-trusted");
  write_reduced_problem(dir, p);
  replace_margin_line(dir, "uniqueness_margin 1");
  const std::string message = test::input_error_of([&] { (void)read_reduced_problem(dir); });
  EXPECT_NE(message.find("problem.txt:"), std::string::npos) << message;
  EXPECT_NE(message.find("uniqueness_margin 1 is not the margin of this problem"), std::string::npos) << message;
  EXPECT_NE(message.find("= -1"), std::string::npos) << message;
  // without the line the margin is computed
  replace_margin_line(dir, "");
  EXPECT_EQ(read_reduced_problem(dir).uniqueness_margin, -1.0);
  // the margin it wrote itself reads back
  replace_margin_line(dir, "uniqueness_margin -1");
  EXPECT_EQ(read_reduced_problem(dir).uniqueness_margin, -1.0);
}

// ---- 4. tolerances are checked in one place ------------------------------------------------

TEST(Claims, ToleranceOutsideItsRangeIsRefusedEverywhere) {
  const ReducedProblem p = problem_with_law(2.0 * Eigen::MatrixXd::Identity(2, 2), "linear");
  const Eigen::VectorXd a = Eigen::VectorXd::Zero(2);
  for (double tol : {1e300, 0.999, 0.5, 0.011, 0.0, -1e-10, std::numeric_limits<double>::quiet_NaN(), 1e-320}) {
    const std::string cert = test::input_error_of([&] { (void)certificate(p, a, tol); });
    EXPECT_NE(cert.find("tolerance: must be in [1e-300, 0.01], got"), std::string::npos) << tol << ": " << cert;
    MinimizerOptions o;
    o.tolerance = tol;
    std::string why;
    EXPECT_FALSE(o.is_valid(&why)) << tol;
    EXPECT_NE(why.find("tolerance: must be in [1e-300, 0.01]"), std::string::npos) << why;
    EXPECT_THROW((void)make_minimizer("ssn")->minimize(p, Eigen::VectorXd(), o), InputError) << tol;
  }
  for (double tol : {1e-300, 1e-14, 1e-10, 1e-2}) {
    EXPECT_NO_THROW((void)certificate(p, a, tol)) << tol;
    MinimizerOptions o;
    o.tolerance = tol;
    EXPECT_TRUE(o.is_valid(nullptr)) << tol;
  }
  // a certificate at a coarse tolerance is not "converged" by a residual of order one
  Eigen::VectorXd far(2);
  far << 0.04, -0.04;
  EXPECT_FALSE(certificate(p, far, max_tolerance).converged());
}

TEST(Claims, SceneToleranceKeyIsChecked) {
  Scene s = default_scene();
  const std::string message = test::input_error_of([&] { apply_override(s, "solver.tolerance=0.5"); });
  EXPECT_NE(message.find("solver.tolerance"), std::string::npos) << message;
  EXPECT_NE(message.find("must be in [1e-300, 0.01], got 0.5"), std::string::npos) << message;
  EXPECT_NO_THROW(apply_override(s, "solver.tolerance=1e-3"));
}

