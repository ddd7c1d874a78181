#include <hemivem/vem/bilinear.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include <hemivem/error.hpp>

namespace hemivem {

Eigen::VectorXd prolong_squares(const Eigen::VectorXd& coarse, int nc, int nf) {
  if (nc < 1 || nf < nc || nf % nc != 0)
    throw InputError("the fine N (" + std::to_string(nf) + ") is not a multiple of the coarse N (" + std::to_string(nc) + ")");
  if (coarse.size() != 2 * (nc + 1) * (nc + 1))
    throw InputError("a field on N x N squares with N = " + std::to_string(nc) + " has " +
                     std::to_string(2 * (nc + 1) * (nc + 1)) + " values, got " + std::to_string(coarse.size()));
  const int r = nf / nc;
  Eigen::VectorXd fine(2 * (nf + 1) * (nf + 1));
  auto cell = [&](int I, int& i, double& f) {
    i = I / r;
    f = static_cast<double>(I % r) / r;
    if (i == nc) i = nc - 1, f = 1.0;
  };
  for (int J = 0; J <= nf; ++J) {
    int j;
    double fy;
    cell(J, j, fy);
    for (int I = 0; I <= nf; ++I) {
      int i;
      double fx;
      cell(I, i, fx);
      const int v00 = j * (nc + 1) + i, v10 = v00 + 1, v01 = v00 + nc + 1, v11 = v01 + 1;
      const int V = J * (nf + 1) + I;
      for (int c = 0; c < 2; ++c)
        fine[2 * V + c] = (1 - fx) * (1 - fy) * coarse[2 * v00 + c] + fx * (1 - fy) * coarse[2 * v10 + c] +
                          fx * fy * coarse[2 * v11 + c] + (1 - fx) * fy * coarse[2 * v01 + c];
    }
  }
  return fine;
}

Eigen::Matrix<double, 8, 8> q1_stiffness(const std::array<Vec2, 4>& v, const Lame& lame) {
  double x0 = v[0].x(), x1 = x0, y0 = v[0].y(), y1 = y0;
  for (const auto& p : v) x0 = std::min(x0, p.x()), x1 = std::max(x1, p.x()), y0 = std::min(y0, p.y()), y1 = std::max(y1, p.y());
  const double a = (x1 - x0) / 2, b = (y1 - y0) / 2, cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  if (!(a > 0) || !(b > 0)) throw InputError("a bilinear element needs a rectangle of positive area");
  // Each vertex must sit on its own corner of the bounding box.
  std::array<double, 4> sx{}, sy{};
  int corners = 0;
  for (int k = 0; k < 4; ++k) {
    const double tol = 1e-9 * std::max(a, b);
    if (std::abs(std::abs(v[k].x() - cx) - a) > tol || std::abs(std::abs(v[k].y() - cy) - b) > tol)
      throw InputError("a bilinear element needs an axis-aligned rectangle, one vertex at each corner");
    sx[k] = v[k].x() > cx ? 1.0 : -1.0;
    sy[k] = v[k].y() > cy ? 1.0 : -1.0;
    corners |= 1 << ((sx[k] > 0) + 2 * (sy[k] > 0));
  }
  if (corners != 15) throw InputError("a bilinear element needs an axis-aligned rectangle, one vertex at each corner");
  const Eigen::Matrix3d C = elasticity_matrix(lame);
  Eigen::Matrix<double, 8, 8> K = Eigen::Matrix<double, 8, 8>::Zero();
  const double g = 1.0 / std::sqrt(3.0);
  for (double xi : {-g, g})
    for (double eta : {-g, g}) {
      Eigen::Matrix<double, 3, 8> B = Eigen::Matrix<double, 3, 8>::Zero();
      for (int k = 0; k < 4; ++k) {
        const double dx = sx[k] * (1 + sy[k] * eta) / (4 * a), dy = sy[k] * (1 + sx[k] * xi) / (4 * b);
        B(0, 2 * k) = dx;
        B(1, 2 * k + 1) = dy;
        B(2, 2 * k) = dy;
        B(2, 2 * k + 1) = dx;
      }
      K += B.transpose() * C * B * (a * b);
    }
  return K;
}

double q1_energy(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  if (u.size() != 2 * mesh.num_vertices()) throw InputError("the field has " + std::to_string(u.size()) + " values, the mesh needs " + std::to_string(2 * mesh.num_vertices()));
  double sum = 0.0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto ids = mesh.element(e);
    if (ids.size() != 4) throw InputError("element " + std::to_string(e) + " is not a quadrilateral: the bilinear energy needs rectangles");
    std::array<Vec2, 4> v;
    Eigen::Matrix<double, 8, 1> ue;
    for (int k = 0; k < 4; ++k) {
      v[k] = mesh.vertex(ids[k]);
      ue.segment<2>(2 * k) = u.segment<2>(2 * ids[k]);
    }
    sum += ue.dot(q1_stiffness(v, materials.lame(mesh.region(e))) * ue);
  }
  return sum;
}

}  // namespace hemivem
