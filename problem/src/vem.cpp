#include <hemivem/error.hpp>
#include <hemivem/vem.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>

namespace hemivem {

std::string to_string(Stabilization s) { return s == Stabilization::two_mu ? "2mu" : "trace"; }

Stabilization stabilization_from_string(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s == "2mu" || s == "two-mu" || s == "two_mu") return Stabilization::two_mu;
  if (s == "trace" || s == "trace-scaled" || s == "trace_scaled") return Stabilization::trace_scaled;
  throw InputError("unknown stabilization '" + std::string(name) + "'; expected 2mu or trace");
}

Eigen::Matrix2Xd vertex_normals(std::span<const Vec2> z) {
  const Eigen::Index n = static_cast<Eigen::Index>(z.size());
  Eigen::Matrix2Xd m(2, n);  // m_i = |e_i| n_i for edge z_i -> z_{i+1}
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec2 d = z[static_cast<std::size_t>((i + 1) % n)] - z[static_cast<std::size_t>(i)];
    m.col(i) = Vec2(d.y(), -d.x());
  }
  Eigen::Matrix2Xd nu(2, n);
  for (Eigen::Index i = 0; i < n; ++i) nu.col(i) = 0.5 * (m.col((i + n - 1) % n) + m.col(i));
  return nu;
}

namespace {

struct Projection {
  Eigen::MatrixXd B;       // 3 x 2n projected strain
  Eigen::MatrixXd R;       // 2n x 3 rigid motions at the vertices (centred at the vertex mean)
  Eigen::MatrixXd Ds;      // 2n x 3 strain modes at the vertices
  Eigen::Vector3d RtR_inv; // (R^T R)^{-1}, diagonal because of the centring
  Vec2 mean = Vec2::Zero();
  double area = 0.0;
};

Projection build(std::span<const Vec2> z) {
  const Eigen::Index n = static_cast<Eigen::Index>(z.size());
  if (n < 3) throw InputError("a virtual element needs at least 3 vertices, got " + std::to_string(n));
  Projection p;
  p.area = signed_area(z);
  if (!(p.area > 0.0)) throw MeshError("element has non-positive area", -1);
  for (const auto& v : z) p.mean += v;
  p.mean /= static_cast<double>(n);

  const Eigen::Matrix2Xd nu = vertex_normals(z);
  p.B.setZero(3, 2 * n);
  p.R.setZero(2 * n, 3);
  p.Ds.setZero(2 * n, 3);
  double r2 = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double a = nu(0, i) / p.area, b = nu(1, i) / p.area;
    p.B(0, 2 * i) = a;
    p.B(2, 2 * i) = b;
    p.B(1, 2 * i + 1) = b;
    p.B(2, 2 * i + 1) = a;

    const Vec2 r = z[static_cast<std::size_t>(i)] - p.mean;
    r2 += r.squaredNorm();
    p.R(2 * i, 0) = 1.0;
    p.R(2 * i + 1, 1) = 1.0;
    p.R(2 * i, 2) = -r.y();
    p.R(2 * i + 1, 2) = r.x();
    p.Ds(2 * i, 0) = r.x();      // eps_xx mode (x, 0)
    p.Ds(2 * i + 1, 1) = r.y();  // eps_yy mode (0, y)
    p.Ds(2 * i, 2) = 0.5 * r.y();     // engineering shear mode (y/2, x/2)
    p.Ds(2 * i + 1, 2) = 0.5 * r.x();
  }
  p.RtR_inv = Eigen::Vector3d(1.0 / static_cast<double>(n), 1.0 / static_cast<double>(n), 1.0 / r2);
  return p;
}

}  // namespace

VemElement vem_element(std::span<const Vec2> z, const Lame& lame, Stabilization stabilization) {
  const Projection p = build(z);
  const Eigen::Index n2 = p.B.cols();
  VemElement el;
  el.area = p.area;
  el.vertex_mean = p.mean;
  el.strain = p.B;
  // Pi = R (R^T R)^{-1} R^T (I - Ds B) + Ds B
  const Eigen::MatrixXd DsB = p.Ds * p.B;
  const Eigen::MatrixXd RtI = p.RtR_inv.asDiagonal() * p.R.transpose();
  el.projection = p.R * (RtI - RtI * DsB) + DsB;
  el.consistency = p.area * p.B.transpose() * elasticity_matrix(lame) * p.B;
  el.tau = stabilization == Stabilization::two_mu ? 2.0 * lame.mu
                                                  : el.consistency.trace() / static_cast<double>(n2);
  const Eigen::MatrixXd IminusPi = Eigen::MatrixXd::Identity(n2, n2) - el.projection;
  el.stabilization = el.tau * IminusPi.transpose() * IminusPi;
  return el;
}

LinearField project_p1(std::span<const Vec2> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  const Projection p = build(z);
  const Eigen::Vector3d eps = p.B * v;
  const Eigen::Vector3d rho = p.RtR_inv.asDiagonal() * (p.R.transpose() * (v - p.Ds * eps));
  LinearField f;
  f.center = p.mean;
  f.value = Vec2(rho(0), rho(1));
  f.gradient << eps(0), 0.5 * eps(2) - rho(2),  //
      0.5 * eps(2) + rho(2), eps(1);
  return f;
}

LinearField project_gradient(std::span<const Vec2> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  const Eigen::Index n = static_cast<Eigen::Index>(z.size());
  const double area = signed_area(z);
  const Eigen::Matrix2Xd nu = vertex_normals(z);
  LinearField f;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec2 vi(v(2 * i), v(2 * i + 1));
    f.center += z[static_cast<std::size_t>(i)];
    f.value += vi;
    f.gradient += vi * nu.col(i).transpose();
  }
  f.center /= static_cast<double>(n);
  f.value /= static_cast<double>(n);
  f.gradient /= area;
  return f;
}

}  // namespace hemivem
