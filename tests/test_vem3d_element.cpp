// The 3D lowest-order virtual element: face weights exact on linear functions, the patch test
// on every kind of cell (convex or not), the projection, the kernel, equality with linear
// finite elements on tetrahedra, the scaling of the stiffness and the errors.
#include <hemivem/vem/element3d.hpp>

#include <hemivem/error.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace hemivem;

namespace {

using Faces = std::vector<std::vector<int>>;

const Lame kLame = lame(Material{65.0, 0.29}, PlaneModel::strain);

// ---------------------------------------------------------------------------------------------
// Face weights

// A planar polygon given in 2D coordinates (counter-clockwise) and placed in space by an
// orthonormal frame: x = origin + u e1 + v e2.
struct PlanarPolygon {
  std::string name;
  std::vector<Vec2> uv;
  Vec3 origin, e1, e2;
  std::vector<Vec3> points() const {
    std::vector<Vec3> z;
    for (const auto& p : uv) z.push_back(origin + p.x() * e1 + p.y() * e2);
    return z;
  }
};

// int_f g for a linear g, by a fan of triangles from the first vertex with signed areas (in the
// polygon's own 2D coordinates): each triangle contributes its area times g at its centroid.
template <class G>
double fan_integral(const PlanarPolygon& f, const G& g) {
  double sum = 0.0;
  const auto z = f.points();
  for (std::size_t i = 1; i + 1 < f.uv.size(); ++i) {
    const Vec2 a = f.uv[i] - f.uv[0], b = f.uv[i + 1] - f.uv[0];
    const double area = 0.5 * (a.x() * b.y() - a.y() * b.x());
    sum += area * g((z[0] + z[i] + z[i + 1]) / 3.0);
  }
  return sum;
}

std::vector<PlanarPolygon> planar_polygons() {
  const Vec3 t1 = Vec3(1.0, 2.0, -0.5).normalized();
  const Vec3 t2 = t1.cross(Vec3(0.3, -0.4, 1.0)).normalized();
  return {
      {"triangle", {{0.1, 0.2}, {1.3, 0.1}, {0.4, 0.9}}, Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()},
      {"quad-in-xz", {{0, 0}, {2, 0.3}, {1.7, 1.4}, {-0.2, 0.9}}, Vec3(0.5, 1.0, -2.0), Vec3::UnitX(), Vec3::UnitZ()},
      // a non-convex hexagon, tilted in space, whose vertex mean is not its centroid
      {"tilted-nonconvex-hexagon",
       {{0, 0}, {3, 0}, {3, 0.5}, {0.8, 0.7}, {1.0, 2.5}, {0, 2.0}},
       Vec3(-1.0, 0.4, 2.0),
       t1,
       t2},
      // a U whose vertex mean lies outside it
      {"tilted-u", {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}, Vec3(10.0, -3.0, 7.0), t2, t1},
  };
}

TEST(FaceWeights, ExactForLinearFunctions) {
  for (const auto& f : planar_polygons()) {
    SCOPED_TRACE(f.name);
    const auto z = f.points();
    const Eigen::VectorXd w = face_weights(z);
    ASSERT_EQ(w.size(), static_cast<Eigen::Index>(z.size()));
    const double area = fan_integral(f, [](const Vec3&) { return 1.0; });
    EXPECT_GT(area, 0.0);
    EXPECT_NEAR(w.sum(), area, 1e-14 * area);
    const std::vector<Eigen::Vector4d> linear{{0.0, 1.0, 0.0, 0.0},
                                              {0.0, 0.0, 1.0, 0.0},
                                              {0.0, 0.0, 0.0, 1.0},
                                              {0.7, -1.3, 0.4, 2.1}};
    for (const auto& c : linear) {
      const auto g = [&](const Vec3& x) { return c(0) + c.tail<3>().dot(x); };
      double quadrature = 0.0;
      for (std::size_t i = 0; i < z.size(); ++i) quadrature += w(static_cast<Eigen::Index>(i)) * g(z[i]);
      const double exact = fan_integral(f, g);
      double scale = 0.0;
      for (const auto& x : z) scale = std::max(scale, std::abs(g(x)));
      EXPECT_NEAR(quadrature, exact, 1e-13 * area * scale) << "g = " << c.transpose();
    }
  }
}

TEST(FaceWeights, TriangleWeightsAreAThirdOfTheArea) {
  const std::vector<Vec3> z{{0.1, 0.2, 0.3}, {1.3, 0.1, -0.2}, {0.4, 0.9, 0.5}};
  const double area = 0.5 * (z[1] - z[0]).cross(z[2] - z[0]).norm();
  const Eigen::VectorXd w = face_weights(z);
  for (Eigen::Index i = 0; i < 3; ++i) EXPECT_NEAR(w(i), area / 3.0, 1e-15 * area);
}

TEST(FaceWeights, RejectsFewerThanThreeVertices) {
  const std::vector<Vec3> z{{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(face_weights(z), InputError);
}

// ---------------------------------------------------------------------------------------------
// Cells

struct Cell {
  std::string name;
  std::vector<Vec3> z;
  Faces faces;
  double volume = 0.0;  // known in closed form
};

double shoelace(const std::vector<Vec2>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

// The solid between a base polygon (counter-clockwise seen from above, at z = 0) and a top
// polygon with the same number of vertices: the bottom face, the top face and one side face
// per edge, all counter-clockwise seen from outside.
Cell loft(std::string name, const std::vector<Vec2>& base, const std::vector<Vec3>& top, double volume) {
  Cell c{std::move(name), {}, {}, volume};
  const int n = static_cast<int>(base.size());
  for (const auto& p : base) c.z.emplace_back(p.x(), p.y(), 0.0);
  for (const auto& p : top) c.z.push_back(p);
  std::vector<int> bottom, upper;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  for (int i = 0; i < n; ++i) upper.push_back(n + i);
  c.faces = {bottom, upper};
  for (int i = 0; i < n; ++i) c.faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  return c;
}

Cell prism(std::string name, const std::vector<Vec2>& base, const Vec3& d) {
  std::vector<Vec3> top;
  for (const auto& p : base) top.push_back(Vec3(p.x(), p.y(), 0.0) + d);
  return loft(std::move(name), base, top, shoelace(base) * d.z());
}

// The pyramid of apex `apex` cut at the fraction t of the way from the base to the apex.
Cell frustum(std::string name, const std::vector<Vec2>& base, const Vec3& apex, double t) {
  std::vector<Vec3> top;
  for (const auto& p : base) {
    const Vec3 b(p.x(), p.y(), 0.0);
    top.push_back(b + t * (apex - b));
  }
  const double full = shoelace(base) * apex.z() / 3.0;
  return loft(std::move(name), base, top, full * (1.0 - std::pow(1.0 - t, 3)));
}

Cell pyramid(std::string name, const std::vector<Vec2>& base, const Vec3& apex) {
  Cell c{std::move(name), {}, {}, shoelace(base) * apex.z() / 3.0};
  const int n = static_cast<int>(base.size());
  for (const auto& p : base) c.z.emplace_back(p.x(), p.y(), 0.0);
  c.z.push_back(apex);
  std::vector<int> bottom;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  c.faces = {bottom};
  for (int i = 0; i < n; ++i) c.faces.push_back({i, (i + 1) % n, n});
  return c;
}

// x -> A x + b: faces stay planar, the volume is multiplied by det A (> 0).
Cell affine(Cell c, std::string name) {
  Eigen::Matrix3d A;
  A << 1.1, 0.3, -0.2,  //
      0.1, 0.9, 0.25,   //
      -0.15, 0.2, 1.3;
  const Vec3 b(0.3, -0.5, 0.7);
  for (auto& x : c.z) x = A * x + b;
  c.volume *= A.determinant();
  c.name = std::move(name);
  return c;
}

Cell translated(Cell c, const Vec3& b, std::string name) {
  for (auto& x : c.z) x += b;
  c.name = std::move(name);
  return c;
}

// The unit cube with a vertex at the middle of the edge (1,0,0)-(1,1,0), on two of its faces
// (straight angles in those faces).
Cell cube_with_edge_vertex() {
  Cell c = prism("cube-with-edge-vertex", {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, Vec3::UnitZ());
  c.z.emplace_back(1.0, 0.5, 0.0);  // vertex 8, between vertices 1 and 2
  c.faces[0] = {3, 2, 8, 1, 0};     // bottom
  c.faces[3] = {1, 8, 2, 6, 5};     // side x = 1
  return c;
}

const std::vector<Vec2> kSquare{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
const std::vector<Vec2> kTriangle{{0, 0}, {1.2, 0.1}, {0.3, 0.9}};
const std::vector<Vec2> kQuad{{0, 0}, {2, 0}, {1.8, 1.5}, {-0.1, 1.1}};
const std::vector<Vec2> kL{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
const std::vector<Vec2> kU{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};

std::vector<Cell> cells() {
  return {
      prism("unit-cube", kSquare, Vec3::UnitZ()),
      translated(prism("", kSquare, Vec3::UnitZ()), Vec3(1e3, -2e3, 5e2), "far-cube"),
      affine(frustum("", kQuad, Vec3(0.7, 0.4, 3.0), 0.4), "hexahedron"),
      pyramid("tetrahedron", kTriangle, Vec3(0.4, 0.3, 1.1)),
      affine(prism("", kTriangle, Vec3(0.2, -0.1, 0.8)), "prism"),
      affine(pyramid("", kQuad, Vec3(0.6, 0.5, 1.3)), "pyramid"),
      affine(prism("", kL, Vec3(0.2, 0.1, 1.3)), "l-prism"),
      prism("u-prism", kU, Vec3(-0.3, 0.2, 0.9)),
      cube_with_edge_vertex(),
  };
}

// Nodal values of the P1 field a + G (x - z_0) (centred at the first vertex, so that a cell far
// from the origin carries no cancellation error in its values).
Eigen::VectorXd nodal(const std::vector<Vec3>& z, const Vec3& a, const Eigen::Matrix3d& G) {
  Eigen::VectorXd v(3 * static_cast<Eigen::Index>(z.size()));
  for (std::size_t i = 0; i < z.size(); ++i) v.segment<3>(3 * static_cast<Eigen::Index>(i)) = a + G * (z[i] - z[0]);
  return v;
}

Eigen::Matrix3d skew(const Vec3& w) {
  Eigen::Matrix3d W;
  W << 0, -w.z(), w.y(),  //
      w.z(), 0, -w.x(),   //
      -w.y(), w.x(), 0;
  return W;
}

// The twelve P1 fields: three translations, three rotations, six strains.
std::vector<Eigen::VectorXd> p1_basis(const std::vector<Vec3>& z) {
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k < 3; ++k) out.push_back(nodal(z, Vec3::Unit(k), Eigen::Matrix3d::Zero()));
  for (int k = 0; k < 3; ++k) out.push_back(nodal(z, Vec3::Zero(), skew(Vec3::Unit(k))));
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    G(k, k) = 1.0;
    out.push_back(nodal(z, Vec3::Zero(), G));
  }
  for (const auto& [r, c] : {std::pair{1, 2}, std::pair{0, 2}, std::pair{0, 1}}) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    G(r, c) = G(c, r) = 1.0;
    out.push_back(nodal(z, Vec3::Zero(), G));
  }
  return out;
}

// The strain of the gradient G in Voigt form (xx, yy, zz, 2yz, 2xz, 2xy).
Eigen::Matrix<double, 6, 1> voigt(const Eigen::Matrix3d& G) {
  Eigen::Matrix<double, 6, 1> e;
  e << G(0, 0), G(1, 1), G(2, 2), G(1, 2) + G(2, 1), G(0, 2) + G(2, 0), G(0, 1) + G(1, 0);
  return e;
}

double max_abs(const Eigen::MatrixXd& M) { return M.cwiseAbs().maxCoeff(); }

class VemElement3DTest : public ::testing::TestWithParam<Cell> {};

TEST_P(VemElement3DTest, VolumeAndVertexMean) {
  const Cell& c = GetParam();
  const VemElement3D el = vem_element_3d(c.z, c.faces, kLame);
  EXPECT_NEAR(el.volume, c.volume, 1e-13 * c.volume);
  Vec3 mean = Vec3::Zero();
  for (const auto& x : c.z) mean += x;
  mean /= static_cast<double>(c.z.size());
  EXPECT_LE((el.vertex_mean - mean).norm(), 1e-14 * mean.norm() + 1e-15);
  EXPECT_EQ(el.strain.rows(), 6);
  EXPECT_EQ(el.strain.cols(), 3 * static_cast<Eigen::Index>(c.z.size()));
}

TEST_P(VemElement3DTest, PatchTest) {
  const Cell& c = GetParam();
  const VemElement3D el = vem_element_3d(c.z, c.faces, kLame);
  const Eigen::Matrix<double, 6, 6> C = elasticity_matrix_3d(kLame);
  Eigen::Matrix3d G;
  G << 0.3, -1.1, 0.7,  //
      0.2, -0.4, 0.9,   //
      -0.6, 0.5, 1.2;
  const Vec3 a(0.5, -2.0, 0.8);
  const Eigen::VectorXd u = nodal(c.z, a, G);
  const Eigen::Matrix<double, 6, 1> eps = voigt(G);
  // the projected strain of a linear field is its strain
  EXPECT_LE((el.strain * u - eps).norm(), 1e-12 * eps.norm());
  // Pi u = u, S u = 0 (S = tau (I - Pi)^T (I - Pi) has the scale tau: on a tetrahedron, where
  // Pi = I, S itself is round-off)
  EXPECT_LE((el.projection * u - u).norm(), 1e-12 * u.norm());
  const Eigen::MatrixXd K = el.stiffness();
  EXPECT_LE((el.stabilization * u).norm(), 1e-12 * el.tau * u.norm());
  // K u equals the nodal forces of the exact constant stress, |E| B^T C eps(u)
  const Eigen::VectorXd forces = el.volume * el.strain.transpose() * (C * eps);
  EXPECT_LE((K * u - forces).norm(), 1e-12 * K.norm() * u.norm());
  // which are in equilibrium
  Vec3 resultant = Vec3::Zero();
  Vec3 moment = Vec3::Zero();
  for (std::size_t i = 0; i < c.z.size(); ++i) {
    const Vec3 f = forces.segment<3>(3 * static_cast<Eigen::Index>(i));
    resultant += f;
    moment += (c.z[i] - el.vertex_mean).cross(f);
  }
  EXPECT_LE(resultant.norm(), 1e-12 * forces.norm());
  EXPECT_LE(moment.norm(), 1e-12 * forces.norm() * std::cbrt(el.volume));
}

TEST_P(VemElement3DTest, ProjectionIsAProjectionOntoP1) {
  const Cell& c = GetParam();
  const VemElement3D el = vem_element_3d(c.z, c.faces, kLame);
  const Eigen::MatrixXd& Pi = el.projection;
  EXPECT_LE(max_abs(Pi * Pi - Pi), 1e-12 * max_abs(Pi));
  for (const auto& p : p1_basis(c.z)) EXPECT_LE((Pi * p - p).norm(), 1e-12 * p.norm());
  const double s = el.stabilization.norm();
  for (const auto& p : p1_basis(c.z)) EXPECT_LE((el.stabilization * p).norm(), 1e-12 * el.tau * p.norm());
  // Pi has the rank of P1^3 (12)
  Eigen::FullPivLU<Eigen::MatrixXd> lu(Pi);
  lu.setThreshold(1e-9);
  EXPECT_EQ(lu.rank(), 12);
  if (c.z.size() > 4) {
    EXPECT_GT(s, 1e-3 * el.consistency.norm());
  }
}

TEST_P(VemElement3DTest, SymmetricPositiveSemidefiniteWithRigidKernel) {
  const Cell& c = GetParam();
  const auto basis = p1_basis(c.z);
  for (auto stab : {Stabilization::two_mu, Stabilization::trace_scaled}) {
    const VemElement3D el = vem_element_3d(c.z, c.faces, kLame, stab);
    const Eigen::MatrixXd K = el.stiffness();
    const double scale = max_abs(K);
    EXPECT_LE(max_abs(K - K.transpose()), 1e-14 * scale);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (K + K.transpose()));
    const Eigen::VectorXd ev = eig.eigenvalues();
    EXPECT_GE(ev.minCoeff(), -1e-12 * ev.maxCoeff());
    int zero = 0;
    for (Eigen::Index i = 0; i < ev.size(); ++i) zero += ev(i) < 1e-10 * ev.maxCoeff();
    EXPECT_EQ(zero, 6) << "kernel dimension; eigenvalues " << ev.transpose();
    for (int r = 0; r < 6; ++r)
      EXPECT_LE((K * basis[static_cast<std::size_t>(r)]).norm(), 1e-12 * scale * basis[static_cast<std::size_t>(r)].norm())
          << "rigid motion " << r;
    for (int r = 6; r < 12; ++r)
      EXPECT_GT((K * basis[static_cast<std::size_t>(r)]).norm(), 1e-6 * scale * basis[static_cast<std::size_t>(r)].norm())
          << "strain mode " << r;
    // element_stiffness_3d computes the same matrix
    Eigen::MatrixXd K2;
    element_stiffness_3d(c.z, c.faces, kLame, stab, K2);
    EXPECT_EQ(K2, K);
  }
}

TEST_P(VemElement3DTest, StabilizationWeights) {
  const Cell& c = GetParam();
  const VemElement3D a = vem_element_3d(c.z, c.faces, kLame, Stabilization::two_mu);
  const VemElement3D b = vem_element_3d(c.z, c.faces, kLame, Stabilization::trace_scaled);
  EXPECT_NEAR(a.tau, 2 * kLame.mu * std::cbrt(c.volume), 1e-14 * a.tau);
  EXPECT_NEAR(b.tau, a.consistency.trace() / static_cast<double>(3 * c.z.size()), 1e-14 * b.tau);
  EXPECT_LE(max_abs(b.stabilization - b.tau / a.tau * a.stabilization), 1e-12 * max_abs(b.stabilization) + 1e-300);
}

TEST_P(VemElement3DTest, ProjectionsReproduceLinearFields) {
  const Cell& c = GetParam();
  Eigen::Matrix3d G;
  G << 0.3, -1.1, 0.7,  //
      0.2, -0.4, 0.9,   //
      -0.6, 0.5, 1.2;
  const Vec3 a(0.5, -2.0, 0.8);
  const Eigen::VectorXd u = nodal(c.z, a, G);
  for (const LinearField3& f : {project_p1_3d(c.z, c.faces, u), project_gradient_3d(c.z, c.faces, u)}) {
    EXPECT_LE((f.gradient - G).cwiseAbs().maxCoeff(), 1e-12 * G.cwiseAbs().maxCoeff());
    for (const auto& x : c.z) EXPECT_LE((f(x) - (a + G * (x - c.z[0]))).norm(), 1e-12 * u.norm());
  }
  // on any nodal values, project_p1_3d is the projection matrix and project_gradient_3d has the
  // projected strain as the symmetric part of its gradient
  const VemElement3D el = vem_element_3d(c.z, c.faces, kLame);
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(u.size(), -1.0, 2.0).array().sin();
  const LinearField3 p = project_p1_3d(c.z, c.faces, v);
  const Eigen::VectorXd Piv = el.projection * v;
  for (std::size_t i = 0; i < c.z.size(); ++i)
    EXPECT_LE((p(c.z[i]) - Piv.segment<3>(3 * static_cast<Eigen::Index>(i))).norm(), 1e-12 * v.norm());
  const LinearField3 g = project_gradient_3d(c.z, c.faces, v);
  EXPECT_LE((voigt(g.gradient) - el.strain * v).norm(), 1e-12 * (el.strain * v).norm());
  EXPECT_LE((voigt(p.gradient) - el.strain * v).norm(), 1e-12 * (el.strain * v).norm());
  Vec3 mean = Vec3::Zero();
  for (Eigen::Index i = 0; i < v.size() / 3; ++i) mean += v.segment<3>(3 * i);
  EXPECT_LE((g.value - mean / static_cast<double>(c.z.size())).norm(), 1e-14 * mean.norm());
  EXPECT_LE((g.center - el.vertex_mean).norm(), 1e-14 * el.vertex_mean.norm() + 1e-15);
}

TEST_P(VemElement3DTest, StiffnessScalesLikeTheCell) {
  // u(s x) = u(x): the strain scales like 1/s, the volume like s^3, the energy like s
  const Cell& c = GetParam();
  for (const double s : {3.7, 1e-3}) {
    std::vector<Vec3> z = c.z;
    for (auto& x : z) x *= s;
    for (auto stab : {Stabilization::two_mu, Stabilization::trace_scaled}) {
      const VemElement3D a = vem_element_3d(c.z, c.faces, kLame, stab);
      const VemElement3D b = vem_element_3d(z, c.faces, kLame, stab);
      EXPECT_LE(max_abs(b.consistency - s * a.consistency), 1e-12 * s * max_abs(a.consistency)) << "s = " << s;
      EXPECT_LE(max_abs(b.stabilization - s * a.stabilization), 1e-12 * s * max_abs(a.consistency)) << "s = " << s;
      EXPECT_NEAR(b.tau, s * a.tau, 1e-13 * s * a.tau);
    }
  }
}

TEST_P(VemElement3DTest, InwardFacesAreRejected) {
  Cell c = GetParam();
  for (auto& f : c.faces) std::reverse(f.begin(), f.end());
  EXPECT_THROW(vem_element_3d(c.z, c.faces, kLame), MeshError);
  Eigen::MatrixXd K;
  EXPECT_THROW(element_stiffness_3d(c.z, c.faces, kLame, Stabilization::two_mu, K), MeshError);
}

INSTANTIATE_TEST_SUITE_P(Cells, VemElement3DTest, ::testing::ValuesIn(cells()), [](const auto& info) {
  std::string s = info.param.name;
  for (auto& ch : s)
    if (ch == '-') ch = '_';
  return s;
});

TEST(VemElement3D, ElasticityMatrix) {
  const Lame l{2.0, 3.0};
  const Eigen::Matrix<double, 6, 6> C = elasticity_matrix_3d(l);
  // sigma : eps = e^T C e for the symmetric strain eps and its Voigt vector e
  Eigen::Matrix3d eps;
  eps << 0.3, 0.1, -0.2,  //
      0.1, -0.5, 0.4,     //
      -0.2, 0.4, 0.7;
  const Eigen::Matrix3d sigma = l.lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2 * l.mu * eps;
  const Eigen::Matrix<double, 6, 1> e = voigt(eps);
  EXPECT_NEAR(e.dot(C * e), (sigma.cwiseProduct(eps)).sum(), 1e-14);
  // and C e is the stress in Voigt form (xx, yy, zz, yz, xz, xy)
  const Eigen::Matrix<double, 6, 1> s = C * e;
  Eigen::Matrix<double, 6, 1> expected;
  expected << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(1, 2), sigma(0, 2), sigma(0, 1);
  EXPECT_LE((s - expected).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(VemElement3D, HandComputedCube) {
  // Unit cube, E = 1, nu = 0 (lambda = 0, mu = 1/2), moving only the vertex (1, 1, 1) by
  // (1, 0, 0): the nodal values of the trilinear field x y z in u_x.
  const Cell c = prism("unit-cube", kSquare, Vec3::UnitZ());
  const Lame l = lame(Material{1.0, 0.0}, PlaneModel::strain);
  const VemElement3D el = vem_element_3d(c.z, c.faces, l);
  EXPECT_DOUBLE_EQ(el.tau, 1.0);  // 2 mu |E|^(1/3)
  Eigen::VectorXd v = Eigen::VectorXd::Zero(24);
  v(3 * 6) = 1.0;  // vertex 6 = (1, 1, 1)
  // its mean gradient is (1/4, 1/4, 1/4) in the row of u_x
  Eigen::Matrix<double, 6, 1> e;
  e << 0.25, 0, 0, 0, 0.25, 0.25;
  EXPECT_LE((el.strain * v - e).norm(), 1e-15);
  // consistency energy |E| (2 mu e_xx^2 + mu (gamma_xz^2 + gamma_xy^2)) = 1/16 + 1/16
  EXPECT_NEAR(v.dot(el.consistency * v), 0.125, 1e-15);
  // Pi v = 1/8 + (x + y + z - 3/2)/4 in u_x; v - Pi v at the vertices is 1/4 at the origin, 0
  // at the three with one coordinate 1, -1/4 at the three with two and 1/2 at (1, 1, 1):
  // stabilization energy tau (1/16 + 3/16 + 1/4) = 1/2
  EXPECT_NEAR(v.dot(el.stabilization * v), 0.5, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Tetrahedra: the virtual element is the linear finite element

// A tetrahedron's four faces, outward for positively oriented vertices 0..3.
const Faces kTetFaces{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

// V B^T C B with B from the gradients of the barycentric coordinates: the columns of the
// inverse of the 4 x 4 matrix of rows [1 x_i y_i z_i] (coordinates relative to the first
// vertex, which leaves the gradients as they are and keeps M well conditioned far from the
// origin).
Eigen::MatrixXd p1_tetrahedron_stiffness(const std::vector<Vec3>& z, const Lame& l) {
  Eigen::Matrix4d M;
  for (int i = 0; i < 4; ++i) M.row(i) << 1.0, (z[static_cast<std::size_t>(i)] - z[0]).transpose();
  const Eigen::Matrix4d coef = M.inverse();  // phi_j = coef(0, j) + coef(1..3, j) . x
  const double volume = std::abs(M.determinant()) / 6.0;
  Eigen::Matrix<double, 6, 12> B = Eigen::Matrix<double, 6, 12>::Zero();
  for (int j = 0; j < 4; ++j) {
    const Vec3 g = coef.block<3, 1>(1, j);
    B(0, 3 * j) = g.x();
    B(1, 3 * j + 1) = g.y();
    B(2, 3 * j + 2) = g.z();
    B(3, 3 * j + 1) = g.z();
    B(3, 3 * j + 2) = g.y();
    B(4, 3 * j) = g.z();
    B(4, 3 * j + 2) = g.x();
    B(5, 3 * j) = g.y();
    B(5, 3 * j + 1) = g.x();
  }
  return volume * B.transpose() * elasticity_matrix_3d(l) * B;
}

TEST(VemElement3D, TetrahedronIsTheLinearFiniteElement) {
  const std::vector<std::vector<Vec3>> tetrahedra{
      {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
      {{0.1, 0.2, -0.3}, {1.7, 0.4, 0.1}, {0.5, 1.3, 0.2}, {0.6, 0.5, 2.1}},
      {{2.0, 1.0, 0.5}, {2.3, 1.05, 0.45}, {2.1, 1.4, 0.6}, {2.05, 1.1, 0.52}},  // flat and small
      {{1e3, 2e3, -1e3}, {1e3 + 0.8, 2e3 + 0.1, -1e3}, {1e3 + 0.2, 2e3 + 1.1, -1e3 + 0.3},
       {1e3 + 0.3, 2e3 + 0.2, -1e3 + 0.9}},  // far from the origin
  };
  for (const auto& z : tetrahedra) {
    ASSERT_GT((z[1] - z[0]).cross(z[2] - z[0]).dot(z[3] - z[0]), 0.0);
    for (auto stab : {Stabilization::two_mu, Stabilization::trace_scaled}) {
      const VemElement3D el = vem_element_3d(z, kTetFaces, kLame, stab);
      const Eigen::MatrixXd expected = p1_tetrahedron_stiffness(z, kLame);
      const Eigen::MatrixXd K = el.stiffness();
      EXPECT_LE((K - expected).norm(), 1e-12 * expected.norm()) << "tetrahedron at " << z[0].transpose();
      EXPECT_LT(el.stabilization.norm(), 1e-12 * K.norm());
      EXPECT_LE(max_abs(el.projection - Eigen::MatrixXd::Identity(12, 12)), 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST(VemElement3D, RejectsBadInput) {
  const std::vector<Vec3> z{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const auto throws_input_not_mesh = [&](const std::vector<Vec3>& vertices, const Faces& faces) {
    try {
      vem_element_3d(vertices, faces, kLame);
    } catch (const MeshError& e) {
      ADD_FAILURE() << "MeshError, expected InputError: " << e.what();
      return;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()), "");
      return;
    }
    ADD_FAILURE() << "no error";
  };
  Faces bad = kTetFaces;
  bad[2][1] = 4;  // out of range
  throws_input_not_mesh(z, bad);
  bad[2][1] = -1;
  throws_input_not_mesh(z, bad);
  bad = kTetFaces;
  bad[1] = {0, 1};  // a face of two vertices
  throws_input_not_mesh(z, bad);
  throws_input_not_mesh(z, Faces(kTetFaces.begin(), kTetFaces.begin() + 3));  // three faces
  throws_input_not_mesh({z[0], z[1], z[2]}, {{0, 2, 1}, {0, 1, 2}, {0, 2, 1}, {0, 1, 2}});  // three vertices
  std::vector<Vec3> extra = z;
  extra.emplace_back(5, 5, 5);  // a vertex on no face
  throws_input_not_mesh(extra, kTetFaces);
  Eigen::MatrixXd K;
  bad = kTetFaces;
  bad[0][0] = 7;
  EXPECT_THROW(element_stiffness_3d(z, bad, kLame, Stabilization::two_mu, K), InputError);
  EXPECT_THROW(project_p1_3d(z, bad, Eigen::VectorXd::Zero(12)), InputError);
  EXPECT_THROW(project_gradient_3d(z, bad, Eigen::VectorXd::Zero(12)), InputError);
}

TEST(VemElement3D, RejectsNonPositiveVolume) {
  // vertices in a plane: zero volume
  const std::vector<Vec3> flat{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_THROW(vem_element_3d(flat, {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}, kLame), MeshError);
  // a negatively oriented tetrahedron with the faces of a positive one
  const std::vector<Vec3> mirrored{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
  EXPECT_THROW(vem_element_3d(mirrored, kTetFaces, kLame), MeshError);
}

}  // namespace
