// Manufactured solution u = (sin(pi x) cos(pi y), x^2 sin(pi y)), E = 65, nu = 0.29 (plane
// strain), Dirichlet data on the whole boundary of the unit square, body force -div sigma(u).
// Errors of Pi u_h, integrated over each polygon with a signed fan of triangles.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/vem/quadrature.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "test_support.hpp"

using namespace hemivem;

namespace {

const double kPi = 3.14159265358979323846;
const Material kMaterial{65.0, 0.29};
const Lame kLame = lame(kMaterial, PlaneModel::strain);

Vec2 exact(const Vec2& p) {
  const double x = p.x(), y = p.y();
  return {std::sin(kPi * x) * std::cos(kPi * y), x * x * std::sin(kPi * y)};
}

Eigen::Matrix2d exact_gradient(const Vec2& p) {
  const double x = p.x(), y = p.y();
  Eigen::Matrix2d G;
  G << kPi * std::cos(kPi * x) * std::cos(kPi * y), -kPi * std::sin(kPi * x) * std::sin(kPi * y),  //
      2 * x * std::sin(kPi * y), kPi * x * x * std::cos(kPi * y);
  return G;
}

Eigen::Matrix2d stress(const Eigen::Matrix2d& grad) {
  const Eigen::Matrix2d eps = 0.5 * (grad + grad.transpose());
  return kLame.lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2 * kLame.mu * eps;
}

// f0 = -div sigma(u), written out by hand.
Vec2 body_force(const Vec2& p) {
  const double x = p.x(), y = p.y(), s = kPi;
  const double sx = std::sin(s * x), cx = std::cos(s * x), sy = std::sin(s * y), cy = std::cos(s * y);
  const double dtr_dx = -s * s * sx * cy + 2 * s * x * cy;
  const double dtr_dy = -s * s * cx * sy - s * s * x * x * sy;
  const double de11_dx = -s * s * sx * cy;
  const double de12_dy = 0.5 * (-s * s * sx * cy + 2 * s * x * cy);
  const double de12_dx = 0.5 * (-s * s * cx * sy + 2 * sy);
  const double de22_dy = -s * s * x * x * sy;
  return -Vec2(kLame.lambda * dtr_dx + 2 * kLame.mu * (de11_dx + de12_dy),
               kLame.lambda * dtr_dy + 2 * kLame.mu * (de12_dx + de22_dy));
}

TEST(ManufacturedSolution, BodyForceIsMinusDivergenceOfStress) {
  // central differences of the stress built from the exact gradient
  const double d = 1e-5;
  for (const Vec2 p : {Vec2(0.3, 0.7), Vec2(0.81, 0.12), Vec2(0.5, 0.5)}) {
    const Eigen::Matrix2d sxp = stress(exact_gradient(p + Vec2(d, 0))), sxm = stress(exact_gradient(p - Vec2(d, 0)));
    const Eigen::Matrix2d syp = stress(exact_gradient(p + Vec2(0, d))), sym = stress(exact_gradient(p - Vec2(0, d)));
    const Vec2 div((sxp(0, 0) - sxm(0, 0) + syp(0, 1) - sym(0, 1)) / (2 * d),
                   (sxp(1, 0) - sxm(1, 0) + syp(1, 1) - sym(1, 1)) / (2 * d));
    EXPECT_LE((body_force(p) + div).norm(), 1e-6 * div.norm());
    // and the gradient against differences of u
    const Eigen::Matrix2d G = exact_gradient(p);
    const Vec2 gx = (exact(p + Vec2(d, 0)) - exact(p - Vec2(d, 0))) / (2 * d);
    const Vec2 gy = (exact(p + Vec2(0, d)) - exact(p - Vec2(0, d))) / (2 * d);
    EXPECT_LE((G.col(0) - gx).norm() + (G.col(1) - gy).norm(), 1e-8);
  }
}

struct Errors {
  double h = 0.0;   // sqrt(area / elements)
  double l2 = 0.0;  // || u - Pi u_h ||_0
  double h1 = 0.0;  // | u - Pi u_h |_1 (broken)
  double energy = 0.0;  // (sum_E int sigma(e) : eps(e))^(1/2)
};

Errors solve_and_measure(const Mesh& mesh) {
  ElasticityProblem p;
  p.mesh = &mesh;
  p.materials = MaterialTable(kMaterial);
  p.body_force = body_force;
  p.dirichlet.push_back(test::dirichlet_everywhere(mesh, exact));
  const Eigen::VectorXd u = test::solve(assemble(p));
  const auto proj = project_solution(mesh, u);
  Errors err;
  std::vector<Vec2> poly;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    poly.clear();
    for (int v : mesh.element(e)) poly.push_back(mesh.vertex(v));
    const LinearField& f = proj[static_cast<std::size_t>(e)];
    err.l2 += quadrature::integrate_polygon(poly, [&](const Vec2& x) { return (exact(x) - f(x)).squaredNorm(); });
    err.h1 += quadrature::integrate_polygon(
        poly, [&](const Vec2& x) { return (exact_gradient(x) - f.gradient).squaredNorm(); });
    err.energy += quadrature::integrate_polygon(poly, [&](const Vec2& x) {
      const Eigen::Matrix2d g = exact_gradient(x) - f.gradient;
      return (stress(g).cwiseProduct(0.5 * (g + g.transpose()))).sum();
    });
  }
  err.l2 = std::sqrt(err.l2);
  err.h1 = std::sqrt(err.h1);
  err.energy = std::sqrt(err.energy);
  err.h = std::sqrt(mesh.total_area() / mesh.num_elements());
  return err;
}

double rate(const Errors& a, const Errors& b, double Errors::*m) {
  return std::log(a.*m / b.*m) / std::log(a.h / b.h);
}

class Convergence : public ::testing::TestWithParam<std::string> {};

TEST_P(Convergence, OptimalRatesOverFourLevels) {
  std::vector<Errors> levels;
  for (int n : {8, 16, 32, 64}) levels.push_back(solve_and_measure(make_mesh(GetParam(), n, Rectangle{}, 3)));
  for (std::size_t i = 0; i < levels.size(); ++i) {
    std::cout << GetParam() << " h=" << levels[i].h << " L2=" << levels[i].l2 << " H1=" << levels[i].h1
              << " energy=" << levels[i].energy;
    if (i > 0)
      std::cout << "  rates L2 " << rate(levels[i - 1], levels[i], &Errors::l2) << " H1 "
                << rate(levels[i - 1], levels[i], &Errors::h1) << " energy " << rate(levels[i - 1], levels[i], &Errors::energy);
    std::cout << "\n";
  }
  const Errors& a = levels[levels.size() - 2];
  const Errors& b = levels.back();
  EXPECT_GE(rate(a, b, &Errors::h1), 0.95);
  EXPECT_GE(rate(a, b, &Errors::energy), 0.95);
  EXPECT_GE(rate(a, b, &Errors::l2), 1.9);
  // errors decrease at every level
  for (std::size_t i = 1; i < levels.size(); ++i) {
    EXPECT_LT(levels[i].energy, levels[i - 1].energy);
    EXPECT_LT(levels[i].l2, levels[i - 1].l2);
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, Convergence, ::testing::Values("squares", "triangles", "voronoi", "nonconvex"));

TEST(ManufacturedSolution, EnergyErrorOnSquaresMatchesIndependentImplementation) {
  // An independent implementation of the same formulas on squares gives energy errors of
  // 2.58 (64 elements) and 0.322 (4096 elements). On 4096 elements hemivem agrees to the
  // digits quoted (0.32245). On 64 elements it gives 2.5703, 0.4 % below: the body-force
  // load is integrated here with a degree-5 rule on each polygon; integrating it with the
  // vertex values instead gives 2.5779. The difference is a quadrature effect that vanishes
  // under refinement (0.002 % at 4096 elements), so the coarse value is checked to 0.5 %.
  EXPECT_NEAR(solve_and_measure(make_squares(64)).energy, 0.322, 0.0005);
  EXPECT_NEAR(solve_and_measure(make_squares(8)).energy, 2.58, 0.005 * 2.58);
}

}  // namespace
