// Loading paths against theory and against each other (docs/paths.md, docs/nonconvex.md):
// Cattaneo and Mindlin's stick zone under a growing shear, every minimizer along a Tresca and a
// Coulomb path within the distance their certificates allow, and the delamination benchmark
// loaded from zero.
#include <hemivem/app/path.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/path/path.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "delamination_path.hpp"
#include "test_support.hpp"

namespace hemivem {
namespace {

// --- Cattaneo-Mindlin -------------------------------------------------------------------------

// scenes/cattaneo-mindlin.toml: a rigid cylinder (R = 1) pressed into the block [-2, 2] x [-2, 0]
// by pushing the block's bottom up (t <= 1), then the bottom moved sideways while the cylinder
// stays (t > 1), Coulomb friction mu = 0.3, E = 65, nu = 0.49 (plane strain). For the normal
// force P and the tangential force Q of each step, Cattaneo and Mindlin's stick zone is
// |x| < c = a sqrt(1 - Q / (mu P)) with Hertz's a = sqrt(4 P R / (pi E*)), E* = E / (1 - nu^2).
//
// The stick zone measured is the span of the nodes in contact whose slip in the step is zero,
// widened by half a node spacing h at each end (its edge lies between the last node that sticks
// and the first that slips): c_h = (x_max - x_min + h) / 2. Locating each edge between two nodes
// puts c_h within h/2 of the stick zone of the discrete solution; what the model leaves (a finite
// block, nu not quite 1/2) is about 0.6 % of a, 0.3 h, on a mesh twice as fine (docs/paths.md).
// The test allows one node spacing, h = 1/512. Measured: within 0.32 h at every step with
// 0 < Q < mu P.
TEST(PathValidation, CattaneoMindlinStickZone) {
  const Scene scene = parse_scene(test::scenes_dir() / "cattaneo-mindlin.toml");
  const app::SceneSolve solved = app::solve_scene_path(scene);
  ASSERT_TRUE(solved.path);
  const PathSolution& path = *solved.path;
  const double E = 65.0, nu = 0.49, mu = 0.3, R = 1.0, Estar = E / (1.0 - nu * nu);
  const double h = 1.0 / 512.0;
  int sheared = 0, sliding = 0;
  double P1 = 0.0;
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("t = " + std::to_string(s.t));
    ASSERT_TRUE(s.converged()) << s.message;
    const double P = -s.contact_force.y(), Q = std::abs(s.contact_force.x());
    ASSERT_GT(P, 0.0);
    if (s.t == 1.0) P1 = P;
    const double a = std::sqrt(4.0 * P * R / (M_PI * Estar));
    // the nodes in contact, in order along x, and those of them that stick
    std::vector<const ContactNode*> in_contact;
    for (const ContactNode& n : s.contact)
      if (n.force() > 0.0) in_contact.push_back(&n);
    ASSERT_GE(in_contact.size(), 20u);
    std::sort(in_contact.begin(), in_contact.end(),
              [](const ContactNode* p, const ContactNode* q) { return p->x.x() < q->x.x(); });
    std::vector<int> stick;
    for (std::size_t i = 0; i < in_contact.size(); ++i)
      if (in_contact[i]->friction_state == FrictionState::stick) stick.push_back(static_cast<int>(i));
    // the contact zone: Hertz's a within one node spacing
    const double zone = 0.5 * (in_contact.back()->x.x() - in_contact.front()->x.x() + h);
    EXPECT_NEAR(zone, a, h);
    if (s.t <= 1.0) {
      // pressed: no tangential resultant (the problem is symmetric)
      EXPECT_LE(Q, 1e-9 * P);
      continue;
    }
    // sheared: the normal force holds (the bottom's sideways motion hardly changes it)
    EXPECT_NEAR(P, P1, 1e-4 * P1);
    EXPECT_LE(Q, mu * P * (1.0 + 1e-8));
    if (stick.empty()) {
      // sliding: the friction force is mu times the normal force everywhere
      EXPECT_NEAR(Q, mu * P, 1e-8 * mu * P);
      ++sliding;
      continue;
    }
    ++sheared;
    // one stick zone, without a slipping node inside
    EXPECT_EQ(stick.back() - stick.front() + 1, static_cast<int>(stick.size()));
    const double c = 0.5 * (in_contact[static_cast<std::size_t>(stick.back())]->x.x() -
                            in_contact[static_cast<std::size_t>(stick.front())]->x.x() + h);
    const double c_theory = a * std::sqrt(1.0 - Q / (mu * P));
    EXPECT_NEAR(c, c_theory, h) << "Q / (mu P) = " << Q / (mu * P);
  }
  EXPECT_GE(sheared, 12);  // Q / (mu P) from about 0.07 to 0.98
  EXPECT_GE(sliding, 1);
}

// --- Every minimizer along a frictional path ----------------------------------------------------

std::unique_ptr<SparseFactorization> eigen_engine() {
  FactorizationOptions fo;
  fo.engine = "eigen";
  return make_factorization(fo);
}

// Example 4.1, pressed by (0, -8) up to t = 1, then sheared by 3 (t - 1).
ContactProblem pressed_then_sheared(const Mesh& mesh) {
  ContactProblem p = example_4_1(mesh);
  for (auto& t : p.elasticity.tractions)
    t.traction = [](const Vec2&) { return Vec2(0.0, -8.0); };
  return p;
}

PathLoading shear_loading() {
  return PathLoading{{0.5, 1.0, 1.25, 1.5, 1.75, 2.0}, [](double t, ContactProblem& q) {
                       for (auto& tr : q.elasticity.tractions)
                         tr.traction = [t](const Vec2&) {
                           return Vec2(3.0 * std::max(t - 1.0, 0.0), -8.0 * std::min(t, 1.0));
                         };
                     }};
}

// What the certificates of two paths of one problem allow between their steps k. Step k of a
// path minimizes F_k(a) = 1/2 a^T S a - c^T a + sum_i w_i j_nu(a_nu,i) + sum_i w_i g_i |a_tau,i - s_i|
// (s: the u_tau of its step k - 1, g: the friction bounds it used); a certified point has
// S a - c + zeta + xi = r with zeta in the normal law's subdifferential (and the constraint's
// normal cone), xi_i in w_i g_i d|a_tau,i - s_i| and |r|_inf <= dual * force_scale. For two such
// points (d = a - a', e = s - s' on the tangential coordinates, G = ||w (g - g')||_2,
// R = ||r||_2 + ||r'||_2), the monotonicity of the laws past the margin m = lambda_min(S - alpha_j W)
// > 0 and of the friction terms gives
//   m |d|^2 <= (R + G + ||S|| |e|) |d| + (R + G) |e|,
// so |d|_2 <= (B + sqrt(B^2 + 4 m (R + G) |e|)) / (2 m), B = R + G + ||S|| |e|. Without friction
// bounds that change (Tresca) G = 0, and at step 1 e = 0: |d| <= R / m.
struct StepBound {
  double m = 0.0;       // the uniqueness margin of the reduced problem
  double norm_S = 0.0;  // ||S||_2
};

double allowed_distance(const StepBound& b, const PathStep& x, const PathStep& y, const Eigen::VectorXd& e) {
  const double n = static_cast<double>(x.a.size());
  const double R = std::sqrt(n) * (x.certificate.dual * x.certificate.force_scale +
                                   y.certificate.dual * y.certificate.force_scale);
  Eigen::VectorXd wg(static_cast<Eigen::Index>(x.contact.size()));
  for (std::size_t i = 0; i < x.contact.size(); ++i)
    wg(static_cast<Eigen::Index>(i)) =
        x.contact[i].weight * (x.friction_bound(static_cast<Eigen::Index>(i)) - y.friction_bound(static_cast<Eigen::Index>(i)));
  const double G = wg.norm(), E = e.norm();
  const double B = R + G + b.norm_S * E;
  return (B + std::sqrt(B * B + 4.0 * b.m * (R + G) * E)) / (2.0 * b.m);
}

// The tangential part of a (the reduced problem orders u_nu, then u_tau).
Eigen::VectorXd tangential(const Eigen::VectorXd& a) { return a.tail(a.size() / 2); }

void every_minimizer_follows(const ContactProblem& problem, const StepBound& bound, const std::string& what) {
  const auto ssn = make_minimizer("ssn");
  ContactProblem p0 = problem;
  const PathSolution reference = solve_path(p0, eigen_engine(), *ssn, shear_loading());
  ASSERT_EQ(reference.steps.size(), 6u);
  for (const PathStep& s : reference.steps) ASSERT_TRUE(s.converged()) << what << " ssn, t = " << s.t << ": " << s.message;
  for (const std::string& name : available_minimizers()) {
    if (name == "ssn") continue;
    SCOPED_TRACE(what + ", " + name);
    const auto minimizer = make_minimizer(name);
    ContactProblem p = problem;
    const PathSolution path = solve_path(p, eigen_engine(), *minimizer, shear_loading());
    ASSERT_EQ(path.steps.size(), reference.steps.size());
    double worst = 0.0;  // the largest distance against what the certificates allow
    for (std::size_t k = 0; k < path.steps.size(); ++k) {
      const PathStep &x = path.steps[k], &y = reference.steps[k];
      SCOPED_TRACE("t = " + std::to_string(x.t));
      EXPECT_TRUE(x.converged()) << x.message;
      if (!x.converged()) continue;
      const Eigen::VectorXd e = k == 0 ? Eigen::VectorXd::Zero(x.a.size() / 2)
                                       : Eigen::VectorXd(tangential(path.steps[k - 1].a) - tangential(reference.steps[k - 1].a));
      const double distance = (x.a - y.a).norm(), allowed = allowed_distance(bound, x, y, e);
      EXPECT_LE(distance, allowed);
      worst = std::max(worst, distance / allowed);
    }
    std::cout << what << ", " << name << ": largest |a - a_ssn| / allowed = " << worst << "\n";
  }
}

// S and the margin of Example 4.1 with Tresca friction (the same for every bound: Tresca's law is
// convex, so the margin is that of the normal law).
StepBound step_bound(const ContactProblem& problem) {
  ReducedProblem reduced;
  const auto ssn = make_minimizer("ssn");
  const ContactSolution s = solve_contact(problem, eigen_engine(), *ssn, MinimizerOptions{}, &reduced);
  EXPECT_TRUE(s.converged()) << s.message;
  StepBound b;
  b.m = reduced.uniqueness_margin;
  b.norm_S = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(reduced.S, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
  return b;
}

TEST(PathValidation, EveryMinimizerFollowsATrescaPath) {
  const Mesh mesh = make_squares(8);
  ContactProblem problem = pressed_then_sheared(mesh);
  problem.parts[0].friction = tresca_law(0.8);
  const StepBound bound = step_bound(problem);
  ASSERT_GT(bound.m, 0.0) << "the certificates bound the distance only where the margin is positive";
  every_minimizer_follows(problem, bound, "tresca");
}

// Coulomb's law: each step a fixed point of Tresca problems. The bound above holds for the Tresca
// problems the two engines ended with (their bounds g compared by G); that the fixed point has one
// solution is not certified (it needs mu small enough for the fixed point to contract).
TEST(PathValidation, EveryMinimizerFollowsACoulombPath) {
  const Mesh mesh = make_squares(8);
  ContactProblem problem = pressed_then_sheared(mesh);
  problem.parts[0].friction = tresca_law(1.0);
  const StepBound bound = step_bound(problem);
  ASSERT_GT(bound.m, 0.0);
  problem.parts[0].friction_bound = FrictionBound{FrictionBound::Kind::coulomb, 0.3, {}};
  every_minimizer_follows(problem, bound, "coulomb");
}

// --- Delamination loaded from zero --------------------------------------------------------------

// scenes/delamination.toml on 32 x 4 squares with the pulling traction at t = 1 set to `mpa`.
Scene delamination(double mpa) {
  Scene scene = parse_scene(test::scenes_dir() / "delamination.toml");
  apply_override(scene, "mesh.n=[32, 4]");
  apply_override(scene, "loads.traction[0].value=[0.0, " + std::to_string(mpa * 1e6) + "]");
  return scene;
}


// The delamination law along a path loaded from 0 to 30 MPa in steps of 0.1 MPa (ssn from the
// step before): every step converges; no step reaches an energy below the lowest critical point
// the global search finds at its load (20 MPa: on the bonded branch, far above it; 26 MPa: just
// before the bonded branch ends; 30 MPa: debonded, where the path is that point); as the load
// grows the debonded nodes (separation beyond 2 mm) never become fewer, and some debond.
TEST(PathValidation, DelaminationLoadedFromZero) {
  test::expect_delamination_path_above_the_global_search(delamination);
}

// The law has no memory: j depends on the separation only, so a node beyond 2 mm is bonded again
// once it comes back below. Loading to 29.7 MPa and unloading (the traction 27 (1.1 - |t - 1.1|)
// MPa) debonds nodes on the way up and bonds every one of them again on the way down: the
// monotone count above is a property of a growing load, not of the law.
TEST(PathValidation, DelaminationHealsOnUnloading) {
  Scene scene = delamination(27.0);
  apply_override(scene, "loads.traction[0].value=[0.0, \"2.7e7*(1.1 - abs(t - 1.1))\"]");
  apply_override(scene, "solver.search=\"local\"");
  std::string t = "path.t=[";
  for (int k = 1; k <= 210; ++k) t += (k > 1 ? ", " : "") + std::to_string(k / 100.0);
  apply_override(scene, t + "]");
  apply_override(scene, "path.frames=1");
  const app::SceneSolve solved = app::solve_scene_path(scene);
  ASSERT_TRUE(solved.path);
  int most = 0;
  for (const PathStep& s : solved.path->steps) {
    ASSERT_TRUE(s.converged()) << "t = " << s.t << ": " << s.message;
    most = std::max(most, test::debonded(s.contact));
  }
  EXPECT_GT(most, 0);
  EXPECT_EQ(test::debonded(solved.path->steps.back().contact), 0) << "at 2.7 MPa after unloading";
}

}  // namespace
}  // namespace hemivem
