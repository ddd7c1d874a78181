#include <hemivem/error.hpp>
#include <hemivem/vem/element.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <type_traits>

namespace hemivem {

std::string to_string(Stabilization s) {
  switch (s) {
    case Stabilization::two_mu: return "2mu";
    case Stabilization::trace_scaled: return "trace";
  }
  throw InternalError("a Stabilization out of range: " + std::to_string(static_cast<int>(s)));
}

Stabilization stabilization_from_string(std::string_view name) {
  std::string s(name);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (s == "2mu" || s == "two-mu" || s == "two_mu") return Stabilization::two_mu;
  if (s == "trace" || s == "trace-scaled" || s == "trace_scaled") return Stabilization::trace_scaled;
  throw InputError("unknown stabilization '" + std::string(name) + "'; expected 2mu or trace");
}

namespace {

/// The scaled vertex normal nu_i = (m_{i-1} + m_i) / 2 of polygon z, m_i = |e_i| n_i for the edge
/// z_i -> z_{i+1}.
Vec2 vertex_normal(std::span<const Vec2> z, std::size_t i) {
  const std::size_t n = z.size();
  const Vec2 d0 = z[i] - z[(i + n - 1) % n], d1 = z[(i + 1) % n] - z[i];
  return 0.5 * (Vec2(d0.y(), -d0.x()) + Vec2(d1.y(), -d1.x()));
}

}  // namespace

Eigen::Matrix2Xd vertex_normals(std::span<const Vec2> z) {
  Eigen::Matrix2Xd nu(2, static_cast<Eigen::Index>(z.size()));
  for (std::size_t i = 0; i < z.size(); ++i) nu.col(static_cast<Eigen::Index>(i)) = vertex_normal(z, i);
  return nu;
}

namespace {

/// Matrices of elements with up to 8 vertices live on the stack (and their products are
/// evaluated coefficient-wise): no heap allocation per element in the assembly.
using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, 16, 16>;
constexpr std::size_t small_element_vertices = 8;

template <class Mat>
struct Projection {
  Mat B;                   // 3 x 2n projected strain
  Mat R;                   // 2n x 3 rigid motions at the vertices (centred at the vertex mean)
  Mat Ds;                  // 2n x 3 strain modes at the vertices
  Eigen::Vector3d RtR_inv; // (R^T R)^{-1}, diagonal because of the centring
  Vec2 mean = Vec2::Zero();
  double area = 0.0;
};

template <class Mat>
Projection<Mat> build(std::span<const Vec2> z) {
  const Eigen::Index n = static_cast<Eigen::Index>(z.size());
  if (n < 3) throw InputError("a virtual element needs at least 3 vertices, got " + std::to_string(n));
  Projection<Mat> p;
  p.area = signed_area(z);
  if (!(p.area > 0.0)) throw MeshError("element has non-positive area", -1);
  for (const auto& v : z) p.mean += v;
  p.mean /= static_cast<double>(n);

  p.B.setZero(3, 2 * n);
  p.R.setZero(2 * n, 3);
  p.Ds.setZero(2 * n, 3);
  double r2 = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec2 nu = vertex_normal(z, static_cast<std::size_t>(i));
    const double a = nu.x() / p.area, b = nu.y() / p.area;
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

/// The projection Pi, K_c, tau and S_E of one element in matrices of type Mat.
template <class Mat>
struct ElementMatrices {
  Projection<Mat> p;
  Mat projection, consistency, stabilization;
  double tau = 0.0;
};

/// a * b: coefficient-wise for the small matrices (GEMM's blocking costs more than it saves at
/// 16 x 16), Eigen's product otherwise.
template <class Mat, class A, class B>
Mat times(const A& a, const B& b) {
  if constexpr (std::is_same_v<Mat, SmallMatrix>)
    return a.lazyProduct(b);
  else
    return a * b;
}

template <class Mat>
ElementMatrices<Mat> element_matrices(std::span<const Vec2> z, const Lame& lame, Stabilization stabilization) {
  ElementMatrices<Mat> m{build<Mat>(z), Mat(), Mat(), Mat(), 0.0};
  const Projection<Mat>& p = m.p;
  const Eigen::Index n2 = p.B.cols();
  // Pi = R (R^T R)^{-1} R^T (I - Ds B) + Ds B
  const Mat DsB = times<Mat>(p.Ds, p.B);
  const Mat RtI = p.RtR_inv.asDiagonal() * p.R.transpose();
  const Mat RtI_IminusDsB = RtI - times<Mat>(RtI, DsB);
  m.projection = times<Mat>(p.R, RtI_IminusDsB) + DsB;
  const Mat BtC = times<Mat>(Mat(p.area * p.B.transpose()), elasticity_matrix(lame));
  m.consistency = times<Mat>(BtC, p.B);
  m.tau = stabilization == Stabilization::two_mu ? 2.0 * lame.mu : m.consistency.trace() / static_cast<double>(n2);
  const Mat IminusPi = Mat::Identity(n2, n2) - m.projection;
  m.stabilization = m.tau * times<Mat>(IminusPi.transpose(), IminusPi);
  return m;
}

}  // namespace

VemElement vem_element(std::span<const Vec2> z, const Lame& lame, Stabilization stabilization) {
  auto m = element_matrices<Eigen::MatrixXd>(z, lame, stabilization);
  VemElement el;
  el.area = m.p.area;
  el.vertex_mean = m.p.mean;
  el.strain = std::move(m.p.B);
  el.projection = std::move(m.projection);
  el.consistency = std::move(m.consistency);
  el.stabilization = std::move(m.stabilization);
  el.tau = m.tau;
  return el;
}

void element_stiffness(std::span<const Vec2> z, const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K) {
  if (z.size() <= small_element_vertices) {
    const auto m = element_matrices<SmallMatrix>(z, lame, stabilization);
    K = m.consistency + m.stabilization;
  } else {
    const auto m = element_matrices<Eigen::MatrixXd>(z, lame, stabilization);
    K = m.consistency + m.stabilization;
  }
}

namespace {

template <class Mat>
LinearField project_p1_with(std::span<const Vec2> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  const auto p = build<Mat>(z);
  const Eigen::Vector3d eps = p.B * v;
  const Eigen::Vector3d rho = p.RtR_inv.asDiagonal() * (p.R.transpose() * (v - p.Ds * eps));
  LinearField f;
  f.center = p.mean;
  f.value = Vec2(rho(0), rho(1));
  f.gradient << eps(0), 0.5 * eps(2) - rho(2),  //
      0.5 * eps(2) + rho(2), eps(1);
  return f;
}

}  // namespace

LinearField project_p1(std::span<const Vec2> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  // an element of up to 8 vertices on the stack, as in element_stiffness()
  return z.size() <= small_element_vertices ? project_p1_with<SmallMatrix>(z, v) : project_p1_with<Eigen::MatrixXd>(z, v);
}

Eigen::Vector3d projected_strain(std::span<const Vec2> z, const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (z.size() < 3) throw InputError("a virtual element needs at least 3 vertices, got " + std::to_string(z.size()));
  const double area = signed_area(z);
  if (!(area > 0.0)) throw MeshError("element has non-positive area", -1);
  Eigen::Vector3d eps = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec2 nu = vertex_normal(z, i);
    const double a = nu.x() / area, b = nu.y() / area;  // B's entries, as build() makes them
    const double vx = v(2 * static_cast<Eigen::Index>(i)), vy = v(2 * static_cast<Eigen::Index>(i) + 1);
    eps(0) += a * vx;
    eps(1) += b * vy;
    eps(2) += b * vx + a * vy;
  }
  return eps;
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
