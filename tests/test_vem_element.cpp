// Element matrices of the lowest-order VEM: symmetry, semi-definiteness, the kernel,
// consistency on P1 fields and the projection.
#include <hemivem/error.hpp>
#include <hemivem/vem/element.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace hemivem;

namespace {

struct Polygon {
  std::string name;
  std::vector<Vec2> z;
};

std::vector<Polygon> polygons() {
  return {
      {"triangle", {{0.1, 0.2}, {1.3, 0.1}, {0.4, 0.9}}},
      {"square", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
      {"far-rectangle", {{1e3, 2e3}, {1e3 + 0.5, 2e3}, {1e3 + 0.5, 2e3 + 0.25}, {1e3, 2e3 + 0.25}}},
      {"pentagon", {{0, 0}, {2, 0.3}, {2.4, 1.5}, {1.1, 2.2}, {-0.3, 1.1}}},
      {"nonconvex-octagon",
       {{0, 0}, {0.75, 0.25}, {1, 0}, {1.25, 0.75}, {1, 1}, {0.75, 1.25}, {0, 1}, {0.25, 0.75}}},
      {"straight-angle", {{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {0, 1}}},
      {"tiny-edge", {{0, 0}, {1, 0}, {1, 1}, {1 - 1e-13, 1}, {0, 1}}},
      {"decagon", [] {
         std::vector<Vec2> z;
         for (int i = 0; i < 10; ++i) z.emplace_back(std::cos(2 * M_PI * i / 10) * (1 + 0.2 * (i % 3)), std::sin(2 * M_PI * i / 10));
         return z;
       }()},
  };
}

const Lame kLame = lame(Material{65.0, 0.29}, PlaneModel::strain);

// Nodal values of the P1 field a + G (x - z_0) (centred at the first vertex, so that the
// values carry no cancellation error for elements far from the origin).
Eigen::VectorXd nodal(const std::vector<Vec2>& z, const Vec2& a, const Eigen::Matrix2d& G) {
  Eigen::VectorXd v(2 * z.size());
  for (std::size_t i = 0; i < z.size(); ++i) v.segment<2>(2 * static_cast<Eigen::Index>(i)) = a + G * (z[i] - z[0]);
  return v;
}

// The six P1 fields: two translations, rotation, three strains.
std::vector<Eigen::VectorXd> p1_basis(const std::vector<Vec2>& z) {
  std::vector<Eigen::VectorXd> out;
  out.push_back(nodal(z, {1, 0}, Eigen::Matrix2d::Zero()));
  out.push_back(nodal(z, {0, 1}, Eigen::Matrix2d::Zero()));
  Eigen::Matrix2d G;
  G << 0, -1, 1, 0;
  out.push_back(nodal(z, {0, 0}, G));
  G << 1, 0, 0, 0;
  out.push_back(nodal(z, {0, 0}, G));
  G << 0, 0, 0, 1;
  out.push_back(nodal(z, {0, 0}, G));
  G << 0, 1, 1, 0;
  out.push_back(nodal(z, {0, 0}, G));
  return out;
}

class VemElementTest : public ::testing::TestWithParam<Polygon> {};

TEST_P(VemElementTest, SymmetricPositiveSemidefiniteWithRigidKernel) {
  const auto& z = GetParam().z;
  for (auto stab : {Stabilization::two_mu, Stabilization::trace_scaled}) {
    const VemElement el = vem_element(z, kLame, stab);
    const Eigen::MatrixXd K = el.stiffness();
    const double scale = K.cwiseAbs().maxCoeff();
    EXPECT_LE((K - K.transpose()).cwiseAbs().maxCoeff(), 1e-14 * scale);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()));
    const Eigen::VectorXd ev = eig.eigenvalues();
    EXPECT_GE(ev.minCoeff(), -1e-12 * ev.maxCoeff());
    int zero = 0;
    for (Eigen::Index i = 0; i < ev.size(); ++i) zero += ev(i) < 1e-10 * ev.maxCoeff();
    EXPECT_EQ(zero, 3) << "kernel dimension; eigenvalues " << ev.transpose();
    // the three rigid motions are in the kernel
    const auto basis = p1_basis(z);
    for (int r = 0; r < 3; ++r) EXPECT_LE((K * basis[r]).norm(), 1e-12 * scale * basis[r].norm()) << "rigid motion " << r;
    // and the strain modes are not
    for (int r = 3; r < 6; ++r) EXPECT_GT((K * basis[r]).norm(), 1e-6 * scale * basis[r].norm());
  }
}

TEST_P(VemElementTest, ProjectionIsAProjectionOntoP1) {
  const auto& z = GetParam().z;
  const VemElement el = vem_element(z, kLame);
  const Eigen::MatrixXd& Pi = el.projection;
  const double n2 = static_cast<double>(Pi.rows());
  EXPECT_LE((Pi * Pi - Pi).cwiseAbs().maxCoeff(), 1e-11 * n2);
  for (const auto& p : p1_basis(z)) EXPECT_LE((Pi * p - p).norm(), 1e-11 * p.norm());
  // the stabilization vanishes on P1 fields
  const double s = el.stabilization.cwiseAbs().maxCoeff();
  for (const auto& p : p1_basis(z)) EXPECT_LE((el.stabilization * p).norm(), 1e-11 * std::max(s, 1.0) * p.norm());
  if (z.size() == 3) {
    EXPECT_LE(el.stabilization.cwiseAbs().maxCoeff(), 1e-11 * el.consistency.cwiseAbs().maxCoeff());
  } else {
    EXPECT_GT(s, 0.0);
  }
  // Rank of Pi is 6 (the dimension of P1^2) once there are more than three vertices.
  Eigen::FullPivLU<Eigen::MatrixXd> lu(Pi);
  lu.setThreshold(1e-9);
  EXPECT_EQ(lu.rank(), 6);
}

TEST_P(VemElementTest, ConsistencyOnP1Fields) {
  // a_h(p, v) = int_E C eps(p) : eps(v) for p in P1^2 and any v; for v also P1 the
  // right side is |E| eps(p)^T C eps(v).
  const auto& z = GetParam().z;
  const VemElement el = vem_element(z, kLame);
  const Eigen::Matrix3d C = elasticity_matrix(kLame);
  Eigen::Matrix2d G;
  G << 0.3, -1.1, 0.7, 0.2;
  const Eigen::VectorXd p = nodal(z, {0.5, -2.0}, G);
  const Eigen::Vector3d ep(G(0, 0), G(1, 1), G(0, 1) + G(1, 0));
  // strain of a P1 field is exact
  EXPECT_LE((el.strain * p - ep).norm(), 1e-12 * ep.norm());
  const Eigen::MatrixXd K = el.stiffness();
  Eigen::Matrix2d H;
  H << -0.4, 0.9, 0.1, 1.3;
  const Eigen::VectorXd q = nodal(z, {1.0, 1.0}, H);
  const Eigen::Vector3d eq(H(0, 0), H(1, 1), H(0, 1) + H(1, 0));
  const double exact = el.area * ep.dot(C * eq);
  EXPECT_NEAR(q.dot(K * p), exact, 1e-11 * std::abs(exact));
  // For a non-P1 v, a_h(p, v) only sees the projected strain of v.
  Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(p.size(), -1.0, 2.0).array().sin();
  EXPECT_NEAR(v.dot(K * p), el.area * (el.strain * v).dot(C * ep), 1e-11 * K.norm() * v.norm() * p.norm());
}

TEST_P(VemElementTest, ProjectedStrainIsTheMeanStrainOfTheEdgeTraces) {
  // (1/|E|) sum_e int_e sym(v (x) n) for v = (x^2, x y): mean of sym grad over the polygon
  // is not needed; check instead against the divergence theorem for a P1 field plus
  // a field vanishing at all vertices (which contributes nothing): B sees only vertex values.
  const auto& z = GetParam().z;
  const VemElement el = vem_element(z, kLame);
  const auto basis = p1_basis(z);
  Eigen::MatrixXd strains(3, 6);
  for (int k = 0; k < 6; ++k) strains.col(k) = el.strain * basis[k];
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(3, 6);
  expected(0, 3) = 1;
  expected(1, 4) = 1;
  expected(2, 5) = 2;
  EXPECT_LE((strains - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_P(VemElementTest, ProjectionsReproduceLinearFields) {
  const auto& z = GetParam().z;
  Eigen::Matrix2d G;
  G << 0.3, -1.1, 0.7, 0.2;
  const Vec2 a(0.5, -2.0);
  const Eigen::VectorXd p = nodal(z, a, G);
  for (const LinearField& f : {project_p1(z, p), project_gradient(z, p)}) {
    EXPECT_LE((f.gradient - G).cwiseAbs().maxCoeff(), 1e-11);
    for (const auto& x : z) EXPECT_LE((f(x) - (a + G * (x - z[0]))).norm(), 1e-12 * (1 + x.norm()));
  }
}

TEST_P(VemElementTest, ProjectedStrainIsTheStrainOfTheProjectionAndOfTheStrainMatrix) {
  // projected_strain (what the stresses use) against two independent routes: B v of the
  // element's strain matrix and the symmetric part of Pi v's gradient, for a field that is
  // not P1 (so that the projection matters), and exactly the strain of a P1 field
  const auto& z = GetParam().z;
  const VemElement el = vem_element(z, kLame);
  const Eigen::Index n2 = 2 * static_cast<Eigen::Index>(z.size());
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(n2, -1.0, 2.0).array().sin();
  const Eigen::Vector3d eps = projected_strain(z, v);
  const Eigen::Vector3d Bv = el.strain * v;
  const LinearField f = project_p1(z, v);
  const double scale = 1e-13 * (1.0 + Bv.cwiseAbs().maxCoeff());
  EXPECT_LE((eps - Bv).cwiseAbs().maxCoeff(), scale);
  EXPECT_NEAR(eps(0), f.gradient(0, 0), scale);
  EXPECT_NEAR(eps(1), f.gradient(1, 1), scale);
  EXPECT_NEAR(eps(2), f.gradient(0, 1) + f.gradient(1, 0), scale);
  Eigen::Matrix2d G;
  G << 0.3, -1.1, 0.7, 0.2;
  const Eigen::Vector3d affine = projected_strain(z, nodal(z, Vec2(0.5, -2.0), G));
  EXPECT_LE((affine - Eigen::Vector3d(0.3, 0.2, -0.4)).cwiseAbs().maxCoeff(), 1e-11);
}

TEST(VemElement, ProjectedStrainRefusesAPolygonOfNoArea) {
  const std::vector<Vec2> clockwise{{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  EXPECT_THROW((void)projected_strain(clockwise, Eigen::VectorXd::Zero(8)), MeshError);
  const std::vector<Vec2> two{{0, 0}, {1, 0}};
  EXPECT_THROW((void)projected_strain(two, Eigen::VectorXd::Zero(4)), InputError);
}

TEST_P(VemElementTest, TraceScaledStabilizationWeight) {
  const auto& z = GetParam().z;
  const VemElement a = vem_element(z, kLame, Stabilization::two_mu);
  const VemElement b = vem_element(z, kLame, Stabilization::trace_scaled);
  EXPECT_DOUBLE_EQ(a.tau, 2 * kLame.mu);
  EXPECT_NEAR(b.tau, a.consistency.trace() / static_cast<double>(2 * z.size()), 1e-14 * b.tau);
  EXPECT_LE((b.stabilization - b.tau / a.tau * a.stabilization).cwiseAbs().maxCoeff(),
            1e-12 * b.stabilization.cwiseAbs().maxCoeff() + 1e-300);
}

INSTANTIATE_TEST_SUITE_P(Polygons, VemElementTest, ::testing::ValuesIn(polygons()),
                         [](const auto& info) {
                           std::string s = info.param.name;
                           for (auto& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(VemElement, HandComputedSquare) {
  // Unit square, E = 1, nu = 0 (lambda = 0, mu = 1/2). Projected strain of the nodal
  // field that moves only vertex 2 = (1,1) by (1, 0): eps_xx = 1/2, 2 eps_xy = 1/2.
  const std::vector<Vec2> z{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const Lame l = lame(Material{1.0, 0.0}, PlaneModel::strain);
  EXPECT_DOUBLE_EQ(l.lambda, 0.0);
  EXPECT_DOUBLE_EQ(l.mu, 0.5);
  const VemElement el = vem_element(z, l);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(8);
  v(4) = 1.0;
  const Eigen::Vector3d e = el.strain * v;
  EXPECT_NEAR(e(0), 0.5, 1e-15);
  EXPECT_NEAR(e(1), 0.0, 1e-15);
  EXPECT_NEAR(e(2), 0.5, 1e-15);
  // consistency energy = |E| (2 mu e_xx^2 + mu gamma^2) = 0.25 + 0.125
  EXPECT_NEAR(v.dot(el.consistency * v), 0.375, 1e-15);
  // Pi v: the bilinear field x*y (in u_x) has no P1 part beyond its mean strain; at the
  // vertices, v - Pi v = (1/4)(1, -1, 1, -1) in u_x, so the stabilization energy is
  // 2 mu * 4 / 16 = 0.25.
  EXPECT_NEAR(v.dot(el.stabilization * v), 0.25, 1e-14);
}

}  // namespace
