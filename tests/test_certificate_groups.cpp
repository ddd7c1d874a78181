// Groups of coordinates with a law of their Euclidean norm (ReducedProblem::groups: a solid's
// isotropic friction): the checks of the contract, the energy, the concave part's subgradient,
// the certificate against hand computations, the existence test and the file format.
#include <hemivem/certificate.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/error.hpp>
#include <hemivem/existence.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/uniqueness.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <unistd.h>

using namespace hemivem;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One group (coordinates 0 and 1) on a spring of stiffness k in each direction, pulled by c,
// under Tresca's law of bound g with weight w: stuck (a = 0) while |c| <= w g, otherwise
// slipping along c by (|c| - w g) / k.
ReducedProblem spring(double k, Eigen::Vector2d c, double w, double g) {
  ReducedProblem p = ReducedProblem::uniform(k * Eigen::MatrixXd::Identity(2, 2), c, Eigen::Vector2d(w, w),
                                             tresca_law(g), ConstraintKind::none);
  p.groups = {{0, 1}};
  return p;
}

Eigen::Vector2d spring_solution(double k, Eigen::Vector2d c, double w, double g) {
  const double m = c.norm();
  return m <= w * g ? Eigen::Vector2d::Zero() : Eigen::Vector2d(c * ((m - w * g) / (k * m)));
}

// A law falling from 0: j(r) = -r on r > 0 (j'(0+) = -1), a norm cannot take it.
std::shared_ptr<const ContactLaw> falling_law() {
  return std::make_shared<PiecewisePolynomialLaw>("falling", std::vector<double>{0.0},
                                                  std::vector<Polynomial>{{0.0}, {0.0}},
                                                  std::vector<Polynomial>{{0.0}, {0.0, 1.0}});
}

}  // namespace

TEST(CoordinateGroups, TheContractRefusesAGroupThatIsNotOneByName) {
  ReducedProblem p = spring(2.0, {1.0, 1.0}, 1.0, 0.5);
  EXPECT_NO_THROW(check_sizes(p, "here"));
  EXPECT_FALSE(p.uniform_form().has_value()) << "a problem with groups is coordinate-wise";
  auto refused = [](ReducedProblem q, const std::string& words) {
    try {
      check_sizes(q, "here");
      ADD_FAILURE() << "accepted; expected: " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("here"), std::string::npos) << e.what();
    }
  };
  ReducedProblem q = p;
  q.groups = {{0, 0}};
  refused(q, "two distinct coordinates");
  q.groups = {{0, 2}};
  refused(q, "two distinct coordinates");
  q = ReducedProblem::uniform(Eigen::MatrixXd::Identity(3, 3), Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones(),
                              tresca_law(1.0), ConstraintKind::none);
  q.groups = {{0, 1}, {1, 2}};
  refused(q, "is in another group");
  q = p;
  q.hi(1) = 1.0;
  refused(q, "has a bound");
  q = p;
  q.w(1) = 2.0;
  refused(q, "differ in law or weight");
  q = p;
  q.laws = {falling_law()};
  refused(q, "falls from 0");
}

TEST(CoordinateGroups, EnergyAndConcaveSubgradientAreThoseOfTheNorm) {
  // slip-weakening: j(r) = g_s r - (g_s - g_k) r^2 / (2 delta) for r <= delta
  const double gs = 0.4, gk = 0.1, delta = 2.0, w = 1.5;
  ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd::Identity(3, 3), Eigen::Vector3d(1.0, 2.0, 3.0),
                                             Eigen::Vector3d(w, w, w), slip_weakening_law(gs, gk, delta),
                                             ConstraintKind::none);
  p.groups = {{0, 2}};
  const Eigen::Vector3d a(0.6, -0.25, 0.8);  // |(a0, a2)| = 1
  const double r = 1.0;
  const double j = [&](double x) { return gs * std::abs(x) - (gs - gk) * x * x / (2.0 * delta); }(r);
  const double jb = gs * 0.25 - (gs - gk) * 0.0625 / (2.0 * delta);
  EXPECT_NEAR(p.energy(a), 0.5 * a.squaredNorm() - Eigen::Vector3d(1.0, 2.0, 3.0).dot(a) + w * j + w * jb, 1e-15);
  // j2(r) = (g_s - g_k) r^2 / (2 delta) on r <= delta: its gradient at v is w (g_s - g_k) v / delta
  const Eigen::VectorXd g2 = p.subgradient_convex2(a);
  EXPECT_NEAR(g2(0), w * (gs - gk) / delta * 0.6, 1e-15);
  EXPECT_NEAR(g2(2), w * (gs - gk) / delta * 0.8, 1e-15);
  EXPECT_NEAR(g2(1), -w * (gs - gk) / delta * 0.25, 1e-15);
  EXPECT_EQ(p.subgradient_convex2(Eigen::Vector3d(0.0, 0.0, 0.0))(0), 0.0);
  // a group's alpha is its law's: j'(r) >= j'(0+) - alpha r, so j'(r)/r >= -alpha
  EXPECT_DOUBLE_EQ(p.alphas()(0), (gs - gk) / delta);
  EXPECT_EQ(p.group_of(), Eigen::Vector3i(0, -1, 0));
}

TEST(CoordinateGroups, TheCertificateOfASpringIsItsClosedForm) {
  const double k = 4.0, w = 0.5, g = 2.0;
  for (const Eigen::Vector2d c : {Eigen::Vector2d(0.6, 0.8), Eigen::Vector2d(3.0, -4.0), Eigen::Vector2d(-0.3, 0.0)}) {
    SCOPED_TRACE(testing::Message() << "c = " << c.transpose());
    const ReducedProblem p = spring(k, c, w, g);
    const Eigen::Vector2d a = spring_solution(k, c, w, g);
    const CertifiedPoint cp = certify(p, a, 1e-12);
    EXPECT_TRUE(cp.certificate.converged()) << cp.certificate.primal << " " << cp.certificate.dual;
    // the law force balances the spring: zeta = c - k a, of length w g when slipping
    EXPECT_NEAR((cp.law_force - (c - k * a)).norm(), 0.0, 1e-14);
    if (c.norm() > w * g) EXPECT_NEAR(cp.law_force.norm(), w * g, 1e-14);
    EXPECT_EQ(cp.reaction, Eigen::Vector2d::Zero());
  }
}

TEST(CoordinateGroups, TheDualResidualIsTheDistanceToTheNormsSubdifferentialByHand) {
  const double k = 1.0, w = 1.0, g = 1.0;
  const Eigen::Vector2d c(3.0, 0.0);  // solution (2, 0)
  const ReducedProblem p = spring(k, c, w, g);
  // at (2, 1): S a - c = (-1, 1); the law force lies on the ray of (2, 1) with length 1
  // (Tresca: j' = 1 off the origin), so the residual is (-1, 1) + (2, 1)/sqrt(5)
  const Eigen::Vector2d a(2.0, 1.0), e = a.normalized();
  const CertifiedPoint cp = certify(p, a, 1e-10);
  const double f = std::max({c.cwiseAbs().maxCoeff(), a.cwiseAbs().maxCoeff(), e.cwiseAbs().maxCoeff()});
  EXPECT_NEAR(cp.certificate.dual, (Eigen::Vector2d(-1.0, 1.0) + e).norm() / f, 1e-15);
  EXPECT_EQ(cp.certificate.primal, 0.0);
  // at the origin with |c| = 3 > w g = 1 the disc gives a law force of length 1: residual 2
  const CertifiedPoint at0 = certify(p, Eigen::Vector2d::Zero(), 1e-10);
  EXPECT_NEAR(at0.certificate.dual, 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(at0.law_force(0), 1.0, 1e-15);
  // with c = (3.5, 1.5) Tresca's law per coordinate slips each by |c_i| - 1: (2.5, 0.5), which
  // the law of the norm does not certify
  ReducedProblem wise = spring(k, Eigen::Vector2d(3.5, 1.5), w, g);
  const Eigen::Vector2d box_point(2.5, 0.5);
  EXPECT_GT(certify(wise, box_point, 1e-10).certificate.dual, 1e-3);
  wise.groups.clear();
  EXPECT_TRUE(certify(wise, box_point, 1e-10).certificate.converged());
}

TEST(CoordinateGroups, ANormWithinTheWindowOfTheOriginIsSnappedOntoIt) {
  const ReducedProblem p = spring(1.0, {0.3, 0.4}, 1.0, 1.0);  // stuck: |c| = 0.5 < 1
  const CertifiedPoint cp = certify(p, Eigen::Vector2d(1e-13, -1e-13), 1e-10);
  EXPECT_EQ(cp.a, Eigen::Vector2d::Zero());
  EXPECT_TRUE(cp.certificate.converged());
  EXPECT_NEAR(cp.law_force(0), 0.3, 1e-15);
  EXPECT_NEAR(cp.law_force(1), 0.4, 1e-15);
  // outside the window it is not, and the point is not a critical one
  EXPECT_FALSE(certify(p, Eigen::Vector2d(1e-6, 0.0), 1e-10).certificate.converged());
}

TEST(CoordinateGroups, ExistenceWeighsTheLoadAgainstTheNormsRate) {
  // S = 0: the group moves freely; Tresca's rate g |d| against the load c . d, |c| = 5
  for (const double g : {6.0, 4.0}) {
    ReducedProblem p = spring(1.0, {3.0, 4.0}, 1.0, g);
    p.S.setZero();
    const Existence e = check_existence(p);
    EXPECT_EQ(e.bounded, g > 5.0) << "g = " << g;
    EXPECT_EQ(e.coercive, g > 5.0) << "g = " << g;
  }
}

TEST(CoordinateGroups, TheFileFormatKeepsTheGroupsAndNamesABadLine) {
  const auto dir = std::filesystem::temp_directory_path() / ("hemivem-groups-io-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  ReducedProblem p = ReducedProblem::uniform(Eigen::MatrixXd::Identity(3, 3) * 2.0, Eigen::Vector3d(1.0, 2.0, 3.0),
                                             Eigen::Vector3d::Ones(), tresca_law(0.5), ConstraintKind::none);
  p.groups = {{1, 2}};
  p.uniqueness_margin = measure_uniqueness(p).margin;
  write_reduced_problem(dir, p);
  EXPECT_TRUE(std::filesystem::exists(dir / "groups.txt"));
  const ReducedProblem q = read_reduced_problem(dir);
  ASSERT_EQ(q.groups.size(), 1u);
  EXPECT_EQ(q.groups[0].first, 1);
  EXPECT_EQ(q.groups[0].second, 2);
  EXPECT_EQ(q.energy(Eigen::Vector3d(0.1, 0.3, 0.4)), p.energy(Eigen::Vector3d(0.1, 0.3, 0.4)));
  {
    std::ofstream(dir / "groups.txt") << "# first second\n1 1\n";
  }
  try {
    read_reduced_problem(dir);
    ADD_FAILURE() << "a group of one coordinate twice was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("groups.txt:2"), std::string::npos) << e.what();
  }
  // without groups a problem is written as before, and no groups.txt stays behind
  p.groups.clear();
  write_reduced_problem(dir, p);
  EXPECT_FALSE(std::filesystem::exists(dir / "groups.txt"));
  EXPECT_TRUE(read_reduced_problem(dir).groups.empty());
  std::filesystem::remove_all(dir);
}
